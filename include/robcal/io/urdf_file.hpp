#pragma once
/// \file
/// URDF robot descriptions (ROS; parsed with Debian's urdfdom) in and out of robcal's model.
///
/// In: the six revolute (or continuous) joints of one serial path from the root link to the tip
/// link, fixed joints folded, joint axes in any direction. At the zero joint values every axis
/// is a line in the root frame; the Modified DH frames are rebuilt from those lines (x along the
/// common normal of consecutive axes, or through the previous foot when they are parallel), so
/// the conversion is exact: FK equals the URDF's to rounding. The root link is the world frame;
/// when axis 1 is not the root's z axis the placement goes to the base parameters (x, y, alpha,
/// beta). The flange (frame 6) is the tip link when it lies on axis 6 with z along it (tool0 of
/// ROS-Industrial and UR descriptions); otherwise `flange_T_tip` holds the rest. A continuous
/// joint gets the limits ±360°; masses before joint 1 are left out (they move with nothing). The
/// URDF's joint values are the controller's (joint 1 reversed through the joint map when its axis
/// points down, joint 6 when it points against the tip's z). Inertial masses and CoGs (folded per
/// moving link) become link masses.
///
/// Out: the rigid geometry (link parameters, base placement, joint zero offsets and signs, tool
/// centre frame as a fixed joint to link "tcp"), joint limits and link masses. What URDF cannot
/// hold (compliance, joint scales, periodic errors, coupled joint maps) is listed by name.

#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "robcal/model/robot_model.hpp"

namespace robcal {

struct UrdfImportOptions {
  /// The link taken as the flange; empty: "tool0" when it follows joint 6, else joint 6's child.
  std::string tip_link;
};

struct UrdfImport {
  RobotModel model;
  ParameterVector params;  ///< model.nominal() with the base placement filled in
  Eigen::Isometry3d flange_T_tip = Eigen::Isometry3d::Identity();  ///< mm
  std::array<std::string, kJointCount> joint_names;
  std::string root_link, tip_link;
  /// True when params' base placement is not zero (axis 1 is not the root's z axis).
  [[nodiscard]] bool has_base_placement() const;
  /// True when the tip is off robcal's flange (beyond 1e-9 mm, 1e-12 rad of rounding).
  [[nodiscard]] bool has_tip_offset() const;
};

/// Converts URDF text; `path` names the file in errors. InputError naming the file and the
/// joint or link when it is not a serial chain of six revolute joints (a tree, a prismatic,
/// floating or planar joint, a mimic joint, fewer or more joints, two joints on one axis line).
UrdfImport robot_from_urdf(const std::string& xml, const std::string& path,
                           const UrdfImportOptions& options = {});

/// Reads and converts a URDF file.
UrdfImport load_urdf_robot(const std::string& path, const UrdfImportOptions& options = {});

struct UrdfExport {
  std::string xml;
  /// What the URDF leaves out, by name (e.g. "joint3.compliance"), with why.
  std::vector<std::string> left_out;
};

/// The URDF of `model` with parameter vector `params` (a calibrated model's values); with
/// `flange_T_tcp`, a fixed joint "tool0-tcp" to link "tcp" (mm). Links are base_link,
/// link_1..link_6 (= robcal's link frames) and tool0 (= the flange); joints joint_1..joint_6.
UrdfExport robot_to_urdf(const RobotModel& model, const ParameterVector& params,
                         const Eigen::Isometry3d* flange_T_tcp = nullptr);

}  // namespace robcal
