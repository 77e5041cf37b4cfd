// The hexapod plan and its file: the planned configurations are the planner's (each one puts the
// tool fixture where its pose says, by forward kinematics), the file reads back into the same plan
// (JSON → plan → JSON is the identity) and bad cells are refused naming the file and key.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "refusal.hpp"
#include "robcal/core/units.hpp"
#include "robcal/hexapod/plan_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "test_support.hpp"

namespace robcal::hexapod {
namespace {

HexapodPlan lr_mate_plan() {
  HexapodPlanRequest request;
  request.placement = {450, 0, 300, 15};
  request.table_z_mm = -20;
  return plan_hexapod(load_robot("fanuc-lrmate200ic"), request);
}

TEST(HexapodPlanFile, PlannedConfigurationsPutTheToolFixtureInTheirPoses) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  const HexapodPlan plan = lr_mate_plan();
  ASSERT_TRUE(plan.outcome && plan.cell && plan.session.flange_T_tool);
  EXPECT_EQ(plan.outcome->configurations_measurable,
            static_cast<int>(plan.session.configurations.size()));
  EXPECT_GT(plan.outcome->poses_measurable, 20);
  // The base fixture frame of the placement, as the planner builds it, and each pose's tool frame.
  const HexapodGeometry g;
  const std::vector<HexapodPose> poses = enumerate_poses(g);
  Pose<double> centroid_T_base;
  centroid_T_base.p = -centroid(fixture_cups(g.base, "base"));
  const Pose<double> robot_T_base = placement_pose(plan.cell->placement) * centroid_T_base;
  for (const SessionConfiguration& c : plan.session.configurations) {
    const auto pose = std::find_if(poses.begin(), poses.end(),
                                   [&](const HexapodPose& p) { return p.label == c.pose; });
    ASSERT_NE(pose, poses.end());
    Vector6d q;
    for (int j = 0; j < kJointCount; ++j) q[j] = deg2rad(c.joints_deg[j]);
    const Pose<double> tool =
        flange_pose(model, PointMass{}, model.nominal(), q) * *plan.session.flange_T_tool;
    const Pose<double> expected = robot_T_base * pose->base_T_tool;
    EXPECT_LT((tool.p - expected.p).norm(), 1e-6) << c.pose << " " << c.labels;
    EXPECT_LT((tool.R - expected.R).norm(), 1e-9) << c.pose << " " << c.labels;
  }
}

TEST(HexapodPlanFile, ReadsBackWhatItWrites) {
  HexapodPlan plan = lr_mate_plan();
  plan.session.tool_sides = TriangleSides{150.01, 149.99, 150.02};
  plan.session.base_sides = TriangleSides{300.01, 299.98, 300.03};
  plan.replanned = Replanned{"s1", "prelim.yaml", {}};
  for (const SessionConfiguration& c : plan.session.configurations) {
    std::vector<double> planned = c.joints_deg;
    planned[0] += 1.5;
    plan.replanned->planned_joints_deg.push_back(planned);
  }
  const nlohmann::json written = hexapod_plan_json(plan);
  const HexapodPlan read = parse_hexapod_plan(written, "plan.json");
  EXPECT_EQ(hexapod_plan_json(read), written);
  ASSERT_TRUE(read.cell);
  EXPECT_EQ(read.cell->placement, plan.cell->placement);
  EXPECT_EQ(read.cell->table_z_mm, -20);
  EXPECT_EQ(read.session.configurations.size(), plan.session.configurations.size());
  EXPECT_EQ(read.session.tool_sides->sides.d23, 149.99);
  EXPECT_EQ(read.replanned->model, "prelim.yaml");
  // The setting-ball configurations reach their points: three points, each with solutions.
  for (const SettingBallPoint& p : read.setting) EXPECT_FALSE(p.configurations.empty());
}

TEST(HexapodPlanFile, HandWrittenPlansHaveNoCell) {
  const nlohmann::json root = nlohmann::json::parse(R"({"configurations": [
      {"pose": "P07", "legs": ["B1-T1","B1-T2","B2-T2","B2-T3","B3-T3","B3-T1"]}]})");
  const HexapodPlan plan = parse_hexapod_plan(root, "hand.json");
  EXPECT_FALSE(plan.cell);
  EXPECT_FALSE(plan.outcome);
  EXPECT_EQ(plan.session.configurations.size(), 1u);
}

TEST(HexapodPlanFile, BadCellNamesFileAndKey) {
  const nlohmann::json good = hexapod_plan_json(lr_mate_plan());
  const auto expect_error = [&](const std::function<void(nlohmann::json&)>& edit,
                                const std::string& key) {
    nlohmann::json bad = good;
    edit(bad);
    try {
      parse_hexapod_plan(bad, "cell.json");
      ADD_FAILURE() << "accepted a bad " << key;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().file, "cell.json");
      EXPECT_EQ(e.where().key, key) << e.what();
    }
  };
  expect_error([](nlohmann::json& p) { p["placement"] = "450,0"; }, "placement");
  expect_error([](nlohmann::json& p) { p["placement"] = "450,0,300,0,1"; }, "placement");
  expect_error(
      [](nlohmann::json& p) {
        p["geometry"]["tool_sides_mm"] = {150, 150};
      },
      "geometry.tool_sides_mm");
  expect_error([](nlohmann::json& p) { p.erase("ball_offset_mm"); }, "ball_offset_mm");
  expect_error([](nlohmann::json& p) { p["setting_ball"][1]["configurations"][0]["labels"] = "x"; },
               "setting_ball[1].configurations.labels");
  // A missing key read through a const json: freed memory before (the fuzz run's
  // crashes/hexapod_plan/configuration-without-joints.json).
  expect_error(
      [](nlohmann::json& p) { p["setting_ball"][0]["configurations"][0].erase("joints_deg"); },
      "setting_ball[0].configurations.joints_deg");
}

TEST(HexapodPlanFile, PlacementText) {
  const std::array<double, 4> p = parse_placement(" 450, -12.5,300 ,90", {"", 0, 0, "--placement"});
  EXPECT_EQ(p, (std::array<double, 4>{450, -12.5, 300, 90}));
  EXPECT_EQ(placement_text(p), "450,-12.5,300,90");
  EXPECT_REFUSED(parse_placement("1,2,3,x", {"", 0, 0, "--placement"}), InputError,
                 "--placement: '1,2,3,x': expected \"x,y,z,yaw\" (mm, deg)");
  EXPECT_REFUSED(parse_placement("1,2,3,nan", {"", 0, 0, "--placement"}), InputError,
                 "--placement: '1,2,3,nan': expected \"x,y,z,yaw\" (mm, deg)");
}

}  // namespace
}  // namespace robcal::hexapod
