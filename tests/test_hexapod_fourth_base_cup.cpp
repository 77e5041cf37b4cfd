// A fourth base cup B4 end to end (issue 20 item 3, the base side of "a fourth cup on either
// fixture"): placed by the robot at its own setting point, planned with its extra legs, written to
// and read from the plan file, measured by the session (b14, b24, b34 after the base sides, resume
// intact), simulated on a true robot, and calibrated with the over-determined DKP (pose fit) or
// straight from every leg (leg fit, B4 free) — at the validation noise floor, the fitted B4 where
// the true one is.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include <nlohmann/json.hpp>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/hexapod/end_to_end.hpp"
#include "robcal/hexapod/four_cup_kinematics.hpp"
#include "robcal/hexapod/placements_simulation.hpp"
#include "robcal/hexapod/plan_file.hpp"
#include "robcal/hexapod/session.hpp"
#include "robcal/hexapod/world_frame.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal::hexapod {
namespace {

/// B4 on the circumcircle of the 300 mm base triangle, opposite B1: 2R from B1, R from B2 and B3
/// (R = 300/√3), so the tool cup of design role T1 — at the ballbar's length from B1, B2 and B3,
/// on the base triangle's axis — reaches it at the ballbar's length in every pose.
constexpr double kBaseCircumradius = 300 / std::numbers::sqrt3;
constexpr std::array<double, 3> kBase4{2 * kBaseCircumradius, kBaseCircumradius, kBaseCircumradius};
/// T4 as the tool-cup tests put it: on the circumcircle of the 150 mm tool triangle, opposite T1.
constexpr double kToolCircumradius = 150 / std::numbers::sqrt3;
constexpr std::array<double, 3> kTool4{2 * kToolCircumradius, kToolCircumradius, kToolCircumradius};

/// The published cell with a ±5 mm gauge (every configuration readable on the uncalibrated robot).
HexapodPlanRequest cell_request(bool base_cup4, bool tool_cup4) {
  HexapodPlanRequest request;
  request.gauge.range_mm = 5;
  if (base_cup4) request.geometry.base_cup4_mm = kBase4;
  if (tool_cup4) request.geometry.tool_cup4_mm = kTool4;
  return request;
}

EndToEndReport simulate(const RobotModel& model, bool base_cup4, bool tool_cup4) {
  EndToEndOptions settings;
  settings.validation_configurations = 300;
  const EndToEndOptions o = end_to_end_options(cell_request(base_cup4, tool_cup4), settings);
  std::mt19937_64 rng(5);
  return run_end_to_end(model, o, rng);
}

TEST(HexapodFourthBaseCup, SetUpPutsB4OnTheCircumcircleOfTheSettingTriangle) {
  // The setting triangle is equilateral, side 300, about the placement: B4 opposite B1 on its
  // circumcircle is B1 mirrored through the centroid, in the triangle's plane.
  const Pose<double> placement = placement_pose({450, 0, 300, 30}, 10);
  const Cups<double> p = setting_ball_points(placement, 300);
  const Eigen::Vector3d b4 = fourth_setting_ball_point(p, kBase4);
  EXPECT_LT((b4 - (2 * centroid(p) - p[0])).norm(), 1e-9);
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  const std::vector<SettingBallPoint> setting =
      plan_setting_ball(model, placement, 300, 100, kBase4);
  ASSERT_EQ(setting.size(), 4u);
  EXPECT_LT((setting[3].ball_position_mm - b4).norm(), 1e-12);
  EXPECT_FALSE(setting[3].configurations.empty());
  EXPECT_EQ(plan_setting_ball(model, placement, 300, 100).size(), 3u);
}

TEST(HexapodFourthBaseCup, SimulatedEndToEndReadsB4AtTheNoiseFloor) {
  // `robcal hexapod simulate --gauge-range-mm 5 --base-cup4-mm …`, same seed as the three-cup run:
  // every configuration readable, each with a seventh leg from B4.
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  const EndToEndReport three = simulate(model, false, false), four = simulate(model, true, false);
  for (const EndToEndReport* r : {&three, &four}) {
    EXPECT_EQ(r->retried, 0);
    EXPECT_EQ(r->measured_first, r->configurations_planned);
    EXPECT_GT(r->measured_first, 50);
  }
  EXPECT_EQ(four.configurations_planned, three.configurations_planned);
  const int n = four.measured_first;
  EXPECT_EQ(three.legs_read, 6 * n);
  EXPECT_EQ(four.legs_read, 7 * n);  // B4 on the circumcircle: one leg from it in every pose
  EXPECT_EQ(four.legs_read_base_cup4, n);
  EXPECT_EQ(four.legs_read_fourth_cup, 0);
  EXPECT_FALSE(three.leg_fit_base_cup4_error_mm);

  const double floor_mm = EndToEndOptions{}.tracker_sigma_mm * std::sqrt(8 / M_PI);
  std::printf(
      "simulate: %d configurations, legs read three cups %d, with B4 %d; validation mean mm "
      "three cups poses %.4f legs %.4f, with B4 poses %.4f legs %.4f (floor %.4f); fitted B4 %.5f "
      "mm from the true one, distances to B1..B3 within %.5f mm\n",
      n, three.legs_read, four.legs_read, three.final_pose_fit.validation.absolute.mean,
      three.leg_fit.validation.absolute.mean, four.final_pose_fit.validation.absolute.mean,
      four.leg_fit.validation.absolute.mean, floor_mm, four.leg_fit_base_cup4_error_mm.value(),
      four.leg_fit_base_cup4_distance_error_mm.value());
  for (const CalibrationStage* s : {&four.final_pose_fit, &four.leg_fit}) {
    EXPECT_TRUE(s->converged);
    EXPECT_GT(s->validation.absolute.mean, 0.95 * floor_mm);
    EXPECT_LT(s->validation.absolute.mean, 1.2 * floor_mm);
  }
  EXPECT_GT(four.nominal.absolute.mean, 0.3);
  // B4 is where the uncalibrated robot put it (≈ 1 mm off its design, as B1..B3): the leg fit
  // finds it from its 120 legs and its three distances at the ballbar's σ (0.00051 mm). Measured
  // 0.6 µm in the B1..B3 frame (which carries B1..B3's own fit errors), distances 0.4 µm.
  const double sigma = HexapodPlanRequest{}.gauge.sigma_mm;
  EXPECT_LT(*four.leg_fit_base_cup4_distance_error_mm, 2 * sigma);
  EXPECT_LT(*four.leg_fit_base_cup4_error_mm, 3 * sigma);
}

TEST(HexapodFourthBaseCup, WithT4TooBothFourthCupsAreReadAndFitted) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  const EndToEndReport both = simulate(model, true, true);
  const int n = both.measured_first;
  EXPECT_EQ(both.retried, 0);
  EXPECT_GT(n, 50);
  // Every pose has its leg from B4 (design-T1 cup) and to T4 (design-B2 cup); a few also B4–T4 or
  // a second one, each counted once in legs_read.
  EXPECT_GE(both.legs_read_base_cup4, n);
  EXPECT_GE(both.legs_read_fourth_cup, n);
  EXPECT_GE(both.legs_read, 8 * n);
  EXPECT_LE(both.legs_read, 6 * n + both.legs_read_base_cup4 + both.legs_read_fourth_cup);
  const double floor_mm = EndToEndOptions{}.tracker_sigma_mm * std::sqrt(8 / M_PI);
  std::printf(
      "simulate with B4 and T4: %d configurations, %d legs (%d from B4, %d to T4); validation "
      "mean poses %.4f legs %.4f mm; fitted B4 %.5f mm off, distances within %.5f mm\n",
      n, both.legs_read, both.legs_read_base_cup4, both.legs_read_fourth_cup,
      both.final_pose_fit.validation.absolute.mean, both.leg_fit.validation.absolute.mean,
      both.leg_fit_base_cup4_error_mm.value(), both.leg_fit_base_cup4_distance_error_mm.value());
  for (const CalibrationStage* s : {&both.final_pose_fit, &both.leg_fit}) {
    EXPECT_TRUE(s->converged);
    EXPECT_GT(s->validation.absolute.mean, 0.95 * floor_mm);
    EXPECT_LT(s->validation.absolute.mean, 1.2 * floor_mm);
  }
  const double sigma = HexapodPlanRequest{}.gauge.sigma_mm;
  EXPECT_LT(*both.leg_fit_base_cup4_distance_error_mm, 2 * sigma);
  EXPECT_LT(*both.leg_fit_base_cup4_error_mm, 3 * sigma);

  // The pose uncertainty with B4's legs and distances: never above the design legs' (one more
  // redundant distance per pose), as with T4 (§7).
  const HexapodPlanRequest request = cell_request(true, false);
  const WorstToolCupUncertainty worst = worst_tool_cup_uncertainty(
      plannable_poses(request.geometry, request.gauge.range_mm, request.angle_deg,
                      request.distance_mm, request.cups)
          .kept,
      request.geometry);
  std::printf("worst tool-cup σ multiple with B4: design legs %.4f, all legs %.4f\n",
              worst.design_legs, worst.all_legs);
  EXPECT_LT(worst.all_legs, worst.design_legs);
}

// Two placements with both fourth cups (simulate_placements, as `hexapod design` plans them): each
// configuration reads its legs from B4 and to T4 too, each placement's B4 is fitted with its
// other cups, and the whole-workspace error stays that of the three-cup fit of the same
// configurations (the floor the fixture sides leave, a few µm).
TEST(HexapodFourthBaseCup, TwoPlacementsReadAndFitBothFourthCups) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  PointMass payload{2.6, Eigen::Vector3d(50, 25, 100)};
  auto truth_rng = test::seeded_rng(7);
  const TrueRobot truth =
      levelled_random_truth(model, payload, ErrorBounds{0.3, 0.1, 0.05e-6, 1.0, 0.1}, truth_rng);
  PlacementsSimulationOptions options;
  options.validation_configurations = 300;
  const auto run = [&](bool fourth_cups) {
    std::vector<SimulatedPlacement> placements;
    for (const std::array<double, 4>& at :
         {std::array<double, 4>{450, 0, 300, 0}, std::array<double, 4>{350, 0, 300, 0}}) {
      HexapodPlanRequest request = cell_request(fourth_cups, fourth_cups);
      request.placement = at;
      const HexapodPlan plan = plan_hexapod(model, request);
      std::vector<int> every_third;
      for (int k = 0; k < static_cast<int>(plan.session.configurations.size()); k += 3)
        every_third.push_back(k);
      placements.push_back({plan, every_third});
    }
    auto rng = test::seeded_rng(8);
    return simulate_placements(model, truth, payload, placements, options, rng);
  };
  const PlacementsSimulation three = run(false), four = run(true);
  for (const PlacementsSimulation* s : {&three, &four}) {
    EXPECT_TRUE(s->converged);
    EXPECT_EQ(s->out_of_range, 0);
    EXPECT_LT(s->fit_rms_mm, 1.2 * options.sigma_mm);
  }
  EXPECT_EQ(four.configurations, three.configurations);
  EXPECT_EQ(three.legs, 6 * three.configurations);
  EXPECT_GE(four.legs, 8 * four.configurations);  // a leg from B4 and one to T4 in every pose
  EXPECT_LT(four.calibrated.mean, 1.2 * three.calibrated.mean);
  EXPECT_LT(four.calibrated.mean, 0.005);
  std::printf(
      "two placements, %d configurations: three cups %d legs, whole workspace %.5f mm; both fourth "
      "cups %d legs, %.5f mm (fit rms %.6f mm)\n",
      four.configurations, three.legs, three.calibrated.mean, four.legs, four.calibrated.mean,
      four.fit_rms_mm);
}

TEST(HexapodFourthBaseCup, PlanFileRoundTripAndSessionStepsWithResume) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  const HexapodPlan plan = plan_hexapod(model, cell_request(true, false));
  ASSERT_GT(plan.session.configurations.size(), 50u);
  // Each configuration: the six design legs, then the leg from B4 to the design-T1 cup.
  for (const SessionConfiguration& c : plan.session.configurations) {
    ASSERT_EQ(c.legs.size(), 7u) << c.pose;
    const std::optional<LegDesign> design = design_of_legs(c.legs);
    ASSERT_TRUE(design);
    EXPECT_EQ(c.legs[6].base, 3);
    EXPECT_EQ(c.legs[6].tool, design->tool[0]);
  }
  const nlohmann::json text = hexapod_plan_json(plan);
  EXPECT_EQ(text["base_cup4_mm"][0].get<double>(), kBase4[0]);
  ASSERT_EQ(text["setting_ball"].size(), 4u);
  EXPECT_EQ(text["setting_ball"][3]["cup"], "B4");
  const HexapodPlan back = parse_hexapod_plan(text, "plan.json");
  ASSERT_TRUE(back.cell);
  EXPECT_EQ(back.cell->geometry.base_cup4_mm, std::optional(kBase4));
  EXPECT_EQ(back.session.base_cup4_mm, std::optional(kBase4));
  ASSERT_TRUE(back.session.setting_point4);
  EXPECT_LT((*back.session.setting_point4 - plan.setting[3].ball_position_mm).norm(), 1e-6);
  EXPECT_EQ(hexapod_plan_json(back), text);

  // The session asks b14, b24, b34 after the base sides, each at its design length.
  Session session(back.session);
  std::vector<SessionStep> steps;
  for (int k = 0; k < 25; ++k) {
    steps.push_back(session.next_step().value());
    session.record(steps.back().nominal_mm);
  }
  EXPECT_EQ(steps[5].key, "base/B3-B1");
  EXPECT_EQ(steps[6].key, "base/B1-B4");
  EXPECT_NEAR(steps[6].nominal_mm, 2 * kBaseCircumradius, 1e-12);
  EXPECT_NE(steps[6].prompt.find("Set the ballbar up at 346.41"), std::string::npos);
  EXPECT_EQ(steps[8].key, "base/B3-B4");
  EXPECT_EQ(steps[8].kind, StepKind::BaseSide);
  const SessionConfiguration& first = back.session.configurations[0];
  EXPECT_EQ(steps[9].key, "leg/1/" + first.legs[0].name());
  EXPECT_EQ(steps[15].key, "leg/1/" + first.legs[6].name());
  EXPECT_EQ(first.legs[6].name().substr(0, 3), "B4-");
  // The result lists the six base distances.
  EXPECT_EQ(session.result_json()["base_sides_mm"].size(), 6u);

  // Killed after 8 readings (inside B4's distances) and resumed: the same next step.
  const auto path = std::filesystem::temp_directory_path() / "robcal_test_base4_resume.jsonl";
  std::filesystem::remove(path);
  {
    SessionJournal journal = SessionJournal::create(path);
    for (int k = 0; k < 8; ++k) journal.append(steps[k].key, steps[k].nominal_mm);
  }
  Session resumed(back.session);
  SessionJournal journal = SessionJournal::open_for_resume(path);
  EXPECT_EQ(journal.replay(resumed), 8);
  EXPECT_EQ(resumed.next_step().value().key, "base/B3-B4");
  std::filesystem::remove(path);

  // A re-plan's measured sides carry B4's distances: not asked again.
  SessionPlan measured = back.session;
  measured.tool_sides = TriangleSides{150, 150, 150};
  measured.base_sides = FixtureDistances(TriangleSides{300, 300, 300}, kBase4);
  EXPECT_EQ(Session(measured).next_step().value().key, steps[9].key);
}

TEST(HexapodFourthBaseCup, BadFourthBaseCupsAreRefusedNamingTheFlagOrFileKey) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  HexapodPlanRequest request = cell_request(false, false);
  const double h = 150 * std::numbers::sqrt3;  // B3's height over B1B2
  // On the line B1B2, halfway: collinear.
  request.geometry.base_cup4_mm = std::array<double, 3>{150, 150, h};
  EXPECT_REFUSED(plan_hexapod(model, request), InputError,
                 "--base-cup4-mm: base fixture: the fourth cup B4 is collinear with B1 and B2");
  // 10 mm from B1 (B4 at (0, −10, 0)): the cups collide; at 0 mm it is no distance at all.
  const auto from_b1 = [&](double y) {
    const Eigen::Vector3d b4(0, -y, 0), b2(300, 0, 0), b3(150, h, 0);
    return std::array<double, 3>{y, (b4 - b2).norm(), (b4 - b3).norm()};
  };
  request.geometry.base_cup4_mm = from_b1(10);
  EXPECT_REFUSED(plan_hexapod(model, request), InputError,
                 "--base-cup4-mm: base cup B4 is 10 mm from B1, closer than a cup diameter "
                 "(25 mm): the cups collide");
  request.geometry.base_cup4_mm = std::array<double, 3>{0, 300, 300};
  EXPECT_REFUSED(plan_hexapod(model, request), InputError, "d14 = 0 mm is not a positive length");
  // Distances no point has.
  request.geometry.base_cup4_mm = std::array<double, 3>{200, 200, 120};
  EXPECT_REFUSED(plan_hexapod(model, request), InputError, "--base-cup4-mm: no point is");
  // 300 mm in front of B1B2 (B4 at (150, −300, 0)): out of the gauge's reach in every pose.
  request.geometry.base_cup4_mm =
      std::array<double, 3>{std::hypot(150, 300), std::hypot(150, 300), h + 300};
  EXPECT_REFUSED(plan_hexapod(model, request), InputError,
                 "--base-cup4-mm: no pose that can be set up has a leg to B4 within ±2.5 mm");
  // The simulator refuses a bad B4 as the planner does, before anything is simulated.
  HexapodPlanRequest collinear = cell_request(false, false);
  collinear.geometry.base_cup4_mm = std::array<double, 3>{150, 150, h};
  std::mt19937_64 rng(5);
  EXPECT_REFUSED(run_end_to_end(model, end_to_end_options(collinear), rng), InputError,
                 "--base-cup4-mm: base fixture: the fourth cup B4 is collinear with B1 and B2");

  // Plan files: a leg from B4 without it, a collinear B4, three setting points for four cups.
  const nlohmann::json good = hexapod_plan_json(plan_hexapod(model, cell_request(true, false)));
  nlohmann::json bad = good;
  bad.erase("base_cup4_mm");
  bad.erase("setting_ball");
  EXPECT_REFUSED(parse_hexapod_plan(bad, "plan.json"), InputError,
                 "B4 only with a fourth base cup, base_cup4_mm");
  bad = good;
  bad["base_cup4_mm"] = {150, 150, h};
  EXPECT_REFUSED(parse_hexapod_plan(bad, "plan.json"), InputError,
                 "plan.json (base_cup4_mm): base fixture: the fourth cup B4 is collinear");
  bad = good;
  bad["setting_ball"].erase(3);
  EXPECT_REFUSED(parse_hexapod_plan(bad, "plan.json"), InputError,
                 "plan.json (setting_ball): expected the four setting-ball points B1..B4");
  bad = good;
  bad["measured_sides"] = {{"tool_mm", {150, 150, 150}}, {"base_mm", {300, 300, 300}}};
  EXPECT_REFUSED(parse_hexapod_plan(bad, "plan.json"), InputError,
                 "plan.json (measured_sides.base_mm): expected six distances [d12, d23, d31, d14, "
                 "d24, d34] (mm): the plan has a fourth base cup");
}

}  // namespace
}  // namespace robcal::hexapod
