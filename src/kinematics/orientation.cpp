#include "robcal/kinematics/orientation.hpp"

#include <fmt/format.h>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal {

Eigen::Quaterniond to_quaternion(const Eigen::Matrix3d& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return q;
}

Eigen::Vector3d euler_angles_deg(const Eigen::Matrix3d& R, EulerConvention convention) {
  // R = Rz(a) Ry(b) Rx(c): b = asin(-r20), a = atan2(r10, r00), c = atan2(r21, r22);
  // at b = ±90° (gimbal lock) c is set to 0 and a absorbs the rest.
  const double b = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  double a, c;
  if (std::abs(R(2, 0)) < 1.0 - 1e-12) {
    a = std::atan2(R(1, 0), R(0, 0));
    c = std::atan2(R(2, 1), R(2, 2));
  } else {
    c = 0.0;
    a = std::atan2(-R(0, 1), R(1, 1));
  }
  const Eigen::Vector3d abc(rad2deg(a), rad2deg(b), rad2deg(c));
  return convention == EulerConvention::ZyxABC ? abc : Eigen::Vector3d(abc[2], abc[1], abc[0]);
}

Eigen::Matrix3d rotation_from_euler_deg(const Eigen::Vector3d& angles, EulerConvention convention) {
  const Eigen::Vector3d abc = convention == EulerConvention::ZyxABC
                                  ? angles
                                  : Eigen::Vector3d(angles[2], angles[1], angles[0]);
  return (Eigen::AngleAxisd(deg2rad(abc[0]), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(deg2rad(abc[1]), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(deg2rad(abc[2]), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

std::array<std::string, 3> euler_labels(EulerConvention convention) {
  if (convention == EulerConvention::ZyxABC) return {"A", "B", "C"};
  return {"W", "P", "R"};
}

Pose<double> pose_from_position_quaternion(const Eigen::Vector3d& p_mm,
                                           const Eigen::Vector4d& q_wxyz) {
  const double norm = q_wxyz.norm();
  if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-6)
    throw InputError(fmt::format("quaternion (w,x,y,z) must have unit norm, has {:.9f}", norm));
  const Eigen::Quaterniond q(q_wxyz[0] / norm, q_wxyz[1] / norm, q_wxyz[2] / norm,
                             q_wxyz[3] / norm);
  Pose<double> pose;
  pose.R = q.toRotationMatrix();
  pose.p = p_mm;
  return pose;
}

double rotation_distance(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb) {
  return Eigen::AngleAxisd(Ra.transpose() * Rb).angle();
}

}  // namespace robcal
