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

/// One of several payloads a calibration carries (tool file `payloads:`), named by measurement
/// rows' `payload` column (docs/method/03-error-model.md §7).
struct NamedPayload {
  std::string name;
  PointMass mass;
};

struct Tool {
  PointMass payload;  ///< mass and CoG in the flange frame
  std::vector<Target> targets;
  Eigen::Isometry3d flange_T_tcp = Eigen::Isometry3d::Identity();  ///< TCP frame in the flange
  bool tcp_given = false;  ///< the tool file has `tcp:` (poses without it are the flange's)
  /// False when the tool file writes `tcp: ~` or `position_mm: ~` / `quaternion_wxyz: ~`: the
  /// part is identified from pose measurements (flange_T_tcp holds the start: identity, zero).
  bool tcp_position_known = true, tcp_orientation_known = true;

  std::vector<NamedPayload> payloads;  ///< further payloads rows may name (empty: one payload)

  /// The payload of a row: payloads[index], or `payload` for index −1.
  [[nodiscard]] const PointMass& payload_of(int index) const {
    return index < 0 ? payload : payloads[static_cast<size_t>(index)].mass;
  }
  /// Index of the named payload in `payloads`, or -1.
  [[nodiscard]] int payload_index(std::string_view name) const {
    for (size_t i = 0; i < payloads.size(); ++i)
      if (payloads[i].name == name) return static_cast<int>(i);
    return -1;
  }

  /// Index of the target with this name, or -1.
  [[nodiscard]] int target_index(std::string_view name) const {
    for (size_t i = 0; i < targets.size(); ++i)
      if (targets[i].name == name) return static_cast<int>(i);
    return -1;
  }
};

}  // namespace robcal
