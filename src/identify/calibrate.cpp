#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "robcal/identify/identification.hpp"

namespace robcal {
namespace {

/// Position residual norm of a row: 3D for points, TCP position for poses, |length| for
/// distances.
double row_error(const Eigen::VectorXd& r, int k, Eigen::Index row) {
  return k == 1 ? std::abs(r[row]) : r.segment<3>(row * k).norm();
}

std::string row_target_name(const Tool& tool, const MeasurementSet& data, size_t row) {
  if (data.kind == MeasurementKind::Points)
    return tool.targets[static_cast<size_t>(data.points[row].target)].name;
  if (data.kind == MeasurementKind::Distances)
    return tool.targets[static_cast<size_t>(data.distances[row].target)].name;
  return "tcp";
}

std::pair<std::string, int> row_origin(const MeasurementSet& data, size_t row) {
  if (data.kind == MeasurementKind::Points) return {data.points[row].config, data.points[row].line};
  if (data.kind == MeasurementKind::Poses) return {data.poses[row].config, data.poses[row].line};
  return {data.distances[row].config, data.distances[row].line};
}

}  // namespace

IdentificationResult calibrate(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const IdentifyOptions& options) {
  const IdentificationSetup setup = prepare_identification(model, tool, data, options);
  const FitResult fit = fit_unknowns(setup, data);
  const ResidualContext context{&setup.model, &setup.tool, &data, &setup.layout,
                                options.orientation_weight_mm};
  IdentificationResult out;
  out.status = fit.status;
  out.warnings = setup.warnings;
  out.values = fit.unknowns;
  out.free = setup.free;
  out.huber_scale_mm = fit.huber_scale_mm;

  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  stacked_residuals(context, fit.unknowns, setup.free, &r, &J);
  const int k = data.residuals_per_row();
  const auto rows = static_cast<Eigen::Index>(data.size());
  {
    Eigen::VectorXd r0;
    stacked_residuals(context, fit.start, {}, &r0, nullptr);
    double sum = 0, sum_sq = 0;
    for (Eigen::Index row = 0; row < rows; ++row) {
      const double e = row_error(r0, k, row);
      sum += e;
      sum_sq += e * e;
      out.start_max_mm = std::max(out.start_max_mm, e);
    }
    out.start_mean_mm = sum / static_cast<double>(rows);
    out.start_rms_mm = std::sqrt(sum_sq / static_cast<double>(rows));
  }
  out.residual_count = static_cast<int>(r.size());
  out.identified_count = static_cast<int>(setup.free.size());

  // Robust per-axis σ (1.4826·median|r|) flags suspected outliers: a position residual beyond
  // 4σ (3 axes) or 3.3σ (a length), each about a 1-in-1000 event for Gaussian noise.
  std::vector<double> magnitudes(r.data(), r.data() + r.size());
  for (double& v : magnitudes) v = std::abs(v);
  std::nth_element(magnitudes.begin(),
                   magnitudes.begin() + static_cast<long>(magnitudes.size() / 2), magnitudes.end());
  const double robust_sigma = 1.4826 * magnitudes[magnitudes.size() / 2];
  const double outlier_limit = (k == 1 ? 3.3 : 4.0) * robust_sigma;
  double rss = 0, sum_sq_error = 0, sum_error = 0;
  int inlier_residuals = 0;
  std::map<std::string, std::pair<int, std::pair<double, double>>> by_target;  // rows, (Σe², max)
  for (Eigen::Index row = 0; row < rows; ++row) {
    const double e = row_error(r, k, row);
    out.row_errors_mm.push_back(e);
    sum_sq_error += e * e;
    sum_error += e;
    out.max_mm = std::max(out.max_mm, e);
    auto& entry = by_target[row_target_name(tool, data, static_cast<size_t>(row))];
    entry.first += 1;
    entry.second.first += e * e;
    entry.second.second = std::max(entry.second.second, e);
    if (robust_sigma > 0 && e > outlier_limit) {
      const auto [config, line] = row_origin(data, static_cast<size_t>(row));
      out.outliers.push_back({config, line, e});
      if (options.huber) continue;  // a robust fit's σ leaves its outliers out
    }
    rss += r.segment(row * k, k).squaredNorm();
    inlier_residuals += k;
  }
  out.rms_mm = std::sqrt(sum_sq_error / static_cast<double>(rows));
  out.mean_mm = sum_error / static_cast<double>(rows);
  for (const auto& [name, entry] : by_target)
    out.by_target.push_back(
        {name, entry.first, std::sqrt(entry.second.first / entry.first), entry.second.second});

  const int dof = std::max(1, inlier_residuals - out.identified_count);
  out.sigma_mm = std::sqrt(rss / dof);
  if (options.instrument_sigma_mm > 0) {
    NoiseTest& t = out.noise_test;
    t.tested = true;
    t.instrument_sigma_mm = options.instrument_sigma_mm;
    t.dof = dof;
    t.chi_square = rss / (options.instrument_sigma_mm * options.instrument_sigma_mm);
    t.p_value = chi_square_upper_tail(t.chi_square, dof);
    t.consistent = t.p_value >= kNoiseTestLevel;
  }
  out.covariance = design_covariance(J, out.sigma_mm);
  {
    const Eigen::VectorXd s = J.colwise().norm().cwiseInverse();
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J * s.asDiagonal());
    const Eigen::VectorXd& sv = svd.singularValues();
    out.condition_number = sv.minCoeff() > 0 ? sv.maxCoeff() / sv.minCoeff() : 0.0;
  }

  // Correlations.
  const auto n = static_cast<Eigen::Index>(setup.free.size());
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j) {
      const double rho =
          out.covariance(i, j) / std::sqrt(out.covariance(i, i) * out.covariance(j, j));
      if (std::abs(rho) >= 0.5)
        out.correlations.push_back({setup.layout.names[setup.free[static_cast<size_t>(i)]],
                                    setup.layout.names[setup.free[static_cast<size_t>(j)]], rho});
    }
  std::sort(
      out.correlations.begin(), out.correlations.end(),
      [](const Correlation& a, const Correlation& b) { return std::abs(a.rho) > std::abs(b.rho); });
  if (out.correlations.size() > 10) out.correlations.resize(10);

  // The calibrated robot.
  CalibratedRobot& robot = out.robot;
  robot.model = setup.model;  // with the warm-up's time constant the fit used (§10)
  robot.params = fit.unknowns.head<kParameterCount>();
  robot.tool = tool;
  robot.level = level_name(options.level);
  robot.covariance = Eigen::MatrixXd::Zero(kParameterCount, kParameterCount);
  const std::vector<int> level_set = level_parameters(options.level);
  std::vector<std::string> reasons(setup.layout.size());
  std::vector<ParameterStatus> status(setup.layout.size(), ParameterStatus::Fixed);
  for (int i = 0; i < setup.layout.size(); ++i) {
    const bool in_level = !setup.layout.is_model(i) ||
                          std::find(level_set.begin(), level_set.end(), i) != level_set.end();
    if (setup.requested[i]) continue;
    reasons[static_cast<size_t>(i)] = in_level ? "held by --fix"
                                      : setup.layout.is_model(i) && is_opt_in(i)
                                          ? "opt-in group, not asked for (--identify)"
                                          : fmt::format("not identified at level {}", robot.level);
  }
  for (const Dependency& dep : setup.dropped) {
    status[static_cast<size_t>(dep.column)] = ParameterStatus::Dropped;
    reasons[static_cast<size_t>(dep.column)] =
        dep.reason.empty() ? "not identifiable: " + describe_dependency(setup.layout, model, dep)
                           : dep.reason;
  }
  for (size_t c = 0; c < setup.free.size(); ++c)
    status[static_cast<size_t>(setup.free[c])] = ParameterStatus::Identified;
  for (int i = 0; i < kParameterCount; ++i) {
    robot.status[static_cast<size_t>(i)] = status[static_cast<size_t>(i)];
    robot.reason[static_cast<size_t>(i)] = reasons[static_cast<size_t>(i)];
  }
  for (size_t a = 0; a < setup.free.size(); ++a)
    for (size_t b = 0; b < setup.free.size(); ++b)
      if (setup.layout.is_model(setup.free[a]) && setup.layout.is_model(setup.free[b]))
        robot.covariance(setup.free[a], setup.free[b]) =
            out.covariance(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
  for (size_t t = 0; t < robot.tool.targets.size(); ++t) {
    const int slot = setup.layout.target_slot[t];
    if (slot < 0) continue;
    robot.tool.targets[t].position_mm = fit.unknowns.segment<3>(slot);
    robot.tool.targets[t].known = true;
  }
  if (data.kind == MeasurementKind::Poses) {
    robot.tool.flange_T_tcp = tcp_frame(context, fit.unknowns);
    robot.tool.tcp_position_known = robot.tool.tcp_orientation_known = true;
  }
  bool base = true;
  for (int i = 0; i < kBaseParamCount; ++i)
    base = base && robot.status[static_cast<size_t>(i)] == ParameterStatus::Identified;
  robot.base_fitted = base;

  // Every unknown in external units.
  for (int i = 0; i < setup.layout.size(); ++i) {
    UnknownEstimate e;
    const double f = setup.layout.to_external(i);
    e.name = setup.layout.names[static_cast<size_t>(i)];
    e.unit = setup.layout.unit(i);
    e.nominal = setup.start[i] * f;
    e.value = fit.unknowns[i] * f;
    e.status = status[static_cast<size_t>(i)];
    e.reason = reasons[static_cast<size_t>(i)];
    e.opt_in_not_asked = !setup.requested[i] && setup.layout.is_model(i) && is_opt_in(i);
    const auto it = std::find(setup.free.begin(), setup.free.end(), i);
    if (it != setup.free.end()) {
      const auto c = it - setup.free.begin();
      e.std_dev = std::sqrt(out.covariance(c, c)) * f;
    }
    out.unknowns.push_back(e);
  }

  // Predicted accuracy over configurations in the box of the measured ones.
  Vector6d lower = Vector6d::Constant(1e300), upper = Vector6d::Constant(-1e300);
  std::vector<Eigen::Vector3d> targets;
  for (size_t row = 0; row < data.size(); ++row) {
    const Vector6d& q = data.kind == MeasurementKind::Points  ? data.points[row].joints
                        : data.kind == MeasurementKind::Poses ? data.poses[row].joints
                                                              : data.distances[row].joints;
    lower = lower.cwiseMin(q);
    upper = upper.cwiseMax(q);
  }
  for (const Target& t : robot.tool.targets) targets.push_back(t.position_mm);
  if (data.kind == MeasurementKind::Poses || targets.empty())
    targets = {Eigen::Vector3d(robot.tool.flange_T_tcp.translation())};
  std::mt19937_64 rng(options.seed);
  const std::vector<Vector6d> validation =
      sample_configurations(lower, upper, options.prediction_configurations, rng);
  std::vector<Eigen::Vector3d> validation_targets;
  for (size_t v = 0; v < validation.size(); ++v)
    validation_targets.push_back(targets[v % targets.size()]);
  std::vector<int> model_free;
  std::vector<Eigen::Index> model_cols;
  for (size_t c = 0; c < setup.free.size(); ++c)
    if (setup.layout.is_model(setup.free[c])) {
      model_free.push_back(setup.free[c]);
      model_cols.push_back(static_cast<Eigen::Index>(c));
    }
  Eigen::MatrixXd C(model_cols.size(), model_cols.size());
  for (size_t a = 0; a < model_cols.size(); ++a)
    for (size_t b = 0; b < model_cols.size(); ++b)
      C(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) =
          out.covariance(model_cols[a], model_cols[b]);
  if (!validation.empty())
    out.predicted = predict_position_error(model, tool.payload, robot.params, model_free, C,
                                           validation, validation_targets, out.sigma_mm);
  return out;
}

double chi_square_upper_tail(double x, int dof) {
  if (dof <= 0 || x <= 0) return 1.0;
  const double nu = dof, v = 2.0 / (9.0 * nu);
  const double z = (std::cbrt(x / nu) - (1.0 - v)) / std::sqrt(v);
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

}  // namespace robcal
