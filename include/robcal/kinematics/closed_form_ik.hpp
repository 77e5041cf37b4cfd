#pragma once
/// \file
/// The nominal closed-form inverse of a robot, chosen from its geometry: ortho-parallel with a
/// spherical wrist (inverse_kinematics.hpp) or the UR family's three parallel axes with an
/// offset wrist (parallel_axes_ik.hpp). Both give all 8 labelled branches with every turn
/// inside the limits; callers that need "the nominal closed form" of any robot use this.

#include <optional>
#include <string>
#include <variant>

#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/kinematics/parallel_axes_ik.hpp"

namespace robcal {

using ClosedFormIk = std::variant<OrthoParallelGeometry, ParallelAxesGeometry>;

/// The closed form the model's geometry admits, else std::nullopt with `why_not` (if given)
/// saying why each one does not apply.
std::optional<ClosedFormIk> analyze_closed_form(const RobotModel& model,
                                                std::string* why_not = nullptr);

/// Which closed form: "ortho-parallel, spherical wrist" or "three parallel axes, offset wrist".
const char* closed_form_name(const ClosedFormIk& geometry);

/// nominal_ik / nominal_ik_branch of the closed form held.
IkResult nominal_ik(const ClosedFormIk& geometry, const Pose<double>& world_T_flange,
                    const Vector6d& seed = Vector6d::Zero(), unsigned branch_mask = kAllBranches);
IkBranchResult nominal_ik_branch(const ClosedFormIk& geometry, const Pose<double>& world_T_flange,
                                 const ArmConfig& config, const Vector6d& seed);

}  // namespace robcal
