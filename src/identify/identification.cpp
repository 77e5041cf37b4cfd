#include "robcal/identify/identification.hpp"

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Dense>
#include <algorithm>
#include <map>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/identify/initial_guess.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/measure/tcp_warning.hpp"

namespace robcal {
namespace {

/// The rows [begin, end) of a measurement set as one Ceres cost on the scaled unknowns z:
/// unknowns = start + scales ⊙ z over the free indices (column scaling makes mm, rad and
/// rad/N·mm comparable; z starts at 0). The rows' configurations are prepared once, at the
/// start, and the scratch is kept: an evaluation computes the parameters' sines and cosines
/// once, no joint's, and allocates nothing. After a successful step Ceres asks for the Jacobian
/// where it has just evaluated the residuals: the rows' chains (the flange poses and what their
/// derivatives need) of the last point evaluated are kept and reused when z is that point again,
/// compared value by value (so whatever order Ceres evaluates in). Ceres evaluates it on one
/// thread (num_threads = 1).
class RowsCost final : public ceres::CostFunction {
 public:
  RowsCost(const ResidualContext& context, const std::vector<int>& free,
           const Eigen::VectorXd& scales, const Eigen::VectorXd& start,
           const std::vector<PreparedConfiguration>& configurations, size_t begin, size_t end)
      : context_(context),
        free_(free),
        scales_(scales),
        start_(start),
        configurations_(configurations),
        begin_(begin),
        end_(end),
        z_(free.size()),
        unknowns_(start),
        row_jacobian_(context.data->residuals_per_row(), context.layout->size()) {
    chains_.reserve(end - begin);
    set_num_residuals(static_cast<int>(end - begin) * context.data->residuals_per_row());
    mutable_parameter_block_sizes()->push_back(static_cast<int>(free.size()));
  }

  bool Evaluate(double const* const* z, double* residuals, double** jacobians) const override {
    const auto n = free_.size();
    if (chains_.empty() || !std::equal(z_.begin(), z_.end(), z[0])) {
      std::copy(z[0], z[0] + n, z_.begin());
      unknowns_ = start_;
      for (size_t i = 0; i < n; ++i)
        unknowns_[free_[i]] += scales_[static_cast<Eigen::Index>(i)] * z[0][i];
      const ParameterTrig trig = parameter_trig(unknowns_.head<kParameterCount>());
      const ParameterVector params = unknowns_.head<kParameterCount>();
      chains_.clear();
      for (size_t row = begin_; row < end_; ++row)
        chains_.emplace_back(*context_.model,
                             context_.tool->payload_of(context_.data->payload(row)), params, trig,
                             configurations_[row]);
    }
    const int k = context_.data->residuals_per_row();
    const bool want_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    for (size_t row = begin_; row < end_; ++row) {
      double* r = residuals + (row - begin_) * static_cast<size_t>(k);
      row_residuals(context_, unknowns_, row, chains_[row - begin_], r,
                    want_jacobian ? &row_jacobian_ : nullptr);
      for (int i = 0; i < k; ++i)
        if (!std::isfinite(r[i])) return false;
      if (!want_jacobian) continue;
      double* out = jacobians[0] + (row - begin_) * static_cast<size_t>(k) * n;
      for (int i = 0; i < k; ++i)
        for (size_t c = 0; c < n; ++c)
          out[static_cast<size_t>(i) * n + c] =
              row_jacobian_(i, free_[c]) * scales_[static_cast<Eigen::Index>(c)];
    }
    return true;
  }

 private:
  const ResidualContext& context_;
  const std::vector<int>& free_;
  const Eigen::VectorXd& scales_;
  const Eigen::VectorXd& start_;
  const std::vector<PreparedConfiguration>& configurations_;
  size_t begin_, end_;
  mutable std::vector<FlangeRegressor> chains_;  ///< of the last evaluation point, z_
  mutable std::vector<double> z_;
  mutable Eigen::VectorXd unknowns_;
  mutable Eigen::MatrixXd row_jacobian_;
};

/// Levenberg–Marquardt on the free unknowns from `unknowns` (updated in place).
SolverStatus solve(const ResidualContext& context, const std::vector<int>& free,
                   const Eigen::VectorXd& scales, int max_iterations, double huber_scale,
                   Eigen::VectorXd& unknowns) {
  const Eigen::VectorXd start = unknowns;
  const size_t rows = context.data->size();
  std::vector<PreparedConfiguration> configurations(rows);
  const ParameterVector start_params = start.head<kParameterCount>();
  for (size_t row = 0; row < rows; ++row)
    configurations[row] =
        prepare_configuration(*context.model, start_params, row_joints(*context.data, row),
                              row_conditions(*context.model, *context.data, row));
  std::vector<double> z(free.size(), 0.0);
  ceres::Problem problem;
  if (huber_scale > 0) {
    for (size_t row = 0; row < rows; ++row)
      problem.AddResidualBlock(
          new RowsCost(context, free, scales, start, configurations, row, row + 1),
          new ceres::HuberLoss(huber_scale), z.data());
  } else {
    problem.AddResidualBlock(new RowsCost(context, free, scales, start, configurations, 0, rows),
                             nullptr, z.data());
  }
  ceres::Solver::Options options;
  options.minimizer_type = ceres::TRUST_REGION;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  // 150 × 31 is small and dense: the normal equations (JᵀJ is 31 × 31) are the cheapest exact
  // solve, and the columns are scaled, so they are well conditioned.
  options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  options.jacobi_scaling = false;  // the unknowns are already column-scaled
  // The rigid fit starts the unknowns close to the solution: begin nearly as Gauss–Newton
  // (damping 1e-6 against the scaled JᵀJ's unit diagonal) so that weakly determined
  // directions are not held back by the default damping for an extra iteration.
  options.initial_trust_region_radius = 1e6;
  options.max_num_iterations = max_iterations;
  // Stop at the noise floor: near the minimum a step lowers the cost by ½|J·δ|² out of
  // ½(m − n)σ², so a relative decrease below 1e-8 means the step moves the modelled values by
  // about 1e-4·√(m − n)·σ in all, 0.1 % of the noise for 150 residuals: further iterations change
  // nothing that the data can tell. The parameter and gradient tolerances only end noise-free
  // fits, whose cost falls to rounding.
  options.function_tolerance = 1e-8;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-12;
  options.logging_type = ceres::SILENT;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  for (size_t i = 0; i < free.size(); ++i)
    unknowns[free[i]] += scales[static_cast<Eigen::Index>(i)] * z[i];
  SolverStatus status;
  status.converged = summary.termination_type == ceres::CONVERGENCE;
  status.iterations = static_cast<int>(summary.iterations.size()) - 1;
  status.message = summary.message;
  const double m = std::max<double>(1, summary.num_residuals);
  status.initial_rms_mm = std::sqrt(2 * summary.initial_cost / m);
  status.final_rms_mm = std::sqrt(2 * summary.final_cost / m);
  return status;
}

int target_of(const MeasurementSet& data, size_t row) {
  return data.kind == MeasurementKind::Points      ? data.points[row].target
         : data.kind == MeasurementKind::Distances ? data.distances[row].target
                                                   : -1;
}

/// Rows whose joints lie outside the robot's limits: warned with their lines (a typo, a
/// different controller convention or the wrong robot file), at most 10 listed. A joint more than
/// kJointLimitSlack beyond a limit is no overtravel or extended-range option but a wrong value
/// (500° on a ±165° joint): refused with its line, before a fit it would ruin.
void check_joint_limits(const RobotModel& model, const MeasurementSet& data,
                        std::vector<std::string>& warnings) {
  constexpr double kJointLimitSlack = deg2rad(20);
  std::vector<std::string> rows;
  for (size_t row = 0; row < data.size(); ++row) {
    const Vector6d& q = row_joints(data, row);
    for (int j = 0; j < kJointCount; ++j) {
      const JointLimit& l = model.limits[static_cast<size_t>(j)];
      if (q[j] >= l.lower - 1e-9 && q[j] <= l.upper + 1e-9) continue;
      const int line = data.kind == MeasurementKind::Points  ? data.points[row].line
                       : data.kind == MeasurementKind::Poses ? data.poses[row].line
                                                             : data.distances[row].line;
      if (q[j] < l.lower - kJointLimitSlack || q[j] > l.upper + kJointLimitSlack)
        throw InputError({data.file, line, 0, fmt::format("j{}", j + 1)},
                         fmt::format("{:.3f}° is more than {:g}° outside the joint's limits [{:g}, "
                                     "{:g}]° of {}: fix the row, or check the robot file and "
                                     "the joint columns' units ('# units:' header)",
                                     rad2deg(q[j]), rad2deg(kJointLimitSlack), rad2deg(l.lower),
                                     rad2deg(l.upper), model.name));
      rows.push_back(fmt::format("{}:{}: j{} = {:.3f}° outside [{:g}, {:g}]°", data.file, line,
                                 j + 1, rad2deg(q[j]), rad2deg(l.lower), rad2deg(l.upper)));
      break;
    }
  }
  if (rows.empty()) return;
  std::string text = fmt::format(
      "{} row{} with joints outside the limits of {} (wrong robot file, or another joint "
      "convention?):",
      rows.size(), rows.size() > 1 ? "s" : "", model.name);
  for (size_t i = 0; i < rows.size() && i < 10; ++i) text += "\n  " + rows[i];
  if (rows.size() > 10) text += fmt::format("\n  and {} more", rows.size() - 10);
  warnings.push_back(text);
}

void check_data(const Tool& tool, const MeasurementSet& data) {
  if (data.size() == 0) throw InputError({data.file, 0, 0, ""}, "the measurements have no rows");
  for (size_t row = 0; row < data.size(); ++row) {
    const int t = target_of(data, row);
    if (data.kind != MeasurementKind::Poses &&
        (t < 0 || t >= static_cast<int>(tool.targets.size())))
      throw InputError({data.file, 0, 0, "target"},
                       fmt::format("row {} refers to target {} of a tool with {} targets", row + 1,
                                   t, tool.targets.size()));
  }
}

/// Rows of the same kind and targets at 60 configurations drawn in the joint limits (fixed
/// seed): rich enough that what stays dependent there is the model's own redundancy.
MeasurementSet synthetic_design(const RobotModel& model, const MeasurementSet& data) {
  std::vector<int> targets;
  for (size_t row = 0; row < data.size(); ++row) {
    const int t = target_of(data, row);
    if (std::find(targets.begin(), targets.end(), t) == targets.end()) targets.push_back(t);
  }
  Vector6d lower, upper;
  for (int i = 0; i < kJointCount; ++i) {
    lower[i] = model.limits[i].lower;
    upper[i] = model.limits[i].upper;
  }
  std::mt19937_64 rng(20140601);
  MeasurementSet synthetic;
  synthetic.kind = data.kind;
  // Both approach sides on every joint: the backlash is then no combination of the offsets
  // (one-sided data are refused by name in drop_one_sided_backlash).
  // Temperatures 0–10 K over the reference: the expansion is then no combination of the lengths
  // (isothermal data are refused by name in drop_isothermal_expansion).
  // Times over three warm-up time constants: the warm-up growth is then no combination of the
  // lengths (data without times are refused by name in drop_isothermal_expansion).
  std::mt19937_64 sides(20140602), heat(20140603), clock(20140604);
  std::uniform_real_distribution<double> warming(0.0, 10.0),
      working(0.0, 3 * model.warmup_time_constant_s);
  for (const Vector6d& q : sample_configurations(lower, upper, 60, rng)) {
    for (int t : targets) {
      Vector6d s;
      for (int j = 0; j < kJointCount; ++j) s[j] = (sides() & 1U) ? 1.0 : -1.0;
      if (data.kind == MeasurementKind::Points) synthetic.points.push_back({"", t, q, {}, 0, s});
      if (data.kind == MeasurementKind::Poses) synthetic.poses.push_back({"", q, {}, 0, s});
      if (data.kind == MeasurementKind::Distances)
        synthetic.distances.push_back({"", t, q, 0, 0, s});
      synthetic.set_temperature_c(synthetic.size() - 1,
                                  model.reference_temperature_c + warming(heat));
      synthetic.set_time_s(synthetic.size() - 1, working(clock));
    }
  }
  return synthetic;
}

/// Requested backlash of a joint that the rows do not approach from both sides is taken out of
/// `candidates` and dropped by name (docs/method/03-error-model.md §6): with every row from one
/// side the dead band only shifts the joint's zero, so only its sum with the joint offset is
/// determined.
void drop_one_sided_backlash(const MeasurementSet& data, std::vector<bool>& candidates,
                             IdentificationSetup& setup) {
  for (int joint = 1; joint <= kJointCount; ++joint) {
    const int i = backlash_param(joint);
    if (!candidates[static_cast<size_t>(i)]) continue;
    size_t below = 0, above = 0;
    for (size_t row = 0; row < data.size(); ++row) {
      const double s = row_approach(data, row)[joint - 1];
      below += s > 0 ? 1 : 0;
      above += s < 0 ? 1 : 0;
    }
    if (below > 0 && above > 0) continue;
    candidates[static_cast<size_t>(i)] = false;
    Dependency dep{i, {}, 1.0, {}};
    dep.reason = fmt::format(
        "every row approaches joint {} from {} ({} rows from below, {} from above, {} of unknown "
        "side), so only the sum of the backlash and the joint's zero offset is determined: "
        "measure configurations approached from both sides and record them in the 'approach' "
        "column (simulate --approach random)",
        joint,
        below > 0   ? "below"
        : above > 0 ? "above"
                    : "an unknown side",
        below, above, data.size() - below - above);
    setup.dropped.push_back(dep);
    setup.warnings.push_back(fmt::format("{} not identified: {}",
                                         setup.layout.names[static_cast<size_t>(i)], dep.reason));
  }
}

/// The lowest and highest value of an optional per-row reading, and how many rows have one.
struct ReadingSpan {
  size_t recorded = 0;
  double lowest = 0, highest = 0;
};
template <typename Reading>
ReadingSpan reading_span(const MeasurementSet& data, Reading reading) {
  ReadingSpan span;
  for (size_t row = 0; row < data.size(); ++row) {
    const std::optional<double>& t = reading(row);
    if (!t) continue;
    span.lowest = span.recorded == 0 ? *t : std::min(span.lowest, *t);
    span.highest = span.recorded == 0 ? *t : std::max(span.highest, *t);
    ++span.recorded;
  }
  return span;
}

/// Requested expansion coefficients (docs/method/03-error-model.md §8) and warm-up growths (§10)
/// the rows cannot determine are taken out of `candidates` and dropped with their real reason: a
/// link without length (a_i = d_i = 0 nominally: nothing expands), or rows that do not record at
/// least two different temperatures (expansion) or times (warm-up): at one temperature or time
/// the link only has other lengths, so only the warm lengths are determined.
void drop_isothermal_expansion(const RobotModel& model, const MeasurementSet& data,
                               std::vector<bool>& candidates, IdentificationSetup& setup) {
  const ReadingSpan temperatures = reading_span(
      data, [&](size_t row) -> const auto& { return data.temperature_c(row); });
  const ReadingSpan times = reading_span(
      data, [&](size_t row) -> const auto& { return data.time_s(row); });
  for (int link = 2; link <= kJointCount; ++link)
    for (const bool warmup : {false, true}) {
      const int i = warmup ? warmup_param(link) : expansion_param(link);
      if (!candidates[static_cast<size_t>(i)]) continue;
      const ReadingSpan& span = warmup ? times : temperatures;
      std::string reason;
      if (model.mdh[link - 1].a == 0 && model.mdh[link - 1].d == 0)
        reason = fmt::format("link {} has no length (a = d = 0 in the robot file): nothing expands",
                             link);
      else if (span.recorded == 0)
        reason = warmup ? "no row records a time: add a 'time_s' column (s since the arm started "
                          "working; simulate --clock writes it for a truth with thermal drift)"
                        : "no row records a temperature: add a 'temperature' column (°C, the arm's "
                          "temperature at each row; simulate writes it for a truth with thermal "
                          "drift)";
      else if (span.highest == span.lowest)
        reason = fmt::format(
            "every row was measured at {} {}{}, so the {} only rescales the lengths and "
            "cannot be told from them: measure at several {} (during the warm-up)",
            span.highest, warmup ? "s" : "°C",
            span.recorded < data.size()
                ? fmt::format(" ({} rows without a {})", data.size() - span.recorded,
                              warmup ? "time" : "temperature")
                : std::string(),
            warmup ? "warm-up" : "expansion", warmup ? "times" : "temperatures");
      if (reason.empty()) continue;
      candidates[static_cast<size_t>(i)] = false;
      Dependency dep{i, {}, 1.0, {}};
      dep.reason = reason;
      setup.dropped.push_back(dep);
      setup.warnings.push_back(fmt::format("{} not identified: {}",
                                           setup.layout.names[static_cast<size_t>(i)], dep.reason));
    }
}

/// The gravity group (docs/method/03-error-model.md §11) acts through the compliances only: it
/// is dropped by name when no compliance is identified; otherwise each identified compliance
/// that starts at zero starts at a plausible 1e-7 rad/N·mm instead, since the tilts' columns are
/// proportional to the compliances and would be zero at the start.
void seen_through_compliances(std::vector<bool>& candidates, IdentificationSetup& setup,
                              Eigen::VectorXd& u0) {
  if (!candidates[kGravityTiltA] && !candidates[kGravityTiltB]) return;
  std::vector<int> compliances{kJoint1Compliance};
  for (int joint = 2; joint <= kJointCount; ++joint) compliances.push_back(compliance_param(joint));
  bool any = false;
  for (int i : compliances) any = any || candidates[static_cast<size_t>(i)];
  if (!any) {
    for (const int i : {kGravityTiltA, kGravityTiltB}) {
      if (!candidates[static_cast<size_t>(i)]) continue;
      candidates[static_cast<size_t>(i)] = false;
      Dependency dep{i, {}, 1.0, {}};
      dep.reason =
          "the direction of gravity is seen only through the joint compliances, and none is "
          "identified: use level full (or --identify '*.compliance') with the robot's masses";
      setup.dropped.push_back(dep);
      setup.warnings.push_back(fmt::format("{} not identified: {}",
                                           setup.layout.names[static_cast<size_t>(i)], dep.reason));
    }
    return;
  }
  constexpr double kPlausibleCompliance = 1e-7;  // rad/N·mm: industrial arms 1e-8 … 1e-6
  for (int i : compliances)
    if (candidates[static_cast<size_t>(i)] && u0[i] == 0.0)
      u0[i] = setup.start[i] = kPlausibleCompliance;
}

/// Why the gravity torque about axis `joint` stays below the floor: axis 1 of a robot whose
/// gravity lies along it (a floor or ceiling mounting, docs/method/03-error-model.md §7), else
/// centres of gravity on the axis.
std::string unloaded_cause(const RobotModel& model, const Tool& tool, int joint) {
  const Eigen::Vector3d& g = model.gravity_m_s2;
  if (joint == 1 && g.head<2>().norm() <= 1e-9 * g.norm())
    return fmt::format(
        "gravity lies along axis 1, as on a floor{} mounting; an inclined, wall or ceiling "
        "mounting is given by 'gravity_base_m_s2' or 'mounting_deg' in the robot file",
        model.gravity_in_base ? " or ceiling" : "");
  return fmt::format("the centres of gravity lie on the axis{}",
                     tool.payload.mass_kg > 0 ? "" : " and the tool has no payload");
}

/// Requested compliances that no measured configuration loads (docs/method/03-error-model.md §3:
/// δθ_j = c_j·τ_j) are taken out of `candidates` and dropped with their real reason: no masses in
/// the robot file, or a gravity torque below kGravityTorqueFloorNmm in every row (centres of
/// gravity on the axis, no payload). Their columns would otherwise be rounding noise that a fit
/// turns into absurd values (−2e7 ± 3e7).
void drop_unloaded_compliances(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const Eigen::VectorXd& unknowns,
                               std::vector<bool>& candidates, IdentificationSetup& setup) {
  ParameterVector params = unknowns.head<kParameterCount>();
  params.segment<kJointCount - 1>(kComplianceOffset).setZero();
  params[kJoint1Compliance] = 0;
  std::array<double, kJointCount> largest{};
  for (size_t row = 0; row < data.size(); ++row) {
    const auto q = model_joint_angles(model, row_joints(data, row).data());
    const PointMass& payload = tool.payload_of(data.payload(row));
    const auto tau = gravity_torques(model, payload, params.data(),
                                     link_angles(model, payload, params.data(), q));
    for (int j = 0; j < kJointCount; ++j)
      largest[static_cast<size_t>(j)] =
          std::max(largest[static_cast<size_t>(j)], std::abs(tau[static_cast<size_t>(j)]));
  }
  bool link_masses = false;
  for (const PointMass& m : model.link_masses) link_masses = link_masses || m.mass_kg > 0;
  const bool masses = link_masses || tool.payload.mass_kg > 0;
  std::vector<std::string> names;
  for (int joint = 1; joint <= kJointCount; ++joint) {
    const int i = compliance_param(joint);
    const double tau = largest[static_cast<size_t>(joint - 1)];
    if (!candidates[static_cast<size_t>(i)] || tau >= kGravityTorqueFloorNmm) continue;
    candidates[static_cast<size_t>(i)] = false;
    Dependency dep{i, {}, 1.0, {}};
    dep.reason = masses
                     ? fmt::format(
                           "the gravity torque about axis {} is below {:g} N·mm in every "
                           "measured configuration (largest {:.2g} N·mm: {}), so nothing "
                           "deflects the joint",
                           joint, kGravityTorqueFloorNmm, tau, unloaded_cause(model, tool, joint))
                     : "the robot file gives no masses ('masses:'), so the gravity torques that "
                       "deflect the joint are unknown";
    setup.dropped.push_back(dep);
    names.push_back(setup.layout.names[static_cast<size_t>(i)]);
    if (masses)
      setup.warnings.push_back(fmt::format("{} not identified: {}", names.back(), dep.reason));
  }
  if (!masses && !names.empty())
    setup.warnings.push_back(fmt::format(
        "the robot file of {} gives no masses ('masses:' with each link's mass_kg and cog_mm) "
        "and the tool no payload, so the joint compliances ({}) cannot be identified: add the "
        "masses to the robot file, or calibrate at level kinematic",
        model.name, fmt::join(names, ", ")));
  // A payload without link masses: the fit explains the arm's own weight, which deflects the
  // joints too, by the payload's torque alone — compliances biased, silently.
  std::vector<std::string> biased;
  for (int joint = 1; joint <= kJointCount && masses && !link_masses; ++joint)
    if (candidates[static_cast<size_t>(compliance_param(joint))])
      biased.push_back(setup.layout.names[static_cast<size_t>(compliance_param(joint))]);
  if (!biased.empty())
    setup.warnings.push_back(fmt::format(
        "the robot file of {} gives no link masses ('masses:'), only the tool's payload: the "
        "compliances ({}) see the payload's torque alone and absorb the deflection under the "
        "arm's own weight, so their values are biased. Add each link's mass_kg and cog_mm to the "
        "robot file (the maker's data sheet or CAD), or calibrate at level kinematic",
        model.name, fmt::join(biased, ", ")));
}

/// Preferred order for the rank test: extras (target coordinates, ballbar centre) first, then
/// the model parameters in layout order; of a dependent group the later one is dropped.
std::vector<int> preference_order(const UnknownLayout& layout, const std::vector<bool>& requested) {
  std::vector<int> order;
  for (int i = kParameterCount; i < layout.size(); ++i)
    if (requested[i]) order.push_back(i);
  for (int i = 0; i < kParameterCount; ++i)
    if (requested[i]) order.push_back(i);
  return order;
}

}  // namespace

std::string describe_dependency(const UnknownLayout& layout, const RobotModel& model,
                                const Dependency& dep) {
  if (dep.depends_on.empty()) return "the measurements do not depend on it";
  std::string text = "depends on ";
  for (size_t i = 0; i < dep.depends_on.size() && i < 4; ++i)
    text += fmt::format("{}{} ({:+.3f})", i ? ", " : "", layout.names[dep.depends_on[i].first],
                        dep.depends_on[i].second);
  if (dep.depends_on.size() > 4) text += fmt::format(" and {} more", dep.depends_on.size() - 4);
  // Two d's along parallel consecutive axes move the chain identically
  // (docs/method/03-error-model.md §2).
  const auto& name = layout.names[dep.column];
  for (const auto& [other, weight] : dep.depends_on) {
    const std::string& o = layout.names[other];
    if (name.size() == 7 && o.size() == 7 && name.substr(5) == ".d" && o.substr(5) == ".d") {
      const int a = std::min(name[4], o[4]) - '0', b = std::max(name[4], o[4]) - '0';
      if (b == a + 1 && std::abs(std::sin(model.mdh[b - 1].alpha)) < 1e-9)
        text += fmt::format(": axes {} and {} are parallel", a, b);
    }
  }
  return text;
}

namespace {

/// Columns of J (unknowns `columns`) scaled by each unknown's plausible error: mm of effect.
void scale_to_plausible_errors(const UnknownLayout& layout, const std::vector<int>& columns,
                               Eigen::MatrixXd& J) {
  for (size_t c = 0; c < columns.size(); ++c)
    J.col(static_cast<Eigen::Index>(c)) *= layout.plausible_error(columns[c]);
}

/// A dropped unknown in words, for the user (warning) and the model file (reason). `columns`
/// maps the dependency's column indices to unknowns; `held`: the fit holds it at its start.
void explain_group(const std::vector<int>& columns, const RobotModel& model,
                   const MeasurementSet& data, const Tool& tool, bool held, Dependency dep,
                   IdentificationSetup& setup) {
  dep.column = columns[static_cast<size_t>(dep.column)];
  for (auto& entry : dep.depends_on) entry.first = columns[static_cast<size_t>(entry.first)];
  const std::string& name = setup.layout.names[static_cast<size_t>(dep.column)];
  // On-axis targets: joint 6 turns them in place (link6.theta unseen, link6 couples to link5).
  bool on_axis = data.kind != MeasurementKind::Poses && !tool.targets.empty();
  for (const Target& t : tool.targets)
    on_axis = on_axis && t.known && t.position_mm.head<2>().norm() < 1.0;
  const std::string advice = fmt::format(
      "{}add targets off the tool axis or more varied configurations, or choose what to hold "
      "with --fix",
      on_axis ? "every target lies on the tool axis (joint 6 turns it in place): " : "");
  const std::string action =
      held ? fmt::format("{} is held at its nominal value", name)
           : "fitted anyway (--keep-near-dependent): expect arbitrary values with large σ";
  if (dep.depends_on.empty() || dep.correlation < kNearDependenceCorrelation) {
    if (!dep.depends_on.empty()) {  // barely seen, not a combination
      dep.reason = fmt::format(
          "held at nominal: these measurements barely see it (σ beyond {:g} "
          "plausible errors)",
          kUndeterminedFactor);
      setup.warnings.push_back(fmt::format(
          "{}: these measurements barely see it (σ beyond {:g} plausible errors: {:g} {}); {}; {}",
          name, kUndeterminedFactor,
          kUndeterminedFactor * setup.layout.plausible_error(dep.column) *
              setup.layout.to_external(dep.column),
          setup.layout.unit(dep.column), action, advice));
      if (held) setup.dropped.push_back(dep);
      return;
    }
    setup.warnings.push_back(
        fmt::format("{}: these measurements do not depend on it; {}; {}", name, action, advice));
    setup.dropped.push_back(dep);
    return;
  }
  const std::string exact = describe_dependency(setup.layout, model, dep);
  const bool model_own = exact.find("are parallel") != std::string::npos;
  std::vector<std::string> group;
  for (const auto& [other, weight] : dep.depends_on)
    if (std::abs(weight) >= 0.1 && group.size() < 3)
      group.push_back(setup.layout.names[static_cast<size_t>(other)]);
  group.push_back(name);
  const std::string what = dep.correlation < 1.0
                               ? fmt::format(
                                     "only their combination is determined by these measurements "
                                     "(correlation {:.6f})",
                                     dep.correlation)
                               : "only their combination is determined by these measurements";
  if (!model_own)
    setup.warnings.push_back(
        fmt::format("{}: {}; {}; {}", fmt::join(group, ", "), what, action, advice));
  if (!held) return;
  dep.reason = model_own || dep.correlation >= 1.0
                   ? "not identifiable: " + exact
                   : fmt::format("held at nominal: {}: {}", fmt::join(group, ", "), what);
  setup.dropped.push_back(dep);
}

/// Near-dependent groups of the data's design `J` (columns `kept`, in preference order): warned
/// by name before the fit and, when `resolve`, the latest member of each is held at its start
/// value (dropped, with the group in its reason) so that the model stays physically sensible.
void resolve_near_dependencies(const Eigen::MatrixXd& J, const RobotModel& model,
                               const MeasurementSet& data, const Tool& tool, bool resolve,
                               std::vector<int>& kept, IdentificationSetup& setup) {
  std::vector<int> all(kept.size());
  for (size_t i = 0; i < kept.size(); ++i) all[i] = static_cast<int>(i);
  std::vector<int> held;
  const double noise =
      setup.options.instrument_sigma_mm > 0 ? setup.options.instrument_sigma_mm : kReferenceNoiseMm;
  for (const Dependency& dep : near_dependencies(J, all, noise)) {
    explain_group(kept, model, data, tool, resolve, dep, setup);
    if (resolve) held.push_back(kept[static_cast<size_t>(dep.column)]);
  }
  kept.erase(
      std::remove_if(kept.begin(), kept.end(),
                     [&](int c) { return std::find(held.begin(), held.end(), c) != held.end(); }),
      kept.end());
}

}  // namespace

IdentificationSetup prepare_identification(const RobotModel& model, const Tool& tool,
                                           const MeasurementSet& data,
                                           const IdentifyOptions& options) {
  check_data(tool, data);
  check_orientation_weight(options.orientation_weight_mm);
  IdentificationSetup setup;
  setup.model = model;
  if (options.warmup_time_constant_s) {
    if (!(*options.warmup_time_constant_s >= 1 && *options.warmup_time_constant_s <= 1e6))
      throw InputError({"", 0, 0, "--warmup-tau-s"},
                       fmt::format("warm-up time constant {} s: expected seconds in [1, 1e6] (a "
                                   "minute to a working week)",
                                   *options.warmup_time_constant_s));
    setup.model.warmup_time_constant_s = *options.warmup_time_constant_s;
  }
  setup.tool = tool;
  setup.kind = data.kind;
  setup.layout = make_unknown_layout(tool, data.kind);
  setup.options = options;
  setup.requested = select_unknowns(setup.layout, options.level, options.identify, options.fix);
  refuse_gearless_motor_terms(model, options.identify, setup.requested);
  setup.start = Eigen::VectorXd::Zero(setup.layout.size());
  if (options.start_parameters.size() != 0 && options.start_parameters.size() != kParameterCount)
    throw std::invalid_argument("IdentifyOptions::start_parameters: expected every parameter");
  setup.start.head<kParameterCount>() = options.start_parameters.size() != 0
                                            ? ParameterVector(options.start_parameters)
                                            : model.nominal();
  bool all_base = data.kind != MeasurementKind::Distances;
  for (int i = 0; i < kBaseParamCount; ++i) all_base = all_base && setup.requested[i];
  setup.fit_base = all_base;

  const ResidualContext context{&setup.model, &setup.tool, &data, &setup.layout,
                                options.orientation_weight_mm};
  Eigen::VectorXd u0 = setup.start;
  initial_guess(context, setup.fit_base, u0);

  check_joint_limits(model, data, setup.warnings);
  if (const auto warning = poses_without_tcp_warning(tool, data))
    setup.warnings.push_back(*warning);
  std::vector<bool> candidates = setup.requested;
  drop_unloaded_compliances(model, tool, data, u0, candidates, setup);
  drop_one_sided_backlash(data, candidates, setup);
  drop_isothermal_expansion(model, data, candidates, setup);
  seen_through_compliances(candidates, setup, u0);

  // The model's own dependencies, on a rich synthetic design.
  const std::vector<int> order = preference_order(setup.layout, candidates);
  const MeasurementSet synthetic = synthetic_design(setup.model, data);
  ResidualContext synthetic_context = context;
  synthetic_context.data = &synthetic;
  Eigen::MatrixXd J;
  stacked_residuals(synthetic_context, u0, order, nullptr, &J);
  scale_to_plausible_errors(setup.layout, order, J);
  std::vector<int> positions(order.size());
  for (size_t i = 0; i < order.size(); ++i) positions[i] = static_cast<int>(i);
  const RankAnalysis structural = analyse_rank(J, positions, kRankTolerance, kNegligibleEffectMm);
  std::vector<int> kept;
  for (int p : structural.kept) kept.push_back(order[static_cast<size_t>(p)]);
  for (const Dependency& dep : structural.dropped)
    explain_group(order, model, data, tool, true, dep, setup);
  if (kept.empty())
    throw InputError({data.file, 0, 0, "--level"},
                     "nothing to identify: every requested parameter is fixed or not seen by "
                     "these measurements");

  // Enough equations?
  const int k = data.residuals_per_row();
  const auto n = static_cast<int>(kept.size());
  const int m = static_cast<int>(data.size()) * k;
  if (m <= n) {
    const char* kind = data.kind == MeasurementKind::Points  ? "point"
                       : data.kind == MeasurementKind::Poses ? "pose"
                                                             : "distance";
    throw InputError(
        {data.file, 0, 0, ""},
        fmt::format("too few measurements: level {} identifies {} unknowns here; a {} row gives "
                    "{} equation{}, so at least {} rows are needed and the file has {} (the "
                    "published calibrations use 35–50 configurations)",
                    level_name(options.level), n, kind, k, k > 1 ? "s" : "", n / k + 1,
                    data.size()));
  }

  // The data's own design.
  stacked_residuals(context, u0, kept, nullptr, &J);
  scale_to_plausible_errors(setup.layout, kept, J);
  std::vector<int> all(kept.size());
  for (size_t i = 0; i < kept.size(); ++i) all[i] = static_cast<int>(i);
  const RankAnalysis design = analyse_rank(J, all, kRankTolerance, kNegligibleEffectMm);
  if (!design.dropped.empty()) {
    std::string list;
    for (Dependency dep : design.dropped) {
      dep.column = kept[static_cast<size_t>(dep.column)];
      for (auto& entry : dep.depends_on) entry.first = kept[static_cast<size_t>(entry.first)];
      list += fmt::format("\n  {}: {}", setup.layout.names[dep.column],
                          describe_dependency(setup.layout, model, dep));
    }
    throw InputError({data.file, 0, 0, ""},
                     fmt::format("the measurements cannot identify {} of the unknowns (rank-"
                                 "deficient design):{}\nmeasure more varied configurations or "
                                 "hold them with --fix",
                                 design.dropped.size(), list));
  }
  resolve_near_dependencies(J, model, data, tool, options.resolve_near_dependencies, kept, setup);
  std::sort(kept.begin(), kept.end());
  setup.free = kept;
  Eigen::MatrixXd Jf;
  stacked_residuals(context, u0, setup.free, nullptr, &Jf);
  setup.scales = Jf.colwise().norm().cwiseInverse().transpose();
  return setup;
}

FitResult fit_unknowns(const IdentificationSetup& setup, const MeasurementSet& data) {
  const ResidualContext context{&setup.model, &setup.tool, &data, &setup.layout,
                                setup.options.orientation_weight_mm};
  FitResult out;
  out.unknowns = setup.start;
  initial_guess(context, setup.fit_base, out.unknowns);
  out.start = out.unknowns;
  out.status =
      solve(context, setup.free, setup.scales, setup.options.max_iterations, 0.0, out.unknowns);
  if (setup.options.huber) {
    out.huber_scale_mm = setup.options.huber_scale_mm;
    if (out.huber_scale_mm <= 0) {
      Eigen::VectorXd r;
      stacked_residuals(context, out.unknowns, {}, &r, nullptr);
      std::vector<double> a(r.data(), r.data() + r.size());
      for (double& v : a) v = std::abs(v);
      std::nth_element(a.begin(), a.begin() + static_cast<long>(a.size() / 2), a.end());
      out.huber_scale_mm = std::max(3 * 1.4826 * a[a.size() / 2], 1e-9);
    }
    const SolverStatus first = out.status;
    out.status = solve(context, setup.free, setup.scales, setup.options.max_iterations,
                       out.huber_scale_mm, out.unknowns);
    out.status.initial_rms_mm = first.initial_rms_mm;
    out.status.iterations += first.iterations;
    Eigen::VectorXd r;
    stacked_residuals(context, out.unknowns, {}, &r, nullptr);
    out.status.final_rms_mm = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
  }
  return out;
}

}  // namespace robcal
