#include "robcal/validate/ballbar_error.hpp"

#include <ceres/ceres.h>

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/measure/instrument.hpp"

namespace robcal {
namespace {

/// e = |p − c| − L for the centre c (so that the fit minimises Σ e²).
struct LengthResidual {
  Eigen::Vector3d p;
  double length;
  template <typename T>
  bool operator()(const T* c, T* residual) const {
    const T dx = T(p.x()) - c[0], dy = T(p.y()) - c[1], dz = T(p.z()) - c[2];
    residual[0] = ceres::sqrt(dx * dx + dy * dy + dz * dz) - T(length);
    return true;
  }
};

Eigen::Vector3d fit_centre(const Eigen::Matrix3Xd& p, const MeasurementSet& set) {
  // |p − c|² = L²  ⇔  2 p·c − |c|² = |p|² − L²: linear in (c, |c|²) for the start.
  const Eigen::Index n = p.cols();
  Eigen::MatrixXd A(n, 4);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double L = set.distances[static_cast<size_t>(i)].length_mm;
    A.row(i) << 2 * p.col(i).transpose(), -1.0;
    b[i] = p.col(i).squaredNorm() - L * L;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (n < 4 || qr.rank() < 4)
    throw InputError({set.file, 0, 0, "--ballbar-centre"},
                     "cannot locate the ballbar centre: the distances need at least four rows with "
                     "the target at positions not on one plane (or give the centre with "
                     "--ballbar-centre X,Y,Z)");
  std::array<double, 3> c{};
  Eigen::Map<Eigen::Vector3d>(c.data()) = qr.solve(b).head<3>();
  ceres::Problem problem;
  for (Eigen::Index i = 0; i < n; ++i)
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<LengthResidual, 1, 3>(
            new LengthResidual{p.col(i), set.distances[static_cast<size_t>(i)].length_mm}),
        nullptr, c.data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.logging_type = ceres::SILENT;
  options.function_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return Eigen::Map<const Eigen::Vector3d>(c.data());
}

/// `value` when positive and finite, else an InputError naming `flag`.
double positive_length(double value, const char* flag, const char* what) {
  if (!std::isfinite(value) || value <= 0)
    throw InputError(
        {"", 0, 0, flag},
        fmt::format("expected the bar's {} as a positive length in mm, got {}", what, value));
  return value;
}

}  // namespace

BallbarRange check_ballbar_readings(const MeasurementSet& set, std::optional<double> length_mm,
                                    std::optional<double> range_mm) {
  BallbarRange out;
  out.range_mm = positive_length(range_mm.value_or(kDefaultBallbarRangeMm), "--ballbar-range",
                                 "measuring range (± mm)");
  out.length_given = length_mm.has_value();
  if (length_mm) {
    out.nominal_length_mm = positive_length(*length_mm, "--ballbar-length", "nominal length");
  } else if (!set.distances.empty()) {
    std::vector<double> lengths;
    lengths.reserve(set.distances.size());
    for (const DistanceMeasurement& m : set.distances) lengths.push_back(m.length_mm);
    const auto middle = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
    std::nth_element(lengths.begin(), middle, lengths.end());
    out.nominal_length_mm = *middle;
  }
  if (out.length_given && out.range_mm >= out.nominal_length_mm)
    throw InputError({"", 0, 0, "--ballbar-range"},
                     fmt::format("a range of ±{:g} mm is not below the bar's length {:g} mm",
                                 out.range_mm, out.nominal_length_mm));
  Ballbar bar;
  bar.nominal_length_mm = out.nominal_length_mm;
  bar.range_mm = out.range_mm;
  const auto outside = [&](const DistanceMeasurement& m) {
    return !ballbar_readable(bar, m.length_mm);
  };
  const auto first = std::find_if(set.distances.begin(), set.distances.end(), outside);
  if (first != set.distances.end()) {
    const auto count = std::count_if(set.distances.begin(), set.distances.end(), outside);
    throw InputError(
        {set.file, first->line, 0, "length"},
        fmt::format("reading {:.4f} mm is outside the ballbar's range {:g} ± {:g} mm (nominal "
                    "length {}; {} of {} readings are outside): such a reading cannot come from "
                    "the bar. Check the file, or give the bar's set-up with --ballbar-length "
                    "and --ballbar-range",
                    first->length_mm, out.nominal_length_mm, out.range_mm,
                    out.length_given ? "given" : "the median reading", count,
                    set.distances.size()));
  }
  return out;
}

BallbarErrors ballbar_errors(const CalibratedRobot& robot, const MeasurementSet& set,
                             const std::optional<Eigen::Vector3d>& centre) {
  if (set.kind != MeasurementKind::Distances)
    throw InputError({set.file, 0, 0, ""}, "ballbar validation needs a distances file");
  const Eigen::Matrix3Xd p = predicted_positions(robot, set);
  BallbarErrors out;
  out.centre_fitted = !centre.has_value();
  out.centre_mm = centre ? *centre : fit_centre(p, set);
  out.length_error_mm.resize(set.size());
  std::vector<double> absolute(set.size());
  for (size_t i = 0; i < set.size(); ++i) {
    out.length_error_mm[i] =
        set.distances[i].length_mm - (p.col(static_cast<Eigen::Index>(i)) - out.centre_mm).norm();
    absolute[i] = std::abs(out.length_error_mm[i]);
  }
  out.absolute_mm = error_statistics(absolute);
  const ErrorStatistics signed_stats = error_statistics(out.length_error_mm);
  out.signed_mean_mm = signed_stats.mean;
  out.signed_std_mm = signed_stats.std;
  out.positive_share = set.size() == 0 ? 0.0
                                       : static_cast<double>(std::count_if(
                                             out.length_error_mm.begin(), out.length_error_mm.end(),
                                             [](double e) { return e > 0; })) /
                                             static_cast<double>(set.size());
  for (size_t t = 0; t < robot.tool.targets.size(); ++t) {
    std::vector<double> errors;
    for (size_t i = 0; i < set.size(); ++i)
      if (set.distances[i].target == static_cast<int>(t)) errors.push_back(absolute[i]);
    if (!errors.empty())
      out.per_target.push_back({robot.tool.targets[t].name, error_statistics(errors)});
  }
  for (const ClassPartition& p : configuration_partitions(robot.model, set)) {
    ClassTable table{p.name, {}};
    for (size_t c = 0; c < p.labels.size(); ++c) {
      std::vector<double> errors;
      for (size_t i = 0; i < set.size(); ++i)
        if (p.class_of_row[i] == static_cast<int>(c)) errors.push_back(absolute[i]);
      table.rows.push_back({p.labels[c], error_statistics(errors), {}, {}});
    }
    out.classes.push_back(std::move(table));
  }
  return out;
}

}  // namespace robcal
