#pragma once
/// \file
/// The tool on the flange: its payload (drives the gravity compliance), its measurement
/// targets (SMRs, nests, cups) and its tool centre frame, all in the flange frame, mm.

#include <Eigen/Geometry>
#include <string>
#include <string_view>
#include <vector>

#include "robcal/model/robot_model.hpp"

namespace robcal {

/// A point on the tool (flange frame, mm). `known == false`: its coordinates are identified.
struct Target {
  std::string name;
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();
  bool known = true;
};

struct Tool {
  PointMass payload;  ///< mass and CoG in the flange frame
  std::vector<Target> targets;
  Eigen::Isometry3d flange_T_tcp = Eigen::Isometry3d::Identity();  ///< TCP frame in the flange
  bool tcp_given = false;  ///< the tool file has `tcp:` (poses without it are the flange's)
  /// False when the tool file writes `tcp: ~` or `position_mm: ~` / `quaternion_wxyz: ~`: the
  /// part is identified from pose measurements (flange_T_tcp holds the start: identity, zero).
  bool tcp_position_known = true, tcp_orientation_known = true;

  /// Index of the target with this name, or -1.
  [[nodiscard]] int target_index(std::string_view name) const {
    for (size_t i = 0; i < targets.size(); ++i)
      if (targets[i].name == name) return static_cast<int>(i);
    return -1;
  }
};

}  // namespace robcal
