// The simulator: readings are the true robot's positions plus the instrument's noise, only
// what the instrument can see is measured, files written are read back by the pipeline's
// measurement reader, and configuration files round trip.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/simulation_files.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

TrueRobot published() {
  return published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
}

RandomConfigurationOptions published_box(const TrueRobot& truth) {
  RandomConfigurationOptions options;
  options.box = published_joint_box(truth.robot.model);
  return options;
}

TEST(SimSimulator, TrackerReadingsAreTruePositionsPlusNoise) {
  const TrueRobot truth = published();
  VirtualInstrument instrument = standard_instrument(InstrumentKind::LaserTracker, truth, 0.05);
  std::mt19937_64 config_rng(1), noise_rng(2);
  const auto configs =
      random_configurations(truth, instrument, 400, config_rng, published_box(truth));
  ASSERT_EQ(configs.size(), 400u);
  const SimulationResult result = simulate_measurements(truth, instrument, configs, noise_rng);
  ASSERT_TRUE(result.skipped.empty());
  ASSERT_EQ(result.measurements.points.size(), 400u);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum_sq = Eigen::Vector3d::Zero();
  const auto box = published_joint_box(truth.robot.model);
  for (const PointMeasurement& m : result.measurements.points) {
    const Pose<double> flange = true_flange_pose(truth, m.joints);
    const Eigen::Vector3d truth_p =
        flange * truth.robot.tool.targets[static_cast<size_t>(m.target)].position_mm;
    const Eigen::Vector3d e = m.position_mm - truth_p;
    sum += e;
    sum_sq += e.cwiseProduct(e);
    // Every measured target faces the tracker, and the joints are in the published box.
    const auto visible = visible_targets(instrument.tracker, flange, truth.robot.tool);
    EXPECT_NE(std::find(visible.begin(), visible.end(), m.target), visible.end());
    for (size_t j = 0; j < kJointCount; ++j) {
      EXPECT_GE(m.joints[static_cast<int>(j)], box[j].lower);
      EXPECT_LE(m.joints[static_cast<int>(j)], box[j].upper);
    }
  }
  const double n = 400;
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(std::abs(sum[k] / n), 4 * 0.05 / std::sqrt(n));
    EXPECT_NEAR(std::sqrt(sum_sq[k] / n) / 0.05, 1.0, 0.15);  // 400 samples: ±3.5 % std error
  }
}

TEST(SimSimulator, UnseenTargetsAreSkippedAndListed) {
  const TrueRobot truth = published();
  VirtualInstrument instrument = standard_instrument(InstrumentKind::LaserTracker, truth);
  std::mt19937_64 config_rng(3), noise_rng(4);
  const auto configs =
      random_configurations(truth, instrument, 60, config_rng, published_box(truth));
  // Turn the tracker 30° about the robot: some planned targets no longer face it.
  instrument.tracker.position_mm = world_from_base(truth, Eigen::Vector3d(1472, 850, 95));
  size_t expected_seen = 0;
  for (const PlannedConfiguration& c : configs) {
    const auto visible =
        visible_targets(instrument.tracker, true_flange_pose(truth, c.joints), truth.robot.tool);
    expected_seen += std::find(visible.begin(), visible.end(), c.target) != visible.end();
  }
  const SimulationResult result = simulate_measurements(truth, instrument, configs, noise_rng);
  EXPECT_EQ(result.measurements.points.size(), expected_seen);
  EXPECT_EQ(result.skipped.size(), configs.size() - expected_seen);
  ASSERT_GT(result.skipped.size(), 0u);
  ASSERT_GT(expected_seen, 0u);
  EXPECT_NE(result.skipped[0].find("not facing the tracker"), std::string::npos);
}

TEST(SimSimulator, CmmPosesAreTheTrueToolPose) {
  const TrueRobot truth = published();
  VirtualInstrument instrument = standard_instrument(InstrumentKind::OpticalCmm, truth);
  instrument.cmm.sigma_mm = 0;
  instrument.cmm.sigma_orientation_deg = 0;
  std::mt19937_64 config_rng(4), noise_rng(5);
  const auto configs =
      random_configurations(truth, instrument, 30, config_rng, published_box(truth));
  const SimulationResult result = simulate_measurements(truth, instrument, configs, noise_rng);
  ASSERT_EQ(result.measurements.poses.size(), 30u);
  for (const PoseMeasurement& m : result.measurements.poses) {
    const Pose<double> flange = true_flange_pose(truth, m.joints);
    EXPECT_LT((m.world_T_tcp.p - flange.p).norm(), 1e-9);
    EXPECT_LT((m.world_T_tcp.R - flange.R).norm(), 1e-12);
    EXPECT_TRUE(cmm_sees_tool(instrument.cmm, flange, truth.robot.tool));
  }
}

TEST(SimSimulator, BallbarReadsOnlyWithinItsWindow) {
  // A random truth with errors of a few mm: the nominal program puts the cup at 150 mm, the
  // real arm misses by up to millimetres, and the ballbar reads only within ±1 mm.
  const RobotModel model = load_robot("abb-irb120");
  std::mt19937_64 truth_rng(6), config_rng(7), noise_rng(8);
  const TrueRobot truth = random_truth(model, default_simulation_tool(), ErrorBounds{}, truth_rng);
  const VirtualInstrument instrument = standard_instrument(InstrumentKind::Ballbar, truth);
  const auto configs =
      random_configurations(truth, instrument, 60, config_rng, published_box(truth));
  ASSERT_EQ(configs.size(), 60u);
  // The operator's program: the nominal robot placed like the truth reaches exactly 150 mm.
  ParameterVector placed = model.nominal();
  placed.head<6>() = truth.robot.params.head<6>();
  for (const PlannedConfiguration& c : configs) {
    const Eigen::Vector3d cup = flange_pose(model, PointMass{}, placed, c.joints) *
                                truth.robot.tool.targets[static_cast<size_t>(c.target)].position_mm;
    EXPECT_NEAR((cup - instrument.ballbar.centre_mm).norm(), 150.0, 1e-6);
  }
  const SimulationResult result = simulate_measurements(truth, instrument, configs, noise_rng);
  EXPECT_EQ(result.measurements.distances.size() + result.skipped.size(), 60u);
  for (const DistanceMeasurement& m : result.measurements.distances) {
    const Eigen::Vector3d cup = true_flange_pose(truth, m.joints) *
                                truth.robot.tool.targets[static_cast<size_t>(m.target)].position_mm;
    const double length = (cup - instrument.ballbar.centre_mm).norm();
    EXPECT_LE(std::abs(length - 150.0), 1.0);
    EXPECT_NEAR(m.length_mm, length, 6 * 0.00051);
  }
  for (const std::string& line : result.skipped)
    EXPECT_NE(line.find("outside the ballbar"), std::string::npos) << line;
}

TEST(SimSimulator, FilesAreReadByTheMeasurementReader) {
  const TrueRobot truth = published();
  const Tool tool = default_simulation_tool();
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "sim_files";
  for (const InstrumentKind kind : {InstrumentKind::LaserTracker, InstrumentKind::OpticalCmm}) {
    SCOPED_TRACE(instrument_name(kind));
    const VirtualInstrument instrument = standard_instrument(kind, truth);
    std::mt19937_64 config_rng(9), noise_rng(10);
    const auto configs =
        random_configurations(truth, instrument, 25, config_rng, published_box(truth));
    const SimulationResult result = simulate_measurements(truth, instrument, configs, noise_rng);
    const SimulationFiles files =
        write_simulation(dir, "cal", result, tool, instrument, truth, "abb-irb120", "test");
    const MeasurementFile back =
        read_measurements_csv(files.measurements.string(), load_tool(files.tool.string()));
    ASSERT_EQ(back.measurements.kind, result.measurements.kind);
    ASSERT_EQ(back.measurements.size(), result.measurements.size());
    for (size_t i = 0; i < back.measurements.points.size(); ++i) {
      EXPECT_EQ(back.measurements.points[i].config, result.measurements.points[i].config);
      EXPECT_EQ(back.measurements.points[i].target, result.measurements.points[i].target);
      EXPECT_LT((back.measurements.points[i].joints - result.measurements.points[i].joints).norm(),
                1e-12);
      EXPECT_LT(
          (back.measurements.points[i].position_mm - result.measurements.points[i].position_mm)
              .norm(),
          1e-9);
    }
    for (size_t i = 0; i < back.measurements.poses.size(); ++i)
      EXPECT_LT(
          (back.measurements.poses[i].world_T_tcp.p - result.measurements.poses[i].world_T_tcp.p)
              .norm(),
          1e-9);
    EXPECT_TRUE(std::filesystem::exists(files.truth));
    EXPECT_EQ(files.truth.parent_path().filename(), "truth");
    EXPECT_LT((load_truth(files.truth.string()).robot.params - truth.robot.params).norm(), 1e-9);
  }
}

TEST(SimSimulator, ConfigurationFilesRoundTripAndBadRowsAreLocated) {
  const TrueRobot truth = published();
  const Tool tool = default_simulation_tool();
  const VirtualInstrument instrument = standard_instrument(InstrumentKind::LaserTracker, truth);
  std::mt19937_64 rng(11);
  const auto configs = random_configurations(truth, instrument, 10, rng, published_box(truth));
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "sim_configs.csv";
  write_file_atomically(path, write_configurations_csv(configs, tool));
  const auto back = read_configurations_csv(path.string(), tool);
  ASSERT_EQ(back.size(), configs.size());
  for (size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back[i].name, configs[i].name);
    EXPECT_EQ(back[i].target, configs[i].target);
    EXPECT_LT((back[i].joints - configs[i].joints).norm(), 1e-12);
  }
  write_file_atomically(path, "config,target,j1,j2,j3,j4,j5,j6\nA,1,0,10,20,30,4x0,50\n");
  try {
    read_configurations_csv(path.string(), tool);
    FAIL() << "accepted a bad number";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 2);
    EXPECT_EQ(e.where().column, 16);
    EXPECT_EQ(e.where().key, "j5");
  }
  write_file_atomically(path, "config,target,j1,j2,j3,j4,j5,j6\nA,7,0,10,20,30,40,50\n");
  EXPECT_REFUSED(read_configurations_csv(path.string(), tool), InputError,
                 "sim_configs.csv:2:3 (target): unknown target '7'; the tool has 1, 2, 3");
  write_file_atomically(path, "config,j1,j2,j3,j4,j5\n");
  EXPECT_REFUSED(read_configurations_csv(path.string(), tool), InputError,
                 "sim_configs.csv:1 (j6): missing column");
}

TEST(SimSimulator, SameSeedSameMeasurements) {
  const TrueRobot truth = published();
  const VirtualInstrument instrument = standard_instrument(InstrumentKind::LaserTracker, truth);
  auto run = [&](uint64_t seed) {
    std::mt19937_64 config_rng(seed), noise_rng(seed + 1);
    const auto configs =
        random_configurations(truth, instrument, 20, config_rng, published_box(truth));
    return simulate_measurements(truth, instrument, configs, noise_rng).measurements.points;
  };
  const auto a = run(3), b = run(3), c = run(4);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].position_mm, b[i].position_mm);
  EXPECT_NE(a[0].position_mm, c[0].position_mm);
}

}  // namespace
}  // namespace robcal
