#include "robcal/kinematics/closed_form_ik.hpp"

#include <fmt/format.h>

#include "robcal/core/units.hpp"
#include "robcal/kinematics/numeric_ik.hpp"

namespace robcal {

std::optional<ClosedFormIk> analyze_closed_form(const RobotModel& model, std::string* why_not) {
  std::string not_ortho, not_parallel, not_general;
  if (auto g = analyze_ortho_parallel(model, &not_ortho)) return ClosedFormIk(std::move(*g));
  if (auto g = analyze_parallel_axes(model, &not_parallel)) return ClosedFormIk(std::move(*g));
  if (auto g = analyze_general_6r(model, &not_general)) return ClosedFormIk(std::move(*g));
  if (why_not)
    *why_not = fmt::format(
        "not ortho-parallel with a spherical wrist ({}); not three parallel "
        "axes with an offset wrist ({}); no general 6R inverse ({})",
        not_ortho, not_parallel, not_general);
  return std::nullopt;
}

const char* closed_form_name(const ClosedFormIk& geometry) {
  if (std::holds_alternative<OrthoParallelGeometry>(geometry))
    return "ortho-parallel, spherical wrist";
  if (std::holds_alternative<ParallelAxesGeometry>(geometry))
    return "three parallel axes, offset wrist";
  return "general 6R, eigenvalue method";
}

IkResult nominal_ik(const ClosedFormIk& geometry, const Pose<double>& world_T_flange,
                    const Vector6d& seed, unsigned branch_mask) {
  return std::visit([&](const auto& g) { return nominal_ik(g, world_T_flange, seed, branch_mask); },
                    geometry);
}

IkBranchResult nominal_ik_branch(const ClosedFormIk& geometry, const Pose<double>& world_T_flange,
                                 const ArmConfig& config, const Vector6d& seed) {
  return std::visit(
      [&](const auto& g) { return nominal_ik_branch(g, world_T_flange, config, seed); }, geometry);
}

AnyIkResult solve_ik(const RobotModel& model, const Pose<double>& world_T_flange,
                     const Vector6d& seed) {
  AnyIkResult out;
  std::string why_not;
  if (const auto geometry = analyze_closed_form(model, &why_not)) {
    out.method = std::holds_alternative<General6rGeometry>(*geometry)
                     ? fmt::format("every real solution ({})", closed_form_name(*geometry))
                     : fmt::format("closed form ({})", closed_form_name(*geometry));
    const IkResult r = nominal_ik(*geometry, world_T_flange, seed);
    out.status = r.status;
    out.solutions.assign(r.begin(), r.end());
    return out;
  }
  out.method = fmt::format("numeric (damped least squares from the seed); {}", why_not);
  const NumericIkResult r = numeric_ik(model, PointMass{}, model.nominal(), world_T_flange, seed);
  if (r.status != NumericIkStatus::Converged) {
    out.status = IkStatus::Unreachable;
    out.method += fmt::format("; {} after {} iterations, {:.3g} mm and {:.3g}° from the pose",
                              to_string(r.status), r.iterations, r.position_error_mm,
                              rad2deg(r.orientation_error_rad));
    return out;
  }
  if (!r.within_limits) {
    out.status = IkStatus::OutsideLimits;
    return out;
  }
  out.status = IkStatus::Solved;
  out.solutions.push_back({r.joints, arm_config(model, r.joints), false, false});
  return out;
}

}  // namespace robcal
