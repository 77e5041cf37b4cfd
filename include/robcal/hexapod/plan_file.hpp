#pragma once
/// \file
/// The hexapod plan (docs/method/07-hexapod.md §3, §5) and its file: the planning workflow behind
/// `robcal hexapod plan` and `setup`, and the one reader/writer pair of the plan file (JSON) that
/// `session`, `simulate-readings`, `calibrate` and `replan` read and `plan` and `replan` write.
///
/// A plan file holds the session's script (SessionPlan: ballbar set-up, configurations, setting
/// points, tool mount, sides measured earlier) and, when `robcal hexapod plan` wrote it, the cell
/// it was planned for and the planning outcome. Hand-written plans give only the configurations.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robcal/core/error.hpp"
#include "robcal/hexapod/cup_collision.hpp"
#include "robcal/hexapod/gauge.hpp"
#include "robcal/hexapod/planning.hpp"
#include "robcal/hexapod/poses.hpp"
#include "robcal/hexapod/session.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal::hexapod {

/// A planned leg to a fourth cup is within this fraction of the gauge's range of the ballbar's
/// length: the rest is left for the robot's errors (the design legs, at the set-up length, have
/// the whole range).
inline constexpr double kExtraLegRangeFraction = 0.5;

/// The cell a plan is made for, as the operator describes it.
struct HexapodPlanRequest {
  std::string robot = "fanuc-lrmate200ic";  ///< built-in name or robot file, kept in the plan
  HexapodGeometry geometry;                 ///< design fixtures and the ballbar's set-up length
  /// Rough base-fixture placement in the robot frame: cup centroid x, y, z (mm), yaw about z (deg).
  std::array<double, 4> placement{450, 0, 300, 0};
  /// Tilt of the pivoting platform (deg): the cup plane turned about the placement's x axis
  /// (after the yaw), issue 20.
  double tilt_deg = 0;
  double tool_offset_mm = 100;  ///< tool fixture centroid along the flange z
  double ball_offset_mm = 100;  ///< setting ball along the flange z
  double table_z_mm = 0;        ///< table plane, robot frame
  double angle_deg = 30;        ///< pruning: redundant when closer in orientation …
  double distance_mm = 50;      ///< … and in position (tool-fixture centroid)
  LengthGauge gauge;            ///< the session's reading range (gauge.hpp); σ for simulations
  /// Poses whose cups or legs collide are refused before pruning (cup_collision.hpp).
  CupClearance cups;
  /// The user's cell (`--cell`, campaign/cell.hpp): floor and keep-out boxes respected.
  std::optional<campaign::Cell> workcell;
};

/// "x,y,z,yaw" (mm, deg) → placement; errors name `where` and say what was expected.
std::array<double, 4> parse_placement(const std::string& text, const SourceLocation& where);
/// The placement's "x,y,z,yaw" text, as the plan file stores it.
std::string placement_text(const std::array<double, 4>& placement);
/// The rough base-fixture placement (cup centroid frame) in the robot frame: Trans(x, y, z) ·
/// Rz(yaw) · Rx(tilt).
Pose<double> placement_pose(const std::array<double, 4>& placement, double tilt_deg = 0);

/// Where the robot puts the setting ball for one base cup (flange z pointing down, the ball
/// `ball_offset_mm` below the flange), and the nominal configurations that reach it.
struct SettingBallPoint {
  Eigen::Vector3d ball_position_mm = Eigen::Vector3d::Zero();
  std::vector<PoseConfiguration> configurations;  ///< empty for robots without closed-form IK
};
/// B1..B3, then B4 when `base_cup4_mm` gives a fourth base cup (fourth_setting_ball_point).
std::vector<SettingBallPoint> plan_setting_ball(
    const RobotModel& model, const Pose<double>& placement, double side_mm, double ball_offset_mm,
    const std::optional<std::array<double, 3>>& base_cup4_mm = std::nullopt);

/// The set-up's JSON, as the plan file's "setting_ball" holds it: cup, ball position, the
/// configurations (labels, joints_deg).
nlohmann::json setting_ball_json(const std::vector<SettingBallPoint>& points);

/// What `robcal hexapod setup` reports: {robot (as given), side_mm, setting_ball
/// (setting_ball_json)}.
nlohmann::json setup_json(const std::string& robot, double side_mm,
                          const std::vector<SettingBallPoint>& points);

/// The planning outcome of one pose, as the plan file lists it.
struct PlannedPose {
  std::string label, description, ik;
  int configurations = 0, rejected_table = 0, rejected_fixture = 0, rejected_workcell = 0;
};

/// What `robcal hexapod plan` found for the cell.
struct PlanOutcome {
  int poses_enumerated = 0, poses_kept = 0, poses_measurable = 0, configurations_measurable = 0;
  std::vector<PlannedPose> poses;
  /// Poses refused before pruning because their cups or legs collide (label, reason).
  std::vector<std::pair<std::string, std::string>> refused;
};

/// A re-plan of the configurations to retry on a preliminary model (`robcal hexapod replan`).
struct Replanned {
  std::string sessions;  ///< the session(s) whose retries were re-planned
  std::string model;     ///< the calibrated model file
  /// Per configuration of the plan: the joints first planned (deg) that the re-plan replaced.
  std::vector<std::vector<double>> planned_joints_deg;
};

/// Everything a plan file holds.
struct HexapodPlan {
  SessionPlan session;                     ///< the session's script
  std::optional<HexapodPlanRequest> cell;  ///< absent from hand-written plans
  std::vector<SettingBallPoint> setting;   ///< with `cell`: the set-up of the base cups (3 or 4)
  std::optional<PlanOutcome> outcome;      ///< with `cell`: the planning outcome
  std::optional<Replanned> replanned;
};

/// The poses a plan offers for `geometry`: all enumerated ones (`enumerated`), each with its legs
/// to a fourth cup within kExtraLegRangeFraction of `gauge_range_mm` (add_fourth_cup_legs), then
/// screened for colliding cups and legs and pruned (screen_poses). Throws InputError naming
/// --tool-cup4-mm or --base-cup4-mm when a fourth cup has no leg in any pose kept.
PoseScreening plannable_poses(const HexapodGeometry& geometry, double gauge_range_mm,
                              double angle_deg, double distance_mm, const CupClearance& cups,
                              int* enumerated = nullptr);

/// Plans every pose of the cell (enumeration, pruning, IK with clearance checks) and the set-up
/// of the base cups. Throws InputError on bad fixtures or a robot without closed-form IK.
HexapodPlan plan_hexapod(const RobotModel& model, const HexapodPlanRequest& request);

/// The plan file's JSON, and the plan back from it: errors name `file` and the key.
nlohmann::json hexapod_plan_json(const HexapodPlan& plan);
HexapodPlan parse_hexapod_plan(const nlohmann::json& root, const std::string& file);

/// Reads a plan file (JSON); writes one whole or not at all.
HexapodPlan read_hexapod_plan(const std::filesystem::path& path);
void write_hexapod_plan(const std::filesystem::path& path, const HexapodPlan& plan);
/// The plan file's text (what write_hexapod_plan writes).
std::string hexapod_plan_text(const HexapodPlan& plan);

}  // namespace robcal::hexapod
