#pragma once
/// \file
/// Generic numerical inverse kinematics: damped least squares (Levenberg–Marquardt) on the
/// templated forward model, so it works for any parameter vector — calibrated robots with
/// compliance, robots that are not ortho-parallel. The joint Jacobian comes from ceres::Jet
/// autodiff through `flange_pose<T>`.
///
/// Error of a pose: e = (p* − p, L·log(R*·Rᵀ)) with p in mm and the rotation vector (rad)
/// weighted by the length L (`rotation_weight_mm`), so millimetres and radians are balanced.
/// Step: (JᵀJ + λ·diag(JᵀJ) + λ·I)·Δq = Jᵀe, λ adapted (÷10 on success, ×10 on failure).

#include <cstdint>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

struct NumericIkOptions {
  int max_iterations = 100;
  double position_tolerance_mm = 1e-7;
  double orientation_tolerance_rad = 1e-10;
  double rotation_weight_mm = 500.0;  ///< L: 1 rad of orientation error weighs as L mm
  double initial_damping = 1e-3;
};

enum class NumericIkStatus : std::uint8_t {
  Converged,      ///< both tolerances met
  MaxIterations,  ///< stopped at max_iterations; `joints` is the best found
  Stalled,        ///< no step reduced the error (unreachable pose or a singularity)
};

/// Human-readable status name.
const char* to_string(NumericIkStatus status);

struct NumericIkResult {
  NumericIkStatus status = NumericIkStatus::Stalled;
  Vector6d joints = Vector6d::Zero();  ///< controller joint values, rad
  int iterations = 0;
  double position_error_mm = 0;
  double orientation_error_rad = 0;
  bool within_limits = false;  ///< the joints are inside the model's limits
};

/// Joints (controller, rad) whose flange pose under `params` (docs/method/03-error-model.md §1
/// layout, with the given payload for compliance) equals `world_T_flange`, iterating from `seed`.
NumericIkResult numeric_ik(const RobotModel& model, const PointMass& payload,
                           const ParameterVector& params, const Pose<double>& world_T_flange,
                           const Vector6d& seed, const NumericIkOptions& options = {});

}  // namespace robcal
