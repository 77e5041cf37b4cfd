#pragma once
/// \file
/// The calibrated robot prepared for inverse kinematics: constants of the error model
/// (METHOD §2–§3) precomputed once, then the TCP pose and its exact joint Jacobian in one pass.
///
/// Jacobian (world frame, rows v then ω, columns = controller joints, mm/rad and rad/rad):
///   with θu the undeflected link angles (θu = scale·q + offset), θ = θu + c·τ(θu) the
///   deflected ones and q = M·j + offset the model angles from controller joints j,
///   J = J_θ · (I + diag(c)·∂τ/∂θu) · diag(scale) · M,
/// J_θ the geometric Jacobian of the deflected chain (column k: [z_k × (p_tcp − o_k); z_k]).
/// The gravity torque τ_i = z_i · ((C_i − M_i·o_i) × g), with M_i, C_i the mass and first
/// moment of links i..6 and the payload (world frame), gives in closed form, V_i = C_i − M_i·o_i:
///   ∂τ_i/∂θu_k = (z_k × z_i)·(V_i × g) + z_i·((z_k × V_i) × g)   for k ≤ i,
///   ∂τ_i/∂θu_k = z_i·((z_k × V_k) × g)                            for k > i.
/// Checked against ceres::Jet autodiff of `flange_pose<T>` and finite differences in the tests.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// Immutable constants of one calibrated robot with one payload and one tool.
struct CalibratedChain {
  Eigen::Matrix3d base_R_xy = Eigen::Matrix3d::Identity();  ///< Rot_x(α_b)·Rot_y(β_b)
  Eigen::Vector3d base_p = Eigen::Vector3d::Zero();         ///< (x_b, y_b, d1 + z_b)
  double base_gamma = 0;
  std::array<double, kJointCount> cos_alpha{}, sin_alpha{}, a{}, d{};  ///< links 2..6 at [1..5]
  std::array<double, kJointCount> theta_offset{};  ///< link 1: the model's θ offset
  std::array<double, kJointCount> scale{};
  std::array<double, kJointCount> compliance{};  ///< [0] = 0 (joint 1 has none)
  bool compliant = false;
  std::array<double, kJointCount> mass{};             ///< link 6 includes the payload
  std::array<Eigen::Vector3d, kJointCount> moment{};  ///< m·CoG in the link frame (kg·mm)
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< world, m/s²
  Matrix6d joint_map = Matrix6d::Identity();
  Vector6d joint_offset = Vector6d::Zero();
  bool map_identity = true;
  Pose<double> flange_T_tcp;
};

/// Precomputes the chain for `params` (METHOD §3 layout), the payload carried and the tool.
CalibratedChain make_calibrated_chain(const RobotModel& model, const ParameterVector& params,
                                      const PointMass& payload, const Pose<double>& flange_T_tcp);

/// World pose of the TCP for controller joints (rad); the Jacobian too when `jacobian` is not
/// null. Equals flange_pose(model, payload, params, joints) · flange_T_tcp.
Pose<double> calibrated_tcp_pose(const CalibratedChain& chain, const Vector6d& joints,
                                 Matrix6d* jacobian = nullptr);

}  // namespace robcal
