#pragma once
/// \file
/// Planning a hexapod measurement (docs/method/07-hexapod.md §3): for a base-fixture placement and
/// the tool fixture on the flange, the robot configurations that put the tool fixture in each pose
/// — every nominal inverse-kinematics solution within the joint limits that passes simple clearance
/// checks against the table and the base fixture — labelled front/back, up/down, flip/no-flip.
///
/// Frames: the robot frame is the nominal model's world (base at the origin, z up, the table
/// plane z = table_z_mm); the base fixture frame is the world frame of the hexapod
/// (docs/method/08-world-frame.md §1).

#include <optional>
#include <string>
#include <vector>

#include "robcal/campaign/cell.hpp"
#include "robcal/hexapod/poses.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal::hexapod {

/// The cell: where the fixtures are, and the gross-collision model.
struct CellSetup {
  Pose<double> robot_T_base;   ///< base fixture frame in the robot frame
  Pose<double> flange_T_tool;  ///< tool fixture frame in the flange frame
  double table_z_mm = 0;       ///< table plane, robot frame
  /// Elbow, wrist centre and flange must stay this far above the table.
  double table_clearance_mm = 50;
  /// The base fixture occupies a vertical cylinder about its cup centroid: radius = cup
  /// circumradius + this margin, from the table up to the cup plane + this margin. The upper arm,
  /// forearm and wrist (shoulder–elbow–wrist centre–flange segments) must stay out of it.
  double fixture_margin_mm = 60;
  /// The user's cell (campaign/cell.hpp, issue 16): its floor and keep-out boxes, in its world
  /// frame, with the robot at its `robot_base`. The robot's link capsules and the tool cups must
  /// stay above the floor and out of every box (campaign/feasibility.hpp check_configuration;
  /// the instrument's line of sight does not apply to the ballbar).
  std::optional<campaign::Cell> workcell;
  Cups<double> tool_cups_flange{};  ///< with `workcell`: the tool cups, flange frame
};

/// The robot frame of the planner (nominal model, base at the origin) in the workcell's world.
Pose<double> workcell_T_robot(const RobotModel& model, const campaign::Cell& workcell);

/// Empty when the base cups (robot frame; B1..B3, then B4 if any) are above the workcell's floor
/// and outside its keep-out boxes; otherwise which cup and why.
std::string base_fixture_in_workcell(const RobotModel& model, const campaign::Cell& workcell,
                                     const std::vector<Eigen::Vector3d>& base_cups_robot);

/// Default tool-fixture mount: fixture plane perpendicular to the flange axis, its centroid
/// `offset_mm` along the flange z, cups opening away from the flange (fixture z = flange z).
Pose<double> default_tool_mount(const TriangleSides& tool_sides, double offset_mm = 100);

/// Why a configuration was rejected (or Ok).
enum class Clearance { Ok, Table, BaseFixture, Workcell };

/// One measurable configuration of a pose.
struct PoseConfiguration {
  Vector6d joints = Vector6d::Zero();  ///< controller joints, rad
  ArmConfig config;
};

struct PosePlan {
  HexapodPose pose;
  Pose<double> robot_T_flange;  ///< where the flange must be (nominal model)
  IkStatus ik_status = IkStatus::Unreachable;
  /// Measurable ones, one per arm branch (equivalent joint turns are not counted twice).
  std::vector<PoseConfiguration> configurations;
  int rejected_table = 0;     ///< IK solutions within limits rejected by the table check
  int rejected_fixture = 0;   ///< … by the base-fixture check
  int rejected_workcell = 0;  ///< … by the workcell's floor and keep-out boxes
};

struct PlanSummary {
  std::vector<PosePlan> poses;
  int measurable_poses = 0;  ///< poses with at least one configuration
  int configurations = 0;    ///< all configurations of all poses
};

/// Clearance of one configuration (controller joints, rad) of the nominal robot; the base
/// fixture's cylinder covers every cup of `base_cups_robot` (B1..B3, then B4 if any).
Clearance check_clearance(const RobotModel& model, const CellSetup& cell,
                          const std::vector<Eigen::Vector3d>& base_cups_robot,
                          const Vector6d& joints);

/// Plans every pose. Throws InputError when the robot is not ortho-parallel (no closed-form IK).
/// A fourth base cup (`base_cup4_fixture`, base fixture frame) widens the fixture's cylinder.
PlanSummary plan_poses(const RobotModel& model, const CellSetup& cell,
                       const Cups<double>& base_cups_fixture, const std::vector<HexapodPose>& poses,
                       const std::optional<Eigen::Vector3d>& base_cup4_fixture = std::nullopt);

}  // namespace robcal::hexapod
