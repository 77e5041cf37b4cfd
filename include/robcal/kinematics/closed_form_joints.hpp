#pragma once
/// \file
/// The controller side shared by the closed-form inverses (inverse_kinematics.hpp for
/// ortho-parallel robots with a spherical wrist, parallel_axes_ik.hpp for the UR family): the
/// MDH θ offsets, the joint map with its integer inverse, and the joint limits. A closed form
/// solves for MDH link angles θ_i; these turn them into controller joints, and because the map
/// and its inverse are integer, a full turn of any controller joint leaves the pose unchanged.

#include <array>
#include <optional>
#include <string>

#include "robcal/model/robot_model.hpp"

namespace robcal {

/// Immutable once built; safe to share between threads.
struct ClosedFormJoints {
  std::array<double, kJointCount> theta_offset{};  ///< MDH θ offsets, rad
  Matrix6d map_inverse = Matrix6d::Identity();     ///< controller = map_inverse·(q − offset)
  Vector6d map_offset = Vector6d::Zero();
  Matrix6d map_matrix = Matrix6d::Identity();
  bool map_identity = true;
  std::array<JointLimit, kJointCount> limits{};
};

/// The model's offsets, map and limits, or std::nullopt with `why_not` (if given) when the
/// joint map or its inverse is not an integer matrix.
std::optional<ClosedFormJoints> analyze_closed_form_joints(const RobotModel& model,
                                                           std::string* why_not = nullptr);

/// Tolerances for reading a table written in degrees and mm: "α = ±90°", "a = 0".
inline constexpr double kRightAngleTolerance = 1e-9;  // rad
inline constexpr double kZeroLengthTolerance = 1e-9;  // mm

/// ±1 when `alpha` (rad) is ±90° within kRightAngleTolerance, 0 otherwise.
double right_angle_sign(double alpha);

/// Controller joint values (rad) from MDH link angles θ1..θ6 (rad), without limit handling.
inline Vector6d controller_from_link_angles(const ClosedFormJoints& joints,
                                            const std::array<double, kJointCount>& theta) {
  Vector6d q;
  for (int i = 0; i < kJointCount; ++i) q[i] = theta[i] - joints.theta_offset[i];
  if (joints.map_identity) return q;
  return joints.map_inverse * (q - joints.map_offset);
}

/// MDH link angles θ1..θ6 (rad) from controller joint values (rad).
inline std::array<double, kJointCount> link_angles_from_controller(const ClosedFormJoints& joints,
                                                                   const Vector6d& controller) {
  const Vector6d q = joints.map_identity
                         ? controller
                         : Vector6d(joints.map_matrix * controller + joints.map_offset);
  std::array<double, kJointCount> theta;
  for (int i = 0; i < kJointCount; ++i) theta[i] = q[i] + joints.theta_offset[i];
  return theta;
}

}  // namespace robcal
