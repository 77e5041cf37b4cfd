// Measurement CSV files: the three kinds, columns in any order, warnings for extra columns,
// every kind of bad input (with file, line and column in the message), and writer round trips.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

Tool three_target_tool() {
  Tool tool;
  tool.targets = {
      {"A", {0, 0, 125}, true}, {"B", {75, 93.675, 215}, true}, {"C", {150, 0, 125}, true}};
  return tool;
}

/// The message of the InputError that parsing `text` throws ("" if none).
std::string error_of(const std::string& text, const std::vector<MeasurementKind>& accepted = {}) {
  try {
    (void)parse_measurements_csv(text, "m.csv", three_target_tool(), accepted);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

constexpr const char* kPointsHeader = "config,target,j1,j2,j3,j4,j5,j6,x,y,z\n";

TEST(MeasurementFile, ReadsPointsWithCommentsBlankLinesAndDegrees) {
  const std::string text = std::string("# tracker export\n\n") + kPointsHeader +
                           "c1,A,10,-20,30,0,90,-180,100.5,-2,3e2\n"
                           "  # a comment in the middle\n"
                           "c1,B,10,-20,30,0,90,-180,101,2,300\n"
                           "c2,C,0,0,0,0,0,0,1,2,3\n";
  const MeasurementFile file = parse_measurements_csv(text, "m.csv", three_target_tool());
  EXPECT_TRUE(file.warnings.empty());
  const MeasurementSet& set = file.measurements;
  ASSERT_EQ(set.kind, MeasurementKind::Points);
  ASSERT_EQ(set.size(), 3u);
  EXPECT_EQ(set.file, "m.csv");
  EXPECT_EQ(set.points[0].config, "c1");
  EXPECT_EQ(set.points[0].target, 0);
  EXPECT_EQ(set.points[1].target, 1);
  EXPECT_EQ(set.points[2].target, 2);
  EXPECT_EQ(set.points[0].line, 4);
  EXPECT_EQ(set.points[1].line, 6);
  EXPECT_DOUBLE_EQ(set.points[0].joints[0], std::numbers::pi / 18);
  EXPECT_DOUBLE_EQ(set.points[0].joints[1], -std::numbers::pi / 9);
  EXPECT_DOUBLE_EQ(set.points[0].joints[4], std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(set.points[0].joints[5], -std::numbers::pi);
  EXPECT_EQ(set.points[0].position_mm, Eigen::Vector3d(100.5, -2, 300));
  EXPECT_EQ(set.residuals_per_row(), 3);
}

TEST(MeasurementFile, ColumnsInAnyOrderAndExtraColumnsWarn) {
  const std::string text =
      "Z,y,x,j6,j5,j4,j3,j2,j1,target,humidity,config\n"
      "3,2,1,60,50,40,30,20,10,C,21.5,k7\n";
  const MeasurementFile file = parse_measurements_csv(text, "m.csv", three_target_tool());
  ASSERT_EQ(file.measurements.points.size(), 1u);
  const PointMeasurement& m = file.measurements.points[0];
  EXPECT_EQ(m.config, "k7");
  EXPECT_EQ(m.target, 2);
  EXPECT_EQ(m.position_mm, Eigen::Vector3d(1, 2, 3));
  for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(m.joints[i], deg2rad(10.0 * (i + 1)));
  ASSERT_EQ(file.warnings.size(), 1u);
  EXPECT_EQ(file.warnings[0],
            "m.csv:1:11: column 'humidity' is not used by a points file; ignored");
}

TEST(MeasurementFile, ReadsPosesAndNormalisesQuaternions) {
  // 90° about z, written to 6 decimals (norm 1 − 3e-7).
  const std::string text =
      "config,j1,j2,j3,j4,j5,j6,x,y,z,qw,qx,qy,qz\n"
      "p1,0,10,20,30,40,50,400,0,500,0.707107,0,0,0.707107\n"
      "p2,0,0,0,0,0,0,1,2,3,1,0,0,0\n";
  const MeasurementFile file = parse_measurements_csv(text, "p.csv", three_target_tool());
  const MeasurementSet& set = file.measurements;
  ASSERT_EQ(set.kind, MeasurementKind::Poses);
  ASSERT_EQ(set.poses.size(), 2u);
  EXPECT_EQ(set.residuals_per_row(), 6);
  Eigen::Matrix3d expected;
  expected << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_LT((set.poses[0].world_T_tcp.R - expected).norm(), 1e-12);
  EXPECT_EQ(set.poses[0].world_T_tcp.p, Eigen::Vector3d(400, 0, 500));
  EXPECT_TRUE(set.poses[1].world_T_tcp.R.isIdentity(0.0));
}

TEST(MeasurementFile, ReadsDistances) {
  const std::string text =
      "config,target,j1,j2,j3,j4,j5,j6,length\n"
      "b1,A,0,0,0,0,0,0,300.0125\n"
      "b1,B,0,0,0,0,0,0,299.5\n";
  const MeasurementSet set =
      parse_measurements_csv(text, "d.csv", three_target_tool()).measurements;
  ASSERT_EQ(set.kind, MeasurementKind::Distances);
  ASSERT_EQ(set.distances.size(), 2u);
  EXPECT_EQ(set.distances[0].length_mm, 300.0125);
  EXPECT_EQ(set.distances[1].target, 1);
  EXPECT_EQ(set.residuals_per_row(), 1);
}

TEST(MeasurementFile, ReadsTheReferenceValidationSet) {
  const Tool tool = load_tool(test::data_path("irb120-published/tool.yaml"));
  const MeasurementFile file =
      read_measurements_csv(test::data_path("irb120-published/validation.csv"), tool);
  const test::CsvTable table = test::read_csv(test::data_path("irb120-published/validation.csv"));
  ASSERT_EQ(file.measurements.points.size(), table.rows.size());
  for (size_t r = 0; r < table.rows.size(); r += 97) {
    const PointMeasurement& m = file.measurements.points[r];
    EXPECT_EQ(m.position_mm.x(), table.at(r, "x"));
    EXPECT_EQ(m.joints[2], deg2rad(table.at(r, "j3")));
    EXPECT_EQ(tool.targets[static_cast<size_t>(m.target)].name,
              std::to_string(static_cast<int>(table.at(r, "target"))));
  }
}

// ---- errors: each names the file, line and column and says what was expected ----

TEST(MeasurementFileErrors, EmptyFile) {
  EXPECT_EQ(error_of(""),
            "m.csv: empty measurement file: expected a header row such as "
            "'config,target,j1,j2,j3,j4,j5,j6,x,y,z'");
  EXPECT_EQ(error_of("# only comments\n\n"), error_of(""));
}

TEST(MeasurementFileErrors, HeaderWithoutRows) {
  EXPECT_EQ(error_of(std::string("# c\n") + kPointsHeader),
            "m.csv:2: no measurement rows after the header: expected at least one row");
}

TEST(MeasurementFileErrors, MissingColumnNamesItAndTheNeededSet) {
  EXPECT_EQ(error_of("config,target,j1,j2,j3,j4,j5,x,y,z\nc,A,0,0,0,0,0,0,0,0\n"),
            "m.csv:1 (j6): missing column 'j6': a points file needs the columns "
            "config,target,j1,j2,j3,j4,j5,j6,x,y,z");
  EXPECT_EQ(error_of("config,j1,j2,j3,j4,j5,j6,x,y,z,qw,qx,qy\n"),
            "m.csv:1 (qz): missing column 'qz': a poses file needs the columns "
            "config,j1,j2,j3,j4,j5,j6,x,y,z,qw,qx,qy,qz");
}

TEST(MeasurementFileErrors, UnknownKindAndDuplicateColumn) {
  EXPECT_NE(error_of("config,target,j1\nc,A,0\n").find("m.csv:1: cannot tell the kind"),
            std::string::npos);
  EXPECT_EQ(error_of("config,target,j1,j2,j3,j4,j5,j6,x,y,z,x\n"),
            "m.csv:1:12 (x): column 'x' appears twice in the header");
}

TEST(MeasurementFileErrors, UnknownTargetListsTheKnownOnes) {
  EXPECT_EQ(
      error_of(std::string(kPointsHeader) + "c1,A,0,0,0,0,0,0,1,2,3\nc2,D,0,0,0,0,0,0,1,2,3\n"),
      "m.csv:3:2 (target): unknown target 'D': the tool has 'A', 'B', 'C'");
}

TEST(MeasurementFileErrors, NonNumericNamesLineColumnAndUnit) {
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,0,0,0,1O,0,0,1,2,3\n"),
            "m.csv:2:6 (j4): '1O' is not a number: expected a finite number (degrees)");
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,0,0,0,0,0,0,1,,3\n"),
            "m.csv:2:10 (y): empty field: expected a finite number (mm)");
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,0,0,0,0,0,0,1,2,3 mm\n"),
            "m.csv:2:11 (z): '3 mm' is not a number: expected a finite number (mm)");
}

TEST(MeasurementFileErrors, NanAndInfinity) {
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,0,0,0,0,0,0,nan,2,3\n"),
            "m.csv:2:9 (x): 'nan' is not finite: expected a finite number (mm)");
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,0,-inf,0,0,0,0,1,2,3\n"),
            "m.csv:2:4 (j2): '-inf' is not finite: expected a finite number (degrees)");
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,0,0,0,0,0,0,1,2,1e999\n"),
            "m.csv:2:11 (z): '1e999' is not finite: expected a finite number (mm)");
}

// The plausible ranges of the header (±100 m, ±720°) in the file's declared units, the bounds
// themselves accepted.
TEST(MeasurementFileErrors, ImplausibleValuesNameTheRangeInTheFilesUnit) {
  const std::string tail =
      ": a typo or a unit slip? (declare the units with '# units: m, rad' or --units if they are "
      "not mm and degrees)";
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,0,0,0,0,0,0,1e300,2,3\n"),
            "m.csv:2:9 (x): 1e300 is outside the plausible range [-100000, 100000] mm" + tail);
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,0,0,0,0,0,0,1,-100000.5,3\n"),
            "m.csv:2:10 (y): -100000.5 is outside the plausible range [-100000, 100000] mm" + tail);
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,0,0,0,0,0,721,1,2,3\n"),
            "m.csv:2:8 (j6): 721 is outside the plausible range [-720, 720] degrees" + tail);
  EXPECT_EQ(
      error_of("# units: m, rad\n" + std::string(kPointsHeader) + "c1,A,0,13,0,0,0,0,1,2,3\n"),
      "m.csv:3:4 (j2): 13 is outside the plausible range [-12.5664, 12.5664] rad" + tail);
  EXPECT_EQ(error_of("# units: m\n" + std::string(kPointsHeader) + "c1,A,0,0,0,0,0,0,1,2,101\n"),
            "m.csv:3:11 (z): 101 is outside the plausible range [-100, 100] m" + tail);
  EXPECT_EQ(error_of("config,target,j1,j2,j3,j4,j5,j6,length\nb,A,0,0,0,0,0,0,2e5\n"),
            "m.csv:2:9 (length): length 2e5 is outside the plausible range (0, 100000] mm: "
            "expected a distance above 0");
  EXPECT_EQ(error_of("config,j1,j2,j3,j4,j5,j6,x,y,z,a,b,c\np,0,0,0,0,0,0,0,0,0,0,900,0\n"),
            "m.csv:2:12 (b): 900 is outside the plausible range [-720, 720] degrees" + tail);
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,720,-720,0,0,0,0,100000,-100000,3\n"), "");
}

TEST(MeasurementFileErrors, DuplicateRowsNameBothLines) {
  EXPECT_EQ(error_of(std::string(kPointsHeader) +
                     "c1,A,0,0,0,0,0,0,1,2,3\nc1,B,0,0,0,0,0,0,1,2,3\nc1,A,0,0,0,0,0,0,1,2,3\n"),
            "m.csv:4:1 (config): duplicate row: config 'c1' with target 'A' already on line 2");
  EXPECT_EQ(error_of("config,j1,j2,j3,j4,j5,j6,x,y,z,qw,qx,qy,qz\n"
                     "p,0,0,0,0,0,0,0,0,0,1,0,0,0\np,0,0,0,0,0,0,0,0,0,1,0,0,0\n"),
            "m.csv:3:1 (config): duplicate row: config 'p' already on line 2");
}

TEST(MeasurementFileErrors, WrongFieldCount) {
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,0,0,0,0,0,0,1,2\n"),
            "m.csv:2: expected 11 comma-separated fields as in the header (line 1), got 10");
  EXPECT_EQ(error_of(std::string(kPointsHeader) + "c1,A,0,0,0,0,0,0,1,2,3,4\n"),
            "m.csv:2: expected 11 comma-separated fields as in the header (line 1), got 12");
}

TEST(MeasurementFileErrors, NonUnitQuaternion) {
  EXPECT_EQ(error_of("config,j1,j2,j3,j4,j5,j6,x,y,z,qw,qx,qy,qz\n"
                     "p,0,0,0,0,0,0,0,0,0,1,0,0.1,0\n"),
            "m.csv:2:11 (qw,qx,qy,qz): quaternion (1, 0, 0.1, 0) has norm 1.004987562: expected "
            "a unit quaternion (within 1e-05)");
}

TEST(MeasurementFileErrors, NonPositiveLengthAndEmptyConfig) {
  EXPECT_EQ(error_of("config,target,j1,j2,j3,j4,j5,j6,length\nb,A,0,0,0,0,0,0,-1\n"),
            "m.csv:2:9 (length): length -1 is outside the plausible range (0, 100000] mm: "
            "expected a distance above 0");
  EXPECT_EQ(error_of("config,target,j1,j2,j3,j4,j5,j6,length\nb,A,0,0,0,0,0,0,0\n"),
            "m.csv:2:9 (length): length 0 is outside the plausible range (0, 100000] mm: "
            "expected a distance above 0");
  EXPECT_EQ(error_of(std::string(kPointsHeader) + ",A,0,0,0,0,0,0,1,2,3\n"),
            "m.csv:2:1 (config): empty config: expected a name");
}

TEST(MeasurementFileErrors, WrongKindForTheCommand) {
  EXPECT_EQ(error_of("config,target,j1,j2,j3,j4,j5,j6,length\nb,A,0,0,0,0,0,0,1\n",
                     {MeasurementKind::Points, MeasurementKind::Poses}),
            "m.csv:1: this is a distances file (by its columns); this command takes points or "
            "poses files");
  EXPECT_EQ(
      error_of(std::string(kPointsHeader) + "c1,A,0,0,0,0,0,0,1,2,3\n", {MeasurementKind::Points}),
      "");
}

TEST(MeasurementFileErrors, UnreadableFileIsNamed) {
  try {
    (void)read_measurements_csv("/nonexistent/robcal/val.csv", three_target_tool());
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/robcal/val.csv"), std::string::npos);
  }
}

// ---- writer ----

MeasurementSet random_set(MeasurementKind kind, int rows, uint64_t seed) {
  auto rng = test::seeded_rng(seed);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), coord(-1500.0, 1500.0);
  MeasurementSet set;
  set.kind = kind;
  for (int r = 0; r < rows; ++r) {
    Vector6d q;
    for (int i = 0; i < 6; ++i) q[i] = angle(rng);
    const std::string config = "cfg" + std::to_string(r / 3);
    if (kind == MeasurementKind::Points) {
      set.points.push_back({config, r % 3, q, {coord(rng), coord(rng), coord(rng)}, 0});
    } else if (kind == MeasurementKind::Distances) {
      set.distances.push_back({config, r % 3, q, std::abs(coord(rng)), 0});
    } else {
      PoseMeasurement m;
      m.config = "cfg" + std::to_string(r);
      m.joints = q;
      m.world_T_tcp.R =
          Eigen::Quaterniond(
              Eigen::Vector4d(angle(rng), angle(rng), angle(rng), angle(rng)).normalized())
              .toRotationMatrix();
      m.world_T_tcp.p = {coord(rng), coord(rng), coord(rng)};
      set.poses.push_back(m);
    }
  }
  return set;
}

TEST(MeasurementFileWriter, RoundTripsEveryKind) {
  const Tool tool = three_target_tool();
  for (MeasurementKind kind :
       {MeasurementKind::Points, MeasurementKind::Poses, MeasurementKind::Distances}) {
    SCOPED_TRACE(std::string(measurement_kind_name(kind)));
    const MeasurementSet set = random_set(kind, 30, 7);
    const std::string text = write_measurements_csv(set, tool, "simulated\nseed 7");
    EXPECT_EQ(text.rfind("# simulated\n# seed 7\nconfig,", 0), 0u);
    const MeasurementFile back = parse_measurements_csv(text, "w.csv", tool);
    EXPECT_TRUE(back.warnings.empty());
    ASSERT_EQ(back.measurements.kind, kind);
    ASSERT_EQ(back.measurements.size(), set.size());
    for (size_t r = 0; r < set.size(); ++r) {
      const auto check_joints = [](const Vector6d& a, const Vector6d& b) {
        // Degrees in the file: deg→rad→deg costs at most an ulp or two.
        for (int i = 0; i < 6; ++i) EXPECT_NEAR(a[i], b[i], 4e-16 * std::abs(b[i]) + 1e-300);
      };
      switch (kind) {
        case MeasurementKind::Points:
          EXPECT_EQ(back.measurements.points[r].config, set.points[r].config);
          EXPECT_EQ(back.measurements.points[r].target, set.points[r].target);
          EXPECT_EQ(back.measurements.points[r].position_mm, set.points[r].position_mm);
          check_joints(back.measurements.points[r].joints, set.points[r].joints);
          break;
        case MeasurementKind::Poses:
          EXPECT_EQ(back.measurements.poses[r].world_T_tcp.p, set.poses[r].world_T_tcp.p);
          EXPECT_LT((back.measurements.poses[r].world_T_tcp.R - set.poses[r].world_T_tcp.R).norm(),
                    4e-15);  // matrix → quaternion → matrix: a few ulps
          check_joints(back.measurements.poses[r].joints, set.poses[r].joints);
          break;
        case MeasurementKind::Distances:
          EXPECT_EQ(back.measurements.distances[r].length_mm, set.distances[r].length_mm);
          EXPECT_EQ(back.measurements.distances[r].target, set.distances[r].target);
          check_joints(back.measurements.distances[r].joints, set.distances[r].joints);
          break;
      }
    }
    // What was read once is a fixed point: written and read again it is bit-identical.
    const MeasurementSet again =
        parse_measurements_csv(write_measurements_csv(back.measurements, tool), "w2.csv", tool)
            .measurements;
    for (size_t r = 0; r < set.size(); ++r) {
      const Vector6d& q1 = kind == MeasurementKind::Points  ? back.measurements.points[r].joints
                           : kind == MeasurementKind::Poses ? back.measurements.poses[r].joints
                                                            : back.measurements.distances[r].joints;
      const Vector6d& q2 = kind == MeasurementKind::Points  ? again.points[r].joints
                           : kind == MeasurementKind::Poses ? again.poses[r].joints
                                                            : again.distances[r].joints;
      EXPECT_EQ(q1, q2);
    }
  }
}

TEST(MeasurementFileWriter, RefusesLabelsThatCsvCannotHold) {
  MeasurementSet set = random_set(MeasurementKind::Points, 1, 1);
  set.points[0].config = "a,b";
  EXPECT_REFUSED((void)write_measurements_csv(set, three_target_tool()), InputError,
                 "config: configuration label 'a,b' cannot be written to CSV");
  set.points[0].config = "ok";
  set.points[0].target = 5;
  EXPECT_REFUSED((void)write_measurements_csv(set, three_target_tool()), InputError,
                 "target: target index 5 is not a target of the tool (3 targets)");
}

}  // namespace
}  // namespace robcal
