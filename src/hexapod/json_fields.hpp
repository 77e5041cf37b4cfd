#pragma once
// Vectors and poses in the hexapod files and reports: mm to 1e-9 (or `decimals`), unit
// quaternions (w, x, y, z) to 1e-12.

#include <nlohmann/json.hpp>

#include "robcal/core/rounding.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::hexapod {

inline nlohmann::json vec_json(const Eigen::Vector3d& v, int decimals = 9) {
  return {rounded(v.x(), decimals), rounded(v.y(), decimals), rounded(v.z(), decimals)};
}

inline nlohmann::json pose_json(const Pose<double>& pose) {
  const Eigen::Quaterniond q = to_quaternion(pose.R);
  return {{"position_mm", vec_json(pose.p)},
          {"quaternion_wxyz",
           {rounded(q.w(), 12), rounded(q.x(), 12), rounded(q.y(), 12), rounded(q.z(), 12)}}};
}

}  // namespace robcal::hexapod
