// Re-identification of a calibrated robot (`calibrate --model`, issue 13 item 5): a new tool
// point, a new TCP frame, a moved base, each recovered within 3σ of the simulated truth while
// every other value stays the calibrated one; the written model keeps the calibration's
// statistics and provenance and records what was re-identified; requests the data cannot meet
// are refused with their reason.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <filesystem>

#include "robcal/core/units.hpp"
#include "robcal/identify/calibration_output.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

constexpr double kNoiseMm = 0.02;

/// A robot calibrated perfectly (its parameters are the truth's): what is tested is the
/// re-identification alone, not the calibration's own error.
CalibratedRobot calibrated_robot(std::mt19937_64& rng) {
  const RobotModel model = load_robot("abb-irb120");
  CalibratedRobot robot =
      CalibratedRobot::nominal(model, load_tool(test::data_path("irb120-published/tool.yaml")));
  std::normal_distribution<double> n(0.0, 1.0);
  robot.params.head<6>() << 1650, -420, -310, deg2rad(0.3), deg2rad(-0.2), deg2rad(-57);
  for (int i = kLinkParamOffset; i < kComplianceOffset; ++i) {
    robot.params[i] +=
        parameter_table()[i].kind == ParamKind::Angle ? deg2rad(0.05 * n(rng)) : 0.2 * n(rng);
    robot.status[static_cast<size_t>(i)] = ParameterStatus::Identified;
  }
  robot.covariance = 1e-6 * Eigen::MatrixXd::Identity(kParameterCount, kParameterCount);
  robot.level = "kinematic";
  robot.base_fitted = true;
  robot.statistics = "rms_mm: 0.0215\nprovenance:\n  date_utc: 2026-11-01T10:00:00Z\n";
  return robot;
}

/// Configurations in the middle 60 % of every joint's range.
std::vector<Vector6d> configurations(const RobotModel& model, int count, std::mt19937_64& rng) {
  Vector6d lower, upper;
  for (int j = 0; j < kJointCount; ++j) {
    const JointLimit& l = model.limits[static_cast<size_t>(j)];
    lower[j] = l.lower + 0.2 * (l.upper - l.lower);
    upper[j] = l.upper - 0.2 * (l.upper - l.lower);
  }
  return sample_configurations(lower, upper, count, rng);
}

/// Points of `target_mm` (flange frame) measured on the robot with parameters `truth`.
MeasurementSet points(const CalibratedRobot& robot, const ParameterVector& truth,
                      const Eigen::Vector3d& target_mm, int target, int count,
                      std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, kNoiseMm);
  MeasurementSet data;
  data.file = "points.csv";
  for (const Vector6d& q : configurations(robot.model, count, rng)) {
    const Eigen::Vector3d p = flange_pose(robot.model, robot.tool.payload, truth, q) * target_mm;
    data.points.push_back({"C" + std::to_string(data.points.size() + 1), target, q,
                           p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)),
                           static_cast<int>(data.points.size()) + 2});
  }
  return data;
}

CalibrationRequest request(CalibrationLevel level, std::vector<std::string> identify = {}) {
  CalibrationRequest r;
  r.options.level = level;
  r.options.identify = std::move(identify);
  r.options.prediction_configurations = 50;
  return r;
}

const UnknownEstimate& unknown(const IdentificationResult& r, const std::string& name) {
  for (const UnknownEstimate& u : r.unknowns)
    if (u.name == name) return u;
  throw std::runtime_error("no unknown " + name);
}

void expect_rest_kept(const CalibratedRobot& start, const CalibratedRobot& after,
                      const std::vector<int>& changed) {
  for (int i = 0; i < kParameterCount; ++i) {
    if (std::find(changed.begin(), changed.end(), i) != changed.end()) continue;
    EXPECT_EQ(after.params[i], start.params[i]) << parameter_table()[i].name;
    EXPECT_EQ(after.status[static_cast<size_t>(i)], start.status[static_cast<size_t>(i)]);
  }
  EXPECT_EQ(after.level, start.level);
  EXPECT_EQ(after.statistics, start.statistics);
}

TEST(Reidentify, NewToolPointWithin3SigmaRestKept) {
  auto rng = test::seeded_rng(13);
  const CalibratedRobot start = calibrated_robot(rng);
  const Eigen::Vector3d truth_point(31.5, -22.25, 141.0);
  Tool tool;
  tool.payload = start.tool.payload;
  tool.targets = {{"N", Eigen::Vector3d(30, -20, 140), true}};  // the drawing's coordinates
  const MeasurementSet data = points(start, start.params, truth_point, 0, 12, rng);
  const CalibrationRun run = reidentify(start, tool, data, request(CalibrationLevel::Tool));
  const IdentificationResult& r = run.result;
  ASSERT_TRUE(r.reidentification);
  EXPECT_EQ(r.reidentification->what, "tool");
  ASSERT_EQ(r.reidentification->values.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const ReidentifiedValue& v = r.reidentification->values[static_cast<size_t>(k)];
    EXPECT_EQ(v.name, std::string("target.N.") + "xyz"[k]);
    EXPECT_EQ(v.before, Eigen::Vector3d(30, -20, 140)[k]);
    // 12 points of σ 0.02 mm per axis: σ of a coordinate ≈ 0.02/√12 ≈ 0.006 mm.
    EXPECT_GT(v.std_dev, 0.002);
    EXPECT_LT(v.std_dev, 0.02);
    EXPECT_LT(std::abs(v.value - truth_point[k]), 3 * v.std_dev) << v.name;
  }
  EXPECT_LT((r.robot.tool.targets[0].position_mm - truth_point).norm(), 0.05);
  expect_rest_kept(start, r.robot, {});
  EXPECT_TRUE(run.problems.empty());

  // Round trip of the written model: the new tool, the calibration's statistics and provenance
  // kept, the re-identification recorded; a second one (a moved base) adds a second record.
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "reidentified.yaml";
  write_file_atomically(path, calibrated_model_file(run, nullptr));
  const CalibratedRobot back = load_calibrated_robot(path.string());
  for (int i = 0; i < kParameterCount; ++i)
    EXPECT_NEAR(back.params[i], start.params[i], 1e-12 * std::max(1.0, std::abs(start.params[i])));
  ASSERT_EQ(back.tool.targets.size(), 1u);
  EXPECT_LT((back.tool.targets[0].position_mm - r.robot.tool.targets[0].position_mm).norm(), 1e-9);
  EXPECT_NE(back.statistics.find("date_utc: 2026-11-01T10:00:00Z"), std::string::npos);
  ASSERT_EQ(back.reidentified.size(), 1u);
  EXPECT_NE(back.reidentified[0].find("what: tool"), std::string::npos) << back.reidentified[0];
  EXPECT_NE(back.reidentified[0].find("target.N.x"), std::string::npos);
  const MeasurementSet again = points(back, back.params, truth_point, 0, 12, rng);
  const CalibrationRun base =
      reidentify(back, std::nullopt, again, request(CalibrationLevel::Base));
  write_file_atomically(path, calibrated_model_file(base, nullptr));
  const CalibratedRobot twice = load_calibrated_robot(path.string());
  ASSERT_EQ(twice.reidentified.size(), 2u);
  EXPECT_NE(twice.reidentified[1].find("what: base"), std::string::npos);
  std::filesystem::remove(path);
}

TEST(Reidentify, MovedBaseWithin3SigmaRestKept) {
  auto rng = test::seeded_rng(14);
  const CalibratedRobot start = calibrated_robot(rng);
  ParameterVector moved = start.params;
  moved.head<6>() +=
      (Vector6d() << 12, -7, 3, deg2rad(0.05), deg2rad(-0.03), deg2rad(0.5)).finished();
  const MeasurementSet data = points(start, moved, start.tool.targets[0].position_mm, 0, 20, rng);
  const CalibrationRun run = reidentify(start, std::nullopt, data, request(CalibrationLevel::Base));
  const IdentificationResult& r = run.result;
  ASSERT_EQ(r.free.size(), 6u);
  for (int i = 0; i < kBaseParamCount; ++i) {
    const UnknownEstimate& u = r.unknowns[static_cast<size_t>(i)];
    const double truth = moved[i] * parameter_table()[i].to_external();
    EXPECT_GT(u.std_dev, 0);
    EXPECT_LT(std::abs(u.value - truth), 3 * u.std_dev) << u.name;
    EXPECT_EQ(r.robot.status[static_cast<size_t>(i)], ParameterStatus::Identified);
    EXPECT_GT(r.robot.covariance(i, i), 0);
  }
  expect_rest_kept(start, r.robot, {0, 1, 2, 3, 4, 5});
}

TEST(Reidentify, NewTcpFrameFromPoses) {
  auto rng = test::seeded_rng(15);
  const CalibratedRobot start = calibrated_robot(rng);
  Eigen::Isometry3d truth_tcp = Eigen::Isometry3d::Identity();
  truth_tcp.translate(Eigen::Vector3d(5, 3, 160));
  truth_tcp.rotate(Eigen::AngleAxisd(deg2rad(10), Eigen::Vector3d::UnitX()));
  Tool tool;
  tool.payload = start.tool.payload;
  tool.tcp_given = true;
  tool.flange_T_tcp.translate(Eigen::Vector3d(0, 0, 150));  // the drawing's TCP
  MeasurementSet data;
  data.kind = MeasurementKind::Poses;
  std::normal_distribution<double> noise(0.0, kNoiseMm);
  for (const Vector6d& q : configurations(start.model, 10, rng)) {
    const Pose<double> f = flange_pose(start.model, start.tool.payload, start.params, q);
    Pose<double> tcp{f.R * truth_tcp.linear(), f * Eigen::Vector3d(truth_tcp.translation())};
    tcp.p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    data.poses.push_back({"C" + std::to_string(data.poses.size() + 1), q, tcp, 0});
  }
  const CalibrationRun run = reidentify(start, tool, data, request(CalibrationLevel::Tool));
  const IdentificationResult& r = run.result;
  for (int k = 0; k < 3; ++k) {
    const UnknownEstimate& u = unknown(r, std::string("tcp.") + "xyz"[k]);
    EXPECT_LT(std::abs(u.value - truth_tcp.translation()[k]), 3 * u.std_dev) << u.name;
  }
  const Eigen::AngleAxisd error(r.robot.tool.flange_T_tcp.linear().transpose() *
                                truth_tcp.linear());
  EXPECT_LT(rad2deg(error.angle()), 0.01);  // noise-free orientations
  ASSERT_EQ(r.reidentification->values.size(), 6u);
  EXPECT_EQ(r.reidentification->values[2].name, "tcp.z");
  EXPECT_EQ(r.reidentification->values[2].before, 150);  // the drawing's TCP
  expect_rest_kept(start, r.robot, {});
}

void expect_refusal(const std::function<void()>& call, const std::string& fragment) {
  try {
    call();
    ADD_FAILURE() << "no refusal; expected " << fragment;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Reidentify, RefusesWhatTheDataCannotDetermine) {
  auto rng = test::seeded_rng(16);
  const CalibratedRobot start = calibrated_robot(rng);
  Tool tool;
  tool.targets = {{"N", Eigen::Vector3d(30, -20, 140), true}};
  const MeasurementSet three =
      points(start, start.params, Eigen::Vector3d(30, -20, 140), 0, 3, rng);
  expect_refusal([&] { reidentify(start, tool, three, request(CalibrationLevel::Tool)); },
                 "level tool: target 'N' is measured in 3 configurations; a new tool point needs "
                 "at least 4");
  expect_refusal([&] { reidentify(start, std::nullopt, three, request(CalibrationLevel::Tool)); },
                 "--level tool identifies a new tool: give its tool file");
  expect_refusal(
      [&] { reidentify(start, std::nullopt, three, request(CalibrationLevel::Patterns)); },
      "say what to re-identify");
  // Another tool beside the model at level base: refused, not silently used.
  expect_refusal([&] { reidentify(start, tool, three, request(CalibrationLevel::Base)); },
                 "not a target of the model's tool");
}

}  // namespace
}  // namespace robcal
