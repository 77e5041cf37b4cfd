// Instrument exports joined with the joint log (issue 16 item 4): a simulated campaign written
// by the test in each supported export style, with that style's quirks, imports into a
// measurement CSV that the pipeline's reader reads back to the simulated readings within
// 1e-9 mm; bad input names the file and the row.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <string>

#include "refusal.hpp"
#include "robcal/campaign/instrument_import.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/simulator.hpp"
#include "test_error_groups_support.hpp"

namespace robcal::campaign {
namespace {

/// A simulated campaign of `count` configurations (seeded).
MeasurementSet simulated(InstrumentKind kind, int count, uint64_t seed) {
  const TrueRobot truth =
      published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
  const VirtualInstrument instrument = standard_instrument(kind, truth);
  std::mt19937_64 rng(seed);
  RandomConfigurationOptions options;
  options.box = published_joint_box(truth.robot.model);
  const auto configs = random_configurations(truth, instrument, count, rng, options);
  return simulate_measurements(truth, instrument, configs, rng).measurements;
}

/// Full precision; the decimal point swapped for a comma when asked.
std::string number(double value, char decimal = '.') {
  std::string text = fmt::format("{:.17g}", value);
  if (decimal == ',')
    for (char& c : text)
      if (c == '.') c = ',';
  return text;
}

/// The joint log the robot program writes: config, time (s), target, j1..j6 (degrees).
std::string joint_log(const MeasurementSet& set, bool with_target, double time_jitter = 0) {
  std::string out =
      with_target ? "config,time,target,j1,j2,j3,j4,j5,j6\n" : "config,time,j1,j2,j3,j4,j5,j6\n";
  const size_t n = set.size();
  for (size_t i = 0; i < n; ++i) {
    const bool points = set.kind == MeasurementKind::Points;
    const Vector6d& q = points ? set.points[i].joints : set.poses[i].joints;
    const std::string& config = points ? set.points[i].config : set.poses[i].config;
    out += fmt::format("{},{}", config,
                       number(20.0 * static_cast<double>(i) + time_jitter * ((i % 3) - 1.0)));
    if (with_target) out += fmt::format(",{}", set.points[i].target + 1);
    for (int j = 0; j < kJointCount; ++j) out += "," + number(rad2deg(q[j]));
    out += "\n";
  }
  return out;
}

Tool named_targets() {
  Tool tool;
  for (const char* name : {"1", "2", "3"})
    tool.targets.push_back({name, Eigen::Vector3d::Zero(), true});
  return tool;
}

/// The imported CSV read back by the pipeline's reader matches the simulated readings.
void expect_round_trip(const ImportResult& result, const MeasurementSet& truth) {
  const MeasurementFile back = parse_measurements_csv(result.csv, "imported.csv", named_targets());
  const MeasurementSet& got = back.measurements;
  ASSERT_GE(truth.size(), 6u);
  ASSERT_EQ(got.kind, truth.kind);
  ASSERT_EQ(got.size(), truth.size());
  double worst_mm = 0, worst_rad = 0, worst_rotation = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    if (truth.kind == MeasurementKind::Points) {
      EXPECT_EQ(got.points[i].config, truth.points[i].config);
      EXPECT_EQ(got.points[i].target, truth.points[i].target);
      worst_mm =
          std::max(worst_mm, (got.points[i].position_mm - truth.points[i].position_mm).norm());
      worst_rad = std::max(worst_rad,
                           (got.points[i].joints - truth.points[i].joints).cwiseAbs().maxCoeff());
    } else {
      EXPECT_EQ(got.poses[i].config, truth.poses[i].config);
      worst_mm =
          std::max(worst_mm, (got.poses[i].world_T_tcp.p - truth.poses[i].world_T_tcp.p).norm());
      worst_rad =
          std::max(worst_rad, (got.poses[i].joints - truth.poses[i].joints).cwiseAbs().maxCoeff());
      worst_rotation = std::max(
          worst_rotation,
          Eigen::AngleAxisd(got.poses[i].world_T_tcp.R.transpose() * truth.poses[i].world_T_tcp.R)
              .angle());
    }
  }
  EXPECT_LT(worst_mm, 1e-9);
  EXPECT_LT(worst_rad, 1e-12);
  EXPECT_LT(worst_rotation, 1e-9);
}

TEST(CampaignImport, SpatialAnalyzerCollectionGroupTargetBlankSeparatedJoinedByName) {
  const MeasurementSet set = simulated(InstrumentKind::LaserTracker, 30, 11);
  // SA "Collection Group Target X Y Z" with // comments; the group is the configuration. The
  // export lists the readings in another order than the log (sorted by target), which a join
  // by name must not care about.
  std::string text = "// SA Version 2023.1\n// Working Frame: WORLD\n";
  for (int t = 0; t < 3; ++t)
    for (const PointMeasurement& m : set.points)
      if (m.target == t)
        text += fmt::format("A::Robot  {}   {}  {} {} {}\n", m.config, m.target + 1,
                            number(m.position_mm.x()), number(m.position_mm.y()),
                            number(m.position_mm.z()));
  ImportRequest request;
  request.export_file = {"sa.txt", text};
  request.joint_log = {"log.csv", joint_log(set, false)};
  request.format = parse_export_format(
      "delimiter: space\ncolumns: [collection, group, target, x, y, z]\nroles: {config: group}\n",
      "map.yaml");
  request.join = JoinBy::Name;
  const ImportResult result = import_measurements(request);
  EXPECT_EQ(result.measurements.points.front().line, 3);  // export lines are kept
  // The import keeps the export's order; the round trip compares against the same order.
  MeasurementSet sorted = set;
  std::stable_sort(
      sorted.points.begin(), sorted.points.end(),
      [](const PointMeasurement& a, const PointMeasurement& b) { return a.target < b.target; });
  expect_round_trip(result, sorted);
}

TEST(CampaignImport, SemicolonDecimalCommaMetresWithBomCrlfJoinedByOrder) {
  const MeasurementSet set = simulated(InstrumentKind::LaserTracker, 25, 12);
  // A European spreadsheet export: BOM, CRLF, ';' fields, decimal commas, metres in the header.
  std::string text = "\xEF\xBB\xBF# exported 24.11.2026\r\nName;X [m];Y [m];Z [m]\r\n";
  for (const PointMeasurement& m : set.points)
    text +=
        fmt::format("{};{};{};{}\r\n", m.target + 1, number(m.position_mm.x() / 1000, ','),
                    number(m.position_mm.y() / 1000, ','), number(m.position_mm.z() / 1000, ','));
  ImportRequest request;
  request.export_file = {"cam2.csv", text};
  request.joint_log = {"log.csv", joint_log(set, true)};
  const ImportResult result = import_measurements(request);
  expect_round_trip(result, set);
}

TEST(CampaignImport, TabSeparatedIsoTimestampsJoinedByTimeWithinTolerance) {
  const MeasurementSet set = simulated(InstrumentKind::LaserTracker, 20, 13);
  // "2026-11-24T21:mm:ss.fff" for `t` seconds after 21:00 (t < 3600).
  const auto iso = [](double t, char separator) {
    const int minutes = static_cast<int>(t / 60);
    return fmt::format("2026-11-24{}21:{:02d}:{:06.3f}", separator, minutes, t - 60.0 * minutes);
  };
  // Readings time-stamped by the tracker's clock, every 20 s; the log's clock differs by
  // -0.3, 0 or +0.3 s.
  std::string text = "Point Name\tX (mm)\tY (mm)\tZ (mm)\tTime Stamp\n";
  std::string log = "config\ttime\tj1\tj2\tj3\tj4\tj5\tj6\n";
  for (size_t i = 0; i < set.points.size(); ++i) {
    const PointMeasurement& m = set.points[i];
    const double t = 100.0 + 20.0 * static_cast<double>(i);
    text += fmt::format("{}\t{}\t{}\t{}\t{}\n", m.target + 1, number(m.position_mm.x()),
                        number(m.position_mm.y()), number(m.position_mm.z()), iso(t, 'T'));
    log += fmt::format("{}\t{}", m.config, iso(t + 0.3 * (static_cast<double>(i % 3) - 1.0), ' '));
    for (int j = 0; j < kJointCount; ++j) log += "\t" + number(rad2deg(m.joints[j]));
    log += "\n";
  }
  ImportRequest request;
  request.export_file = {"leica.txt", text};
  request.joint_log = {"log.tsv", log};
  request.join = JoinBy::Time;
  request.time_tolerance_s = 0.5;
  expect_round_trip(import_measurements(request), set);

  // With a tolerance below the clock offset the first offset reading is refused by line.
  request.time_tolerance_s = 0.1;
  try {
    import_measurements(request);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("leica.txt:2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no joint-log row within ±0.1 s"), std::string::npos)
        << e.what();
  }
}

TEST(CampaignImport, SeveralTargetsPerConfigurationJoinedByTime) {
  // The log has one row per configuration; the tracker reads two targets at each, a few
  // seconds apart. A second reading of the same target at one configuration is refused.
  const MeasurementSet set = simulated(InstrumentKind::LaserTracker, 8, 17);
  std::string log = "config,time,j1,j2,j3,j4,j5,j6\n";
  std::string text = "target,x,y,z,time\n";
  MeasurementSet expected = set;
  expected.points.clear();
  for (size_t i = 0; i < set.points.size(); ++i) {
    const PointMeasurement& m = set.points[i];
    log += fmt::format("{},{}", m.config, 60 * i);
    for (int j = 0; j < kJointCount; ++j) log += "," + number(rad2deg(m.joints[j]));
    log += "\n";
    for (int t = 0; t < 2; ++t) {
      PointMeasurement r = m;
      r.target = (m.target + t) % 3;
      r.position_mm += Eigen::Vector3d(t, 0, 0);  // another SMR, another point
      text += fmt::format("{},{},{},{},{}\n", r.target + 1, number(r.position_mm.x()),
                          number(r.position_mm.y()), number(r.position_mm.z()), 60 * i + 3 * t);
      expected.points.push_back(r);
    }
  }
  ImportRequest request;
  request.export_file = {"tracker.csv", text};
  request.joint_log = {"log.csv", log};
  request.join = JoinBy::Time;
  request.time_tolerance_s = 5;
  expect_round_trip(import_measurements(request), expected);
  // A second reading of the first configuration's first target, 1 s after it.
  request.export_file.text = text + fmt::format("{},1,2,3,1\n", set.points[0].target + 1);
  std::string e;
  try {
    import_measurements(request);
  } catch (const InputError& err) {
    e = err.what();
  }
  EXPECT_NE(e.find("(same target) are both nearest to log row log.csv:2"), std::string::npos) << e;
}

TEST(CampaignImport, OpticalCmmPosesWithFixedXyzAnglesJoinedByName) {
  const MeasurementSet set = simulated(InstrumentKind::OpticalCmm, 15, 14);
  ASSERT_EQ(set.kind, MeasurementKind::Poses);
  std::string text = "Pose,X,Y,Z,Rx,Ry,Rz\n";
  for (const PoseMeasurement& m : set.poses) {
    // Roll-pitch-yaw about the fixed axes: R = Rz(rz)·Ry(ry)·Rx(rx).
    const Eigen::Vector3d zyx = m.world_T_tcp.R.eulerAngles(2, 1, 0);
    text += fmt::format("{},{},{},{},{},{},{}\n", m.config, number(m.world_T_tcp.p.x()),
                        number(m.world_T_tcp.p.y()), number(m.world_T_tcp.p.z()),
                        number(rad2deg(zyx[2])), number(rad2deg(zyx[1])), number(rad2deg(zyx[0])));
  }
  ImportRequest request;
  request.export_file = {"ctrack.csv", text};
  request.joint_log = {"log.csv", joint_log(set, false)};
  request.join = JoinBy::Name;
  expect_round_trip(import_measurements(request), set);

  // The same file read with the other angle order gives other rotations: the convention matters.
  request.format.angle_order = AngleOrder::MobileXyz;
  const ImportResult other = import_measurements(request);
  double largest = 0;
  for (size_t i = 0; i < set.poses.size(); ++i)
    largest =
        std::max(largest, Eigen::AngleAxisd(other.measurements.poses[i].world_T_tcp.R.transpose() *
                                            set.poses[i].world_T_tcp.R)
                              .angle());
  EXPECT_GT(largest, 0.1);
}

TEST(CampaignImport, OpticalCmmPosesWithQuaternionsMappedByAFileWithoutHeader) {
  const MeasurementSet set = simulated(InstrumentKind::OpticalCmm, 12, 16);
  // No header, tab-separated, quaternion written x, y, z, w (scalar last), in metres.
  std::string text = "# C-Track export\n";
  for (const PoseMeasurement& m : set.poses) {
    const Eigen::Quaterniond q(m.world_T_tcp.R);
    text += fmt::format("{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\n", m.config,
                        number(m.world_T_tcp.p.x() / 1000), number(m.world_T_tcp.p.y() / 1000),
                        number(m.world_T_tcp.p.z() / 1000), number(q.x()), number(q.y()),
                        number(q.z()), number(q.w()));
  }
  ImportRequest request;
  request.export_file = {"ctrack.txt", text};
  request.joint_log = {"log.csv", joint_log(set, false)};
  request.format = parse_export_format(
      "columns: [pose, x, y, z, i, j, k, w]\nroles: {qx: i, qy: j, qz: k, qw: w}\nunit: m\n",
      "map.yaml");
  request.join = JoinBy::Name;
  expect_round_trip(import_measurements(request), set);
}

std::string error_of(const ImportRequest& request) {
  try {
    import_measurements(request);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(CampaignImport, TargetOptionOnlyWhenNoFileNamesTheTarget) {
  ImportRequest request;
  request.export_file = {"export.csv", "x,y,z\n400,0,500\n"};
  request.joint_log = {"log.csv", "config,j1,j2,j3,j4,j5,j6\nc1,0,10,20,0,30,0\n"};
  request.default_target = "T1";
  EXPECT_EQ(import_measurements(request).targets.targets.front().name, "T1");
  for (const char* bad : {"a,b", "a;b", "a\"b", "a\nb", " a", "a "}) {
    request.default_target = bad;
    EXPECT_EQ(error_of(request),
              fmt::format("--target: target name '{}': expected a name without blanks at its ends, "
                          "commas, semicolons, quotes or control characters (it is written into "
                          "the target column of the CSV)",
                          bad));
  }
  // The export names its targets: --target would be ignored, so it is refused.
  request.export_file = {"export.csv", "target,x,y,z\n1,400,0,500\n"};
  request.default_target = "T1";
  EXPECT_EQ(error_of(request),
            "--target: 'T1' would not be used: export.csv names the target of every reading (its "
            "target column); give --target only when neither file names it");
}

TEST(CampaignImport, MismatchedRowsAreRefusedNamingTheRows) {
  const MeasurementSet set = simulated(InstrumentKind::LaserTracker, 6, 15);
  std::string text = "target,x,y,z\n";
  for (const PointMeasurement& m : set.points)
    text += fmt::format("{},{},{},{}\n", m.target + 1, m.position_mm.x(), m.position_mm.y(),
                        m.position_mm.z());
  ImportRequest request;
  request.export_file = {"export.csv", text + "1,1,2,3\n"};
  request.joint_log = {"log.csv", joint_log(set, false)};
  // One reading too many: the extra one is named by its line (8: header + 6 + 1).
  std::string e = error_of(request);
  EXPECT_NE(e.find("7 readings"), std::string::npos) << e;
  EXPECT_NE(e.find("readings without a log row: export.csv:8"), std::string::npos) << e;

  // One log row too many, joined by name: the unmeasured row is named.
  std::string named = "config,target,x,y,z\n";
  for (size_t i = 0; i + 1 < set.points.size(); ++i) {
    const PointMeasurement& m = set.points[i];
    named += fmt::format("{},{},{},{},{}\n", m.config, m.target + 1, m.position_mm.x(),
                         m.position_mm.y(), m.position_mm.z());
  }
  request.export_file = {"export.csv", named};
  request.join = JoinBy::Name;
  e = error_of(request);
  EXPECT_NE(
      e.find("1 joint-log rows have no reading: log.csv:7 (" + set.points.back().config + ")"),
      std::string::npos)
      << e;
  request.allow_unmeasured = true;
  const ImportResult partial = import_measurements(request);
  EXPECT_EQ(partial.measurements.size(), set.points.size() - 1);
  ASSERT_EQ(partial.warnings.size(), 1u);

  // A configuration the log does not have.
  request.export_file = {"export.csv", named + "C99,1,1,2,3\n"};
  e = error_of(request);
  EXPECT_NE(e.find("export.csv:7"), std::string::npos) << e;
  EXPECT_NE(e.find("configuration 'C99' is not in the joint log log.csv"), std::string::npos) << e;

  // A malformed number: file, line and column.
  request.export_file = {"export.csv",
                         "config,target,x,y,z\n" + set.points[0].config + ",1,12.5,1.2.3,4\n"};
  e = error_of(request);
  EXPECT_NE(e.find("export.csv:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("'1.2.3' is not a number"), std::string::npos) << e;

  // A decimal point in a decimal-comma file.
  request.export_file = {"export.csv",
                         "config;target;x;y;z\n" + set.points[0].config + ";1;12,5;1.5;4,25\n"};
  e = error_of(request);
  EXPECT_NE(e.find("export.csv:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("decimal point"), std::string::npos) << e;

  // A bad joint value in the log.
  request.export_file = {"export.csv", named};
  std::string log = joint_log(set, false);
  log.replace(log.find('\n') + 1 + set.points[0].config.size() + 1, 1, "x");
  request.joint_log = {"log.csv", log};
  e = error_of(request);
  EXPECT_NE(e.find("log.csv:2:"), std::string::npos) << e;

  // An unknown key in the mapping file is located, with the key it is a typo of.
  EXPECT_REFUSED((void)parse_export_format("delimiter: tab\ncolumnz: [x, y, z]\n", "map.yaml"),
                 InputError,
                 "map.yaml:2:1 (columnz): unknown key 'columnz': did you mean 'columns'? (expected "
                 "one of: delimiter, decimal, header, columns, roles, unit, angles)");
  EXPECT_REFUSED((void)parse_export_format("angles: {unit: deg, ordre: fixed-xyz}\n", "map.yaml"),
                 InputError,
                 "map.yaml:1:21 (angles.ordre): unknown key 'ordre': did you mean 'order'?");
}

// The plan's conditions (issue 19, docs/method/05-observability.md §7): 80 configurations
// planned with each joint's side (drawn) and a payload each (the tool's own, none, a 6 kg
// gripper), measured on the published IRB 120 with the simulator's backlash as the program moves
// them (σ = 0.01 mm). The export joined with the log by order and with the plan (listed in the
// reverse order) by the log's configuration names: every imported row carries its
// configuration's sides and payload, read back by the measurement reader, and the calibration
// with the backlash group on the imported rows recovers each dead band within 3σ; imported
// without the plan every row is from below and the dead bands cannot be told from the offsets.
TEST(CampaignImport, PlanGivesEachRowItsApproachAndPayload) {
  const Tool tool = test::tool_with_payloads();
  TrueRobot truth = published_irb120_truth(load_robot("abb-irb120"), tool);
  truth.effects.backlash = true;
  const VirtualInstrument tracker = standard_instrument(InstrumentKind::LaserTracker, truth, 0.01);
  std::mt19937_64 rng(2131);
  RandomConfigurationOptions options;
  options.box = published_joint_box(truth.robot.model);
  std::vector<PlannedConfiguration> configs =
      random_configurations(truth, tracker, 80, rng, options);
  for (size_t k = 0; k < configs.size(); ++k) {
    for (int j = 0; j < kJointCount; ++j) configs[k].approach[j] = rng() % 2 ? 1.0 : -1.0;
    configs[k].payload = static_cast<int>(k % 3) - 1;
  }
  const MeasurementSet set = simulate_measurements(truth, tracker, configs, rng).measurements;
  ASSERT_GT(set.size(), 70u);
  std::string text = "target,x,y,z\n";
  for (const PointMeasurement& m : set.points)
    text += fmt::format("{},{},{},{}\n", m.target + 1, number(m.position_mm.x()),
                        number(m.position_mm.y()), number(m.position_mm.z()));
  ImportRequest request;
  request.export_file = {"export.csv", text};
  request.joint_log = {"log.csv", joint_log(set, true)};
  const std::vector<PlannedConfiguration> reversed(configs.rbegin(), configs.rend());
  request.plan = NamedText{"plan.csv", write_configurations_csv(reversed, tool)};
  const ImportResult result = import_measurements(request);
  const MeasurementSet back = parse_measurements_csv(result.csv, "imported.csv", tool).measurements;
  ASSERT_EQ(back.size(), set.size());
  for (size_t i = 0; i < set.size(); ++i) {
    EXPECT_EQ(back.points[i].approach, set.points[i].approach) << set.points[i].config;
    EXPECT_EQ(back.points[i].payload, set.points[i].payload) << set.points[i].config;
    const int imported = result.measurements.points[i].payload;
    EXPECT_EQ(imported < 0 ? "" : result.targets.payloads[static_cast<size_t>(imported)].name,
              set.points[i].payload < 0
                  ? ""
                  : tool.payloads[static_cast<size_t>(set.points[i].payload)].name);
  }

  IdentifyOptions identify;
  identify.level = CalibrationLevel::Full;
  identify.identify = {"backlash"};
  const IdentificationResult with_plan = calibrate(load_robot("abb-irb120"), tool, back, identify);
  test::expect_dead_bands_recovered(with_plan, truth, 2131);

  request.plan.reset();
  const MeasurementSet from_below =
      parse_measurements_csv(import_measurements(request).csv, "imported.csv", tool).measurements;
  const IdentificationResult without =
      calibrate(load_robot("abb-irb120"), tool, from_below, identify);
  for (int joint = 1; joint <= kJointCount; ++joint)
    EXPECT_NE(without.robot.status[static_cast<size_t>(backlash_param(joint))],
              ParameterStatus::Identified)
        << joint;
}

// A log configuration the plan does not list is refused naming the log row, the plan and the
// flag; a bad cell of the plan at its file:line:column.
TEST(CampaignImport, PlanLackingALogConfigurationIsRefused) {
  ImportRequest request;
  request.export_file = {"export.csv", "x,y,z\n400,0,500\n410,0,500\n"};
  request.joint_log = {"log.csv",
                       "config,j1,j2,j3,j4,j5,j6\nc1,0,10,20,0,30,0\nc2,5,10,20,0,30,0\n"};
  request.default_target = "1";
  const std::string header = "config,target,j1,j2,j3,j4,j5,j6,approach\n";
  request.plan = NamedText{"plan.csv", header + "c1,,0,10,20,0,30,0,+-++++\n"};
  EXPECT_EQ(error_of(request),
            "log.csv:3 (config): configuration 'c2' is not in the plan plan.csv (--configs): the "
            "joint log is of another measurement program");
  request.plan =
      NamedText{"plan.csv", header + "c1,,0,10,20,0,30,0,+-++++\nc2,,5,10,20,0,30,0,+x\n"};
  EXPECT_NE(error_of(request).find("plan.csv:3:"), std::string::npos) << error_of(request);
  EXPECT_NE(error_of(request).find("(approach): '+x'"), std::string::npos);
  request.plan =
      NamedText{"plan.csv", header + "c1,,0,10,20,0,30,0,+-++++\nc2,,5,10,20,0,30,0,++++++\n"};
  const ImportResult r = import_measurements(request);
  Vector6d sides = Vector6d::Ones();
  sides[1] = -1;
  EXPECT_EQ(r.measurements.points[0].approach, sides);
  EXPECT_EQ(r.measurements.points[1].approach, Vector6d::Ones());
}

TEST(CampaignImport, AGrowingExportGivesItsCompleteLinesOnly) {
  ExportFormat format;  // a header line
  EXPECT_TRUE(read_export_points({"live.csv", ""}, format).empty());
  EXPECT_TRUE(read_export_points({"live.csv", "// started\nname;x;y;z\n"}, format).empty());
  EXPECT_TRUE(read_export_points({"live.csv", "name;x;y;z\nP1;1,5;2;3"}, format).empty());
  const auto points = read_export_points({"live.csv", "name;x;y;z\nP1;1,5;2;3\nP2;4;5"}, format);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0], Eigen::Vector3d(1.5, 2, 3));
  EXPECT_REFUSED(read_export_points({"live.csv", "name;x;y;z\nP1;1,5;2;x3\n"}, format), InputError,
                 "live.csv:2:10 (z): 'x3' is not a number");
}

TEST(CampaignImport, DialectDetection) {
  const auto dialect = [](const std::string& text) { return read_text_table(text, "f").dialect; };
  EXPECT_EQ(dialect("a,b,c\n1.5,2,3\n").delimiter, ',');
  EXPECT_EQ(dialect("a,b,c\n1.5,2,3\n").decimal, '.');
  EXPECT_EQ(dialect("a;b;c\n1,5;2;3\n").delimiter, ';');
  EXPECT_EQ(dialect("a;b;c\n1,5;2;3\n").decimal, ',');
  EXPECT_EQ(dialect("a\tb\n1,5\t2\n").delimiter, '\t');
  // Blank-separated with decimal commas: a comma split would leave blanks inside fields.
  EXPECT_EQ(dialect("P1 1,5 2,5 3,5\nP2 1,5 2,5 3,5\n").delimiter, ' ');
  EXPECT_EQ(dialect("P1 1,5 2,5 3,5\nP2 1,5 2,5 3,5\n").decimal, ',');
  // Quoted names with blanks in a blank-separated file.
  const TextTable quoted = read_text_table("\"Target A\" 1 2 3\n\"Target B\" 4 5 6\n", "f");
  ASSERT_EQ(quoted.rows[1].fields.size(), 4u);
  EXPECT_EQ(quoted.rows[1].fields[0], "Target B");
  EXPECT_EQ(parse_time_seconds("1970-01-02T00:00:01.5", '.', {}), 86401.5);
  EXPECT_EQ(parse_time_seconds("01:02:03,25", ',', {}), 3723.25);
}

}  // namespace
}  // namespace robcal::campaign
