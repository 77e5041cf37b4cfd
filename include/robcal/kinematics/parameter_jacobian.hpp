#pragma once
/// \file
/// Derivatives of measured quantities with respect to the robot's parameter vector (the
/// identification Jacobian's blocks, METHOD §5), in internal units (mm per mm, mm per rad).

#include <Eigen/Core>

#include "robcal/model/parameters.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

using PositionJacobian = Eigen::Matrix<double, 3, kParameterCount>;

/// World position of a flange-frame point and its derivative with respect to all
/// kParameterCount parameters, by automatic differentiation through the templated FK
/// (exact; the reference the analytic regressor is checked against).
void target_position_jacobian_autodiff(const RobotModel& model, const PointMass& payload,
                                       const ParameterVector& params, const Vector6d& joints,
                                       const Eigen::Vector3d& target_flange_mm,
                                       Eigen::Vector3d* position_mm, PositionJacobian* jacobian);

}  // namespace robcal
