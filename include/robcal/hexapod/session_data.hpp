#pragma once
/// \file
/// A measurement session's readings as the calibration uses them (docs/method/07-hexapod.md §6,
/// published procedure): the journal replayed over its plan gives the fixture sides and, per
/// configuration, the six legs or a "retry"; the plan gives the joints, the leg design and assembly
/// mode of each configuration, where the robot put the base cups and the tool fixture mount.
///
/// From there: the world frame from the base cups (world_frame.hpp), each configuration's tool
/// fixture pose by the direct kinematics, expressed in the robot frame through that world frame
/// (the standard poses measurement file), the raw legs as a CSV, and the flange poses the
/// configurations to retry need (for re-planning them on a preliminary model).
///
/// Several sessions of one cell combine: the first pass and the re-measurement of its retries.
/// Sessions of several base-fixture placements (issue 20) are grouped by placement
/// (load_placements): each placement has its own world frame (docs/method/08-world-frame.md §4).

#include <filesystem>
#include <string>
#include <vector>

#include "robcal/hexapod/measurement.hpp"
#include "robcal/hexapod/session.hpp"
#include "robcal/hexapod/world_frame.hpp"

namespace robcal::hexapod {

/// A configuration a leg of which was out of the ballbar's range.
struct RetryConfiguration {
  std::string config;  ///< label, as in the poses file
  std::string pose;    ///< pose label ("P07")
  std::string labels;  ///< arm configuration labels
  int mode = 1;
  LegDesign design;
  std::vector<PhysicalLeg> legs;       ///< as the plan lists them (the design's six, then extras)
  Vector6d joints = Vector6d::Zero();  ///< as planned, controller, rad
};

struct SessionData {
  std::string source;               ///< the session(s), for messages
  std::filesystem::path plan_file;  ///< the (first) session's plan file
  SessionPlan plan;                 ///< … and its contents: ballbar set-up and cell
  TriangleSides tool_sides, base_sides;
  std::optional<std::array<double, 3>> tool_cup4_mm{};  ///< measured d14, d24, d34 of a fourth cup
  std::optional<std::array<double, 3>> base_cup4_mm{};  ///< … of a fourth base cup
  [[nodiscard]] FixtureDistances tool_fixture() const { return {tool_sides, tool_cup4_mm}; }
  [[nodiscard]] FixtureDistances base_fixture() const { return {base_sides, base_cup4_mm}; }
  Cups<double> setting_points;        ///< where the robot put the setting ball, robot frame
  Pose<double> flange_T_tool;         ///< tool fixture frame in the flange frame
  std::vector<LegReadings> readings;  ///< configurations with all their legs read
  std::vector<RetryConfiguration> retry;
  int pending = 0;  ///< configurations the session has not reached yet
};

/// Loads a session: `session` is a directory holding plan.json and journal.jsonl, or a journal
/// file whose plan is `plan`. Throws InputError naming the file and key when the plan lacks what
/// the calibration needs (setting-ball points, tool mount, assembly modes: plans written by
/// `robcal hexapod plan` have them) or the fixture sides were never read.
SessionData load_session_data(const std::filesystem::path& session,
                              const std::filesystem::path& plan = {});

/// Sessions of one cell in order: readings and retries of all (a retry measured by a later
/// session is no longer a retry), sides, cups and mount of the first. Throws InputError when a
/// later session's setting points or tool mount differ from the first one's.
SessionData merge_sessions(const std::vector<SessionData>& sessions);

/// Loads and merges sessions: directories, or one journal file with its `plan` (InputError with
/// key "--plan" when a plan is given with several sessions).
SessionData load_sessions(const std::vector<std::string>& sessions,
                          const std::filesystem::path& plan = {});

/// Sessions grouped by base-fixture placement (their setting-ball points), in the order each
/// placement first appears, each group merged as merge_sessions does. Throws InputError naming
/// the session and key when two placements' base cups (B4's included) overlap (a cup of one within
/// a cup diameter,
/// 25 mm, of a cup of another: the same placement given twice with different points, or fixtures
/// that cannot both stand there) or the tool fixture mount differs between placements.
std::vector<SessionData> group_placements(const std::vector<SessionData>& sessions);

/// Loads sessions and groups them by placement (InputError with key "--plan" when a plan is given
/// with several sessions).
std::vector<SessionData> load_placements(const std::vector<std::string>& sessions,
                                         const std::filesystem::path& plan = {});

/// World frame from the planned setting-ball points and the measured base sides.
WorldFrameFit session_world_frame(const SessionData& data);

/// The poses MeasurementSet of the readings (robot frame through the world frame).
MeasurementSet session_pose_measurements(const SessionData& data);

/// The raw legs as CSV: `config,pose,mode,j1..j6,leg,base_cup,tool_cup,length` (deg, mm), one
/// row per leg, the fixture sides and the frame in `#` comment lines.
std::string session_legs_csv(const SessionData& data);

/// Where the flange must be, robot frame, for a configuration's pose with every leg at the
/// ballbar's length, given the world frame of the base cups.
Pose<double> required_flange_pose(const SessionData& data, const WorldFrameFit& world,
                                  const RetryConfiguration& retry);

}  // namespace robcal::hexapod
