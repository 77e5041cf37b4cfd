#pragma once
/// \file
/// ROS-Industrial OPW parameter files (moveit_opw_kinematics_plugin / opw_kinematics: the seven
/// lengths a1, a2, b, c1..c4 in metres, joint offsets in radians or `deg(x)`, sign corrections)
/// read as a robcal robot model (Modified DH and a joint map).
///
/// OPW's internal angles are q_OPW = sign·J − offset, with J the ROS joint values; its zero
/// pose has the upper arm and forearm upright. In Modified DH (Craig) the same chain is
///   link 1 [α, a, θ0, d] = [0, 0, 0, c1],   link 2 = [−90°, a1, −90°, 0],  link 3 = [0, c2, 0, 0],
///   link 4 = [−90°, −a2, 0, c3],            link 5 = [90°, 0, 0, 0],        link 6 = [−90°, 0,
///   180°, c4]
/// with MDH link angles θ = q_OPW + (0, −90, −90, 0, 0, 180)°: θ = θ0 + q with the joint map
/// q = diag(sign)·J + (−offset + (0, 0, −90, 0, 0, 0)°). This is the derivation of the built-in
/// KUKA KR 6 R900 sixx and of tests/data/opw (checked there against opw_kinematics' own poses).
/// The lateral offset b must be 0 (every ROS-Industrial OPW file has b = 0).
/// The joints are ROS-Industrial's: for FANUC robots ROS's joint 3 is J3 + J2 of the controller
/// (`fanuc_j2_j3_coupling` maps the controller's values, as the built-in FANUC files do).

#include <array>
#include <string>

#include "robcal/io/yaml_support.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

struct OpwParameters {
  double a1 = 0, a2 = 0, b = 0, c1 = 0, c2 = 0, c3 = 0, c4 = 0;  ///< mm
  std::array<double, kJointCount> offsets{};                     ///< rad
  std::array<int, kJointCount> signs{1, 1, 1, 1, 1, 1};
};

/// Reads the parameters from a parsed OPW file: keys `opw_kinematics_geometric_parameters`,
/// `opw_kinematics_joint_offsets`, `opw_kinematics_joint_sign_corrections` (or the
/// `kinematics_solver_` spelling of older files), at the top or under one planning-group key.
/// Errors name the file, line and key.
OpwParameters parse_opw_parameters(const yaml::Node& root);

struct OpwImportOptions {
  std::string name = "OPW robot";
  std::string manufacturer;
  /// Controller J3 measured from the horizontal (FANUC): ROS joint 3 = J3 + J2.
  bool fanuc_j2_j3_coupling = false;
};

/// The robot model of the parameters (see the file comment). Joint limits are not in OPW files:
/// ±180° on every joint, to be replaced by the data sheet's. InputError when b ≠ 0, a sign is
/// not ±1 or c2 (the upper arm) is 0.
RobotModel robot_from_opw(const OpwParameters& parameters, const OpwImportOptions& options = {});

/// Loads an OPW file and converts it.
RobotModel load_opw_robot(const std::string& path, const OpwImportOptions& options = {});

}  // namespace robcal
