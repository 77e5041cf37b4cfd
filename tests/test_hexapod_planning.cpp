// Hexapod planning and the simulated cell: planned configurations reach their poses, pass the
// clearance checks and, on a perfect robot, the legs read exactly the ballbar length and the
// measured poses reproduce the planned flange poses through the whole chain (setting ball,
// world frame, DKP, relabelling, frames).

#include <gtest/gtest.h>

#include <set>

#include "robcal/core/units.hpp"
#include "robcal/hexapod/measurement.hpp"
#include "robcal/hexapod/planning.hpp"
#include "robcal/hexapod/simulation.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "test_support.hpp"

namespace robcal::hexapod {
namespace {

HexapodCellOptions lr_mate_cell() {
  HexapodCellOptions o;
  o.placement.p = Eigen::Vector3d(450, 0, 300);
  return o;
}

TEST(HexapodPlanning, ConfigurationsReachTheirPosesWithinLimitsAndClearOfTheTable) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  const HexapodGeometry g;
  const Cups<double> base = fixture_cups(g.base, "base");
  CellSetup cell;
  Pose<double> centroid_T_base;
  centroid_T_base.p = -centroid(base);
  Pose<double> placement;
  placement.p = Eigen::Vector3d(400, 0, 100);
  cell.robot_T_base = placement * centroid_T_base;
  cell.flange_T_tool = default_tool_mount(g.tool);
  const PlanSummary plan = plan_poses(model, cell, base, enumerate_poses(g));
  EXPECT_GT(plan.measurable_poses, 20);
  int total = 0;
  for (const PosePlan& p : plan.poses) {
    std::set<int> branches;
    for (const PoseConfiguration& c : p.configurations) {
      ++total;
      EXPECT_TRUE(branches.insert(c.config.index()).second) << p.pose.label;
      EXPECT_TRUE(model.within_limits(c.joints));
      const Pose<double> f = flange_pose(model, PointMass{}, model.nominal(), c.joints);
      EXPECT_LT((f.p - p.robot_T_flange.p).norm(), 1e-8) << p.pose.label;
      EXPECT_LT(rotation_distance(f.R, p.robot_T_flange.R), 1e-10) << p.pose.label;
      std::vector<Eigen::Vector3d> cups_robot(3);
      for (int i = 0; i < 3; ++i) cups_robot[i] = cell.robot_T_base * base[i];
      EXPECT_EQ(check_clearance(model, cell, cups_robot, c.joints), Clearance::Ok);
      // The tool cups sit on the planned pose: every leg at the ballbar length.
      const Pose<double> robot_T_tool = f * cell.flange_T_tool;
      const Cups<double> tool_local = fixture_cups(g.tool, "tool");
      for (const PhysicalLeg& leg : p.pose.legs)
        EXPECT_NEAR((cups_robot[leg.base] - robot_T_tool * tool_local[leg.tool]).norm(), 300, 1e-8);
    }
  }
  EXPECT_EQ(total, plan.configurations);
  std::printf(
      "LR Mate 200iC, fixture at (400, 0, 100) mm: %d of 72 poses measurable, %d "
      "configurations (published: 46 poses, 124 configurations for its placement)\n",
      plan.measurable_poses, plan.configurations);
}

TEST(HexapodPlanning, ArmBelowTheTableIsRejected) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  CellSetup cell;
  cell.robot_T_base.p = Eigen::Vector3d(1500, 0, 0);  // far away: only the table matters
  const Cups<double> base = fixture_cups({300, 300, 300}, "base");
  std::vector<Eigen::Vector3d> cups_robot(3);
  for (int i = 0; i < 3; ++i) cups_robot[i] = cell.robot_T_base * base[i];
  // Upper arm leaning far forward, forearm turned down until the wrist centre is near the table.
  Vector6d down = Vector6d::Zero();
  down[1] = deg2rad(100);
  double wrist_z = 1e9;
  for (double j3 = -70; j3 <= 205 && wrist_z >= 30; j3 += 5) {
    down[2] = deg2rad(j3);
    wrist_z = link_frames(model, PointMass{}, model.nominal().data(), down.data())[4].p.z();
  }
  ASSERT_LT(wrist_z, 30);
  ASSERT_TRUE(model.within_limits(down));
  EXPECT_EQ(check_clearance(model, cell, cups_robot, down), Clearance::Table);
  EXPECT_EQ(check_clearance(model, cell, cups_robot, Vector6d::Zero()), Clearance::Ok);
  // The same home configuration with the fixture right under the wrist.
  const auto home =
      link_frames(model, PointMass{}, model.nominal().data(), Vector6d::Zero().eval().data());
  Pose<double> centroid_T_base;
  centroid_T_base.p = -centroid(base);
  Pose<double> under;
  under.p = Eigen::Vector3d(home[4].p.x(), home[4].p.y(), home[4].p.z() - 30);
  cell.robot_T_base = under * centroid_T_base;
  for (int i = 0; i < 3; ++i) cups_robot[i] = cell.robot_T_base * base[i];
  EXPECT_EQ(check_clearance(model, cell, cups_robot, Vector6d::Zero()), Clearance::BaseFixture);
}

TEST(HexapodSimulation, PerfectRobotReadsNominalLegsAndRecoversPlannedPoses) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  TrueRobot truth;
  truth.robot = CalibratedRobot::nominal(model, Tool{});
  HexapodCellOptions o = lr_mate_cell();
  o.fixture_tolerance_mm = 0;
  o.sigma_mm = 0;
  auto rng = test::seeded_rng(3);
  const SimulatedHexapodCell cell = set_up_simulated_cell(truth, model, o, rng);
  EXPECT_LT(cell.world.rms_mm, 1e-9);  // a perfect robot puts the cups exactly 300 mm apart
  const PlanSummary plan = plan_poses(model, cell.cell, fixture_cups(cell.base_sides, "base"),
                                      enumerate_poses(o.design));
  std::vector<LegReadings> readings;
  std::vector<Pose<double>> expected;
  for (const PosePlan& p : plan.poses)
    for (const PoseConfiguration& c : p.configurations) {
      const auto legs = simulate_legs(cell, p.pose, c.joints, rng);
      ASSERT_TRUE(legs.has_value()) << p.pose.label;
      for (double l : *legs) EXPECT_NEAR(l, 300, 1e-8);
      readings.push_back({p.pose.label, c.joints, p.pose.design, p.pose.mode, *legs});
      expected.push_back(p.robot_T_flange * cell.cell.flange_T_tool);
    }
  ASSERT_FALSE(readings.empty());
  const MeasurementSet set = pose_measurements(cell.base_sides, cell.tool_sides, readings,
                                               cell.world.robot_T_fixture, "simulated");
  ASSERT_EQ(set.poses.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_LT((set.poses[i].world_T_tcp.p - expected[i].p).norm(), 1e-7) << set.poses[i].config;
    EXPECT_LT(rotation_distance(set.poses[i].world_T_tcp.R, expected[i].R), 1e-9);
  }
}

}  // namespace
}  // namespace robcal::hexapod
