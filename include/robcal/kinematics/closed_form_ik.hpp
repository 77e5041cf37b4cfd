#pragma once
/// \file
/// The nominal all-solution inverse of a robot, chosen from its geometry: ortho-parallel with a
/// spherical wrist (inverse_kinematics.hpp) or the UR family's three parallel axes with an
/// offset wrist (parallel_axes_ik.hpp), both closed forms with all 8 labelled branches; any
/// other 6R arm, the eigenvalue method of general_6r_ik.hpp (up to 16 solutions). Every turn
/// inside the limits; callers that need "the nominal inverse" of any robot use this.

#include <optional>
#include <string>
#include <variant>

#include "robcal/kinematics/general_6r_ik.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/kinematics/parallel_axes_ik.hpp"

namespace robcal {

using ClosedFormIk = std::variant<OrthoParallelGeometry, ParallelAxesGeometry, General6rGeometry>;

/// The closed form the model's geometry admits, else the general 6R method; std::nullopt with
/// `why_not` (if given) saying why none applies (a joint map without an integer inverse, or a
/// geometry on which the general elimination degenerates).
std::optional<ClosedFormIk> analyze_closed_form(const RobotModel& model,
                                                std::string* why_not = nullptr);

/// Which method: "ortho-parallel, spherical wrist", "three parallel axes, offset wrist" or
/// "general 6R, eigenvalue method".
const char* closed_form_name(const ClosedFormIk& geometry);

/// nominal_ik / nominal_ik_branch of the closed form held.
IkResult nominal_ik(const ClosedFormIk& geometry, const Pose<double>& world_T_flange,
                    const Vector6d& seed = Vector6d::Zero(), unsigned branch_mask = kAllBranches);
IkBranchResult nominal_ik_branch(const ClosedFormIk& geometry, const Pose<double>& world_T_flange,
                                 const ArmConfig& config, const Vector6d& seed);

}  // namespace robcal
