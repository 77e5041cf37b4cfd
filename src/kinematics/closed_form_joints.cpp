#include "robcal/kinematics/closed_form_joints.hpp"

#include <Eigen/LU>
#include <cmath>
#include <numbers>

namespace robcal {
namespace {

bool is_integer_matrix(const Matrix6d& m) {
  for (int i = 0; i < 36; ++i)
    if (std::abs(m.data()[i] - std::round(m.data()[i])) > 1e-12) return false;
  return true;
}

}  // namespace

double right_angle_sign(double alpha) {
  constexpr double kHalfPi = std::numbers::pi / 2;
  if (std::abs(alpha - kHalfPi) < kRightAngleTolerance) return 1.0;
  if (std::abs(alpha + kHalfPi) < kRightAngleTolerance) return -1.0;
  return 0.0;
}

std::optional<ClosedFormJoints> analyze_closed_form_joints(const RobotModel& model,
                                                           std::string* why_not) {
  auto fail = [&](const char* reason) -> std::optional<ClosedFormJoints> {
    if (why_not) *why_not = reason;
    return std::nullopt;
  };
  const Matrix6d& M = model.joint_map.matrix;
  if (!is_integer_matrix(M)) return fail("joint map matrix is not integer (signs and couplings)");
  Eigen::FullPivLU<Matrix6d> lu(M);
  if (!lu.isInvertible()) return fail("joint map matrix is singular");
  const Matrix6d inverse = lu.inverse();
  if (!is_integer_matrix(inverse)) return fail("joint map inverse is not integer");
  ClosedFormJoints j;
  for (int i = 0; i < kJointCount; ++i) j.theta_offset[i] = model.mdh[i].theta_offset;
  j.map_matrix = M;
  j.map_inverse = inverse.array().round().matrix();
  j.map_offset = model.joint_map.offset;
  j.map_identity = model.joint_map.is_identity();
  j.limits = model.limits;
  return j;
}

}  // namespace robcal
