#pragma once
/// \file
/// Derivatives of measured quantities with respect to the robot's parameter vector (the
/// identification Jacobian's blocks, METHOD §5), in internal units (mm per mm, mm per rad).
///
/// Two implementations of the same derivative: the analytic kinematic regressor (fast, used by
/// the identification) and automatic differentiation through the templated FK (the reference
/// the regressor is checked against in the tests).

#include <Eigen/Core>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/model/parameters.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

using PositionJacobian = Eigen::Matrix<double, 3, kParameterCount>;

/// Spatial (world-frame) twist Jacobian of the flange: column ξ is (v; ω) such that a point p
/// rigidly attached to the flange moves by dp/dξ = v + ω × p (world, mm per unit of ξ) and the
/// flange rotates by ω (rad per unit of ξ, world axes).
using TwistJacobian = Eigen::Matrix<double, 6, kParameterCount>;

/// World pose of the flange and its twist Jacobian with respect to all kParameterCount
/// parameters, analytically (the kinematic regressor):
/// - each geometric parameter is an elementary motion along the chain: a base translation, a
///   rotation about a base axis, a link's Rot_x(α_i) about x_{i-1} through o_{i-1}, Trans_x(a_i)
///   along x_{i-1}, Trans_z(d_i) along z_i;
/// - joint offsets, scales and compliances act through the joint angles θ_i, whose column is
///   the joint twist (o_i × z_i; z_i) of the deflected chain;
/// - with compliance, θ_i = θu_i + c_i·τ_i(θu, params) (METHOD §3), so every parameter also
///   moves θ_i through the gravity torque τ_i; its derivative follows from the same elementary
///   motions applied to τ_i = z_i · ((Σ_{j≥i} m_j (c_j − o_i)) × g) in the undeflected chain.
/// Cost: two chain evaluations plus O(parameters × joints) dot products, ≈1 µs.
void flange_twist_jacobian(const RobotModel& model, const PointMass& payload,
                           const ParameterVector& params, const Vector6d& joints,
                           Pose<double>* world_T_flange, TwistJacobian* jacobian);

/// World position of a flange-frame point and its derivative with respect to all parameters,
/// from the analytic twist Jacobian: dp/dξ = v_ξ + ω_ξ × p.
void target_position_jacobian(const RobotModel& model, const PointMass& payload,
                              const ParameterVector& params, const Vector6d& joints,
                              const Eigen::Vector3d& target_flange_mm, Eigen::Vector3d* position_mm,
                              PositionJacobian* jacobian);

/// Position rows of a twist Jacobian for the world point p: J_v − [p]× J_ω.
PositionJacobian point_jacobian_from_twist(const TwistJacobian& twist, const Eigen::Vector3d& p);

/// World position of a flange-frame point and its derivative with respect to all
/// kParameterCount parameters, by automatic differentiation through the templated FK
/// (exact; the reference the analytic regressor is checked against).
void target_position_jacobian_autodiff(const RobotModel& model, const PointMass& payload,
                                       const ParameterVector& params, const Vector6d& joints,
                                       const Eigen::Vector3d& target_flange_mm,
                                       Eigen::Vector3d* position_mm, PositionJacobian* jacobian);

}  // namespace robcal
