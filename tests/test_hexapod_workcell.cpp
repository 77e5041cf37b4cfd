// The hexapod planner in the user's cell (issue 16, `hexapod plan --cell`) and with the measuring
// options of issue 20 (gauge range, cup screening, tilted platform): every planned configuration
// is checked here by an independent sampling of the robot's capsules against the floor and the
// keep-out boxes; the screening and gauge options reach the plan and its file.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "refusal.hpp"
#include "robcal/campaign/feasibility.hpp"
#include "robcal/core/units.hpp"
#include "robcal/hexapod/end_to_end.hpp"
#include "robcal/hexapod/plan_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal::hexapod {
namespace {

campaign::Cell cell_with_box(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  return campaign::parse_cell(fmt::format(R"(format: robcal-cell
name: hexapod bench
robot_base: {{position_mm: [0, 0, 0], rotation_xyz_deg: [0, 0, 0]}}
instrument: {{kind: laser-tracker, position_mm: [-2000, 0, 500]}}
floor_z_mm: -10
link_radius_mm: 40
keep_out:
  - {{name: shelf, min_mm: [{}, {}, {}], max_mm: [{}, {}, {}]}}
)",
                                          min.x(), min.y(), min.z(), max.x(), max.y(), max.z()),
                              "bench.yaml");
}

/// Distance from a point to an axis-aligned box by clamping (0 inside).
double point_box(const Eigen::Vector3d& p, const campaign::KeepOutBox& box) {
  return (p - p.cwiseMax(box.min_mm).cwiseMin(box.max_mm)).norm();
}

/// Independent of the planner's check: 201 points along each capsule and the tool cups.
bool touches(const campaign::Cell& cell, const RobotModel& model, const Vector6d& joints,
             const Cups<double>& tool_cups_flange) {
  const ParameterVector params = cell.robot_params(model);
  const auto capsules = campaign::link_capsules(model, params, joints, cell.link_radius_mm);
  const Pose<double> flange = flange_pose(model, PointMass{}, params, joints);
  for (size_t c = 0; c < capsules.size(); ++c)
    for (int k = 0; k <= 200; ++k) {
      const Eigen::Vector3d p = capsules[c].a + (capsules[c].b - capsules[c].a) * (k / 200.0);
      if (c > 0 && p.z() - capsules[c].radius_mm < cell.floor_z_mm) return true;
      for (const auto& box : cell.keep_out)
        if (point_box(p, box) < capsules[c].radius_mm - 1e-6) return true;
    }
  for (const Eigen::Vector3d& t : tool_cups_flange) {
    const Eigen::Vector3d p = flange * t;
    if (p.z() < cell.floor_z_mm) return true;
    for (const auto& box : cell.keep_out)
      if (point_box(p, box) == 0) return true;
  }
  return false;
}

TEST(HexapodWorkcell, PlannedConfigurationsStayOutOfTheKeepOutBoxAndAboveTheFloor) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  HexapodPlanRequest request;
  const HexapodPlan free = plan_hexapod(model, request);
  // A shelf above the fixture, in the way of many configurations.
  request.workcell = cell_with_box({300, -100, 650}, {600, 100, 900});
  const HexapodPlan boxed = plan_hexapod(model, request);
  ASSERT_TRUE(free.outcome && boxed.outcome);
  int rejected = 0;
  for (const PlannedPose& p : boxed.outcome->poses) rejected += p.rejected_workcell;
  EXPECT_EQ(boxed.outcome->configurations_measurable + rejected,
            free.outcome->configurations_measurable);
  EXPECT_GT(rejected, 10);
  const Cups<double> tool = fixture_cups(request.geometry.tool, "tool");
  Cups<double> tool_flange;
  for (int j = 0; j < 3; ++j) tool_flange[j] = *boxed.session.flange_T_tool * tool[j];
  const auto joints = [](const SessionConfiguration& c) {
    Vector6d q;
    for (int j = 0; j < 6; ++j) q[j] = deg2rad(c.joints_deg[j]);
    return q;
  };
  for (const SessionConfiguration& c : boxed.session.configurations)
    EXPECT_FALSE(touches(*request.workcell, model, joints(c), tool_flange)) << c.pose << c.labels;
  // The free plan's configurations that the box plan dropped are exactly those that touch it.
  int touching = 0;
  for (const SessionConfiguration& c : free.session.configurations)
    touching += touches(*request.workcell, model, joints(c), tool_flange);
  EXPECT_EQ(touching, rejected);
  std::printf("shelf above the fixture: %d of %d configurations rejected, %d poses measurable\n",
              rejected, free.outcome->configurations_measurable, boxed.outcome->poses_measurable);
  // The plan file names the cell (provenance: the session does not need it) and keeps the counts.
  nlohmann::json written = hexapod_plan_json(boxed);
  EXPECT_EQ(written["cell_file"], "bench.yaml");
  const HexapodPlan back = parse_hexapod_plan(written, "plan.json");
  written.erase("cell_file");
  EXPECT_TRUE(hexapod_plan_json(back) == written);
}

TEST(HexapodWorkcell, BaseFixtureInsideAKeepOutBoxIsRefusedNamingTheCellFile) {
  HexapodPlanRequest request;
  request.workcell = cell_with_box({400, -50, 200}, {500, 50, 400});  // around the cups' centroid
  request.placement = {450, -173.2, 300, 0};  // B1, B2 outside; B3 at (450, 0, 300)
  EXPECT_REFUSED(plan_hexapod(load_robot("fanuc-lrmate200ic"), request), InputError, "base cup B3");
  EXPECT_REFUSED(plan_hexapod(load_robot("fanuc-lrmate200ic"), request), InputError,
                 "keep-out box 'shelf' of bench.yaml");
}

TEST(HexapodWorkcell, ScreeningAndGaugeOptionsReachThePlan) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  HexapodPlanRequest request;
  request.geometry.tool = {300, 300, 300};  // issue 20: tool cups land on base cups
  request.gauge.range_mm = 5;
  const HexapodPlan plan = plan_hexapod(model, request);
  ASSERT_TRUE(plan.outcome);
  EXPECT_EQ(plan.outcome->refused.size(), 54u);
  EXPECT_EQ(plan.session.range_mm, 5);
  for (const SessionConfiguration& c : plan.session.configurations)
    for (const auto& [label, reason] : plan.outcome->refused) EXPECT_NE(c.pose, label);
  const HexapodPlan back = parse_hexapod_plan(hexapod_plan_json(plan), "plan.json");
  EXPECT_EQ(back.session.range_mm, 5);
  EXPECT_EQ(back.outcome->refused, plan.outcome->refused);
  request.gauge.range_mm = 0;
  EXPECT_REFUSED(plan_hexapod(model, request), InputError, "gauge range 0 mm");
  request.gauge = {};
  request.geometry.tool = {150, 155, 150};  // t23 beyond ±1 mm of the tool set-up (t12)
  EXPECT_REFUSED(plan_hexapod(model, request), InputError, "fixture side t23");
}

TEST(HexapodWorkcell, TiltedPlacementPutsTheSettingBallInTheTiltedPlane) {
  HexapodPlanRequest request;
  request.tilt_deg = 20;
  const HexapodPlan plan = plan_hexapod(load_robot("fanuc-lrmate200ic"), request);
  const Cups<double>& p = *plan.session.setting_points;
  // The cup plane's normal is the placement's z turned 20° about its x axis (yaw 0: world x).
  const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
  EXPECT_NEAR(rad2deg(std::acos(n.z())), 20, 1e-9);
  EXPECT_NEAR(n.x(), 0, 1e-12);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR((p[i] - p[(i + 1) % 3]).norm(), 300, 1e-9);
  EXPECT_GT(plan.outcome->poses_measurable, 10);
  EXPECT_EQ(parse_hexapod_plan(hexapod_plan_json(plan), "plan.json").cell->tilt_deg, 20);
}

TEST(HexapodWorkcell, TiltedPlatformCalibratesEndToEndAndAFiveMillimetreGaugeReadsEverything) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  EndToEndOptions o;
  o.cell.placement = placement_pose({450, 0, 300, 0}, 20);
  o.validation_configurations = 300;
  o.leg_fit = false;
  std::mt19937_64 rng(1);
  const EndToEndReport r = run_end_to_end(model, o, rng);
  EXPECT_GT(r.configurations_planned, 50);
  EXPECT_GT(r.retried, 0);  // ±1 mm: the uncalibrated robot misses some
  // Tracker-noise floor (σ 0.022 mm per axis, the test of HexapodEndToEnd) against ≈ 1.3 mm.
  EXPECT_LT(r.final_pose_fit.validation.absolute.mean, 0.05);
  EXPECT_GT(r.nominal.absolute.mean, 0.5);
  o.cell.range_mm = 5;
  std::mt19937_64 rng5(1);
  const EndToEndReport wide = run_end_to_end(model, o, rng5);
  EXPECT_EQ(wide.retried, 0);
  EXPECT_EQ(wide.measured_first, wide.configurations_planned);
  std::printf(
      "tilted 20°: %d configurations, %d out of ±1 mm (0 of %d with ±5 mm), final mean "
      "%.4f mm (nominal %.4f)\n",
      r.configurations_planned, r.retried, wide.configurations_planned,
      r.final_pose_fit.validation.absolute.mean, r.nominal.absolute.mean);
}

}  // namespace
}  // namespace robcal::hexapod
