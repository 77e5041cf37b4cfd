// A fourth tool cup end to end (issue 20 item 3): planned with its extra legs, written to and read
// from the plan file, measured by the session (every leg asked, resume intact), simulated on a true
// robot, and calibrated with the over-determined DKP in least squares (pose fit) or straight from
// every leg (leg fit) — at the validation noise floor, with a per-pose uncertainty no larger than
// the three-cup one.

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
#include "robcal/hexapod/measurement.hpp"
#include "robcal/hexapod/placement_search.hpp"
#include "robcal/hexapod/plan_file.hpp"
#include "robcal/hexapod/session.hpp"
#include "robcal/hexapod/session_calibration.hpp"
#include "robcal/hexapod/session_data.hpp"
#include "robcal/hexapod/simulated_readings.hpp"
#include "robcal/hexapod/uncertainty.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/validate/validation.hpp"

namespace robcal::hexapod {
namespace {

/// T4 on the circumcircle of the 150 mm tool triangle, opposite T1: 2R from T1, R from T2 and T3
/// (R = 150/√3), so the base cup of design role B2 reaches it at the ballbar's length in every
/// pose.
constexpr double kCircumradius = 150 / std::numbers::sqrt3;
constexpr std::array<double, 3> kTool4{2 * kCircumradius, kCircumradius, kCircumradius};

/// The published cell with a ±5 mm gauge: every configuration readable on the uncalibrated robot
/// (docs/method/07-hexapod.md §7), so one session measures the whole plan.
HexapodPlanRequest cell_request(bool fourth_cup) {
  HexapodPlanRequest request;
  request.gauge.range_mm = 5;
  if (fourth_cup) request.geometry.tool_cup4_mm = kTool4;
  return request;
}

/// A session directory (plan.json, journal.jsonl) whose journal holds `readings` in script order.
std::filesystem::path measured_session(const std::string& name, const HexapodPlan& plan,
                                       const std::vector<std::optional<double>>& readings) {
  const auto dir = std::filesystem::temp_directory_path() / ("robcal_test_cup4_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_hexapod_plan(dir / "plan.json", plan);
  SessionJournal journal = SessionJournal::create(dir / "journal.jsonl");
  Session session(plan.session);
  for (const std::optional<double>& r : readings) {
    journal.append(session.next_step().value().key, r);
    session.record(r);
  }
  EXPECT_FALSE(session.next_step());
  return dir;
}

struct CellRun {
  HexapodPlan plan;
  SimulatedReadings simulated;
  std::vector<SessionData> placements;
  double pose_fit_mean_mm = 0, leg_fit_mean_mm = 0, nominal_mean_mm = 0;
};

CellRun plan_simulate_calibrate(const RobotModel& model, bool fourth_cup) {
  CellRun run;
  run.plan = plan_hexapod(model, cell_request(fourth_cup));
  SimulatedReadingsRequest sim{"plan.json", std::nullopt, 5, 500};
  run.simulated = simulate_readings(run.plan, model, sim);
  EXPECT_EQ(run.simulated.out_of_range, 0);
  const auto dir =
      measured_session(fourth_cup ? "four" : "three", run.plan, run.simulated.readings);
  run.placements = load_placements({dir.string()});
  const PointMass payload = run.simulated.tool.payload;
  SessionCalibrationRequest request;
  const SessionCalibration poses = calibrate_sessions(run.placements, model, payload, request);
  request.fit = SessionFit::Legs;
  const SessionCalibration legs = calibrate_sessions(run.placements, model, payload, request);
  run.pose_fit_mean_mm =
      validate_model(poses.robot, run.simulated.validation).positions.position_mm.mean;
  run.leg_fit_mean_mm =
      validate_model(legs.robot, run.simulated.validation).positions.position_mm.mean;
  CalibratedRobot nominal = poses.robot;
  nominal.params = model.nominal();
  run.nominal_mean_mm =
      validate_model(nominal, run.simulated.validation).positions.position_mm.mean;
  std::filesystem::remove_all(dir);
  return run;
}

TEST(HexapodFourthCup, PlanSimulateSessionCalibrateAtTheNoiseFloorWithNoLargerPoseUncertainty) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  const CellRun three = plan_simulate_calibrate(model, false);
  const CellRun four = plan_simulate_calibrate(model, true);
  // The same poses and configurations, each with the leg from its B2 role to T4 (and no other:
  // every other B–T4 length is off 300 mm by more than the 2.5 mm allowed).
  ASSERT_EQ(four.plan.session.configurations.size(), three.plan.session.configurations.size());
  ASSERT_GT(four.plan.session.configurations.size(), 50u);
  for (const SessionConfiguration& c : four.plan.session.configurations) {
    ASSERT_EQ(c.legs.size(), 7u) << c.pose;
    const std::optional<LegDesign> design = design_of_legs(c.legs);
    ASSERT_TRUE(design);
    EXPECT_EQ(c.legs[6].base, design->base[1]);
    EXPECT_EQ(c.legs[6].tool, 3);
  }
  // Readings: 3 tool sides + 3 distances to T4, 3 base sides, 7 legs per configuration, and the
  // calibrator checks (every 5 configurations, none after the last).
  const size_t n = four.plan.session.configurations.size();
  EXPECT_EQ(four.simulated.readings.size(), 9 + 7 * n + (n - 1) / 5);
  EXPECT_EQ(three.simulated.readings.size(), 6 + 6 * n + (n - 1) / 5);
  const SessionData& data = four.placements.front();
  ASSERT_TRUE(data.tool_cup4_mm);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR((*data.tool_cup4_mm)[j], kTool4[j], 0.2);
  ASSERT_EQ(data.readings.size(), n);
  for (const LegReadings& r : data.readings) ASSERT_EQ(r.extra_legs.size(), 1u);

  // Validation by the simulated tracker on T1 (σ 0.022 mm per axis: mean |error| of noise alone
  // 0.022·√(8/π) = 0.0351 mm) against the nominal model's ≈ 1 mm: at the noise floor like the
  // three-cup case.
  constexpr double kFloor = 0.0351;
  std::printf(
      "validation mean, mm: three cups poses %.4f legs %.4f; four cups poses %.4f legs %.4f; "
      "nominal %.3f\n",
      three.pose_fit_mean_mm, three.leg_fit_mean_mm, four.pose_fit_mean_mm, four.leg_fit_mean_mm,
      four.nominal_mean_mm);
  for (const double mean :
       {three.pose_fit_mean_mm, three.leg_fit_mean_mm, four.pose_fit_mean_mm, four.leg_fit_mean_mm})
    EXPECT_LT(mean, 1.2 * kFloor);
  EXPECT_GT(four.nominal_mean_mm, 0.5);

  // Per pose: the GUM uncertainty of each tool cup (σ multiples, four_cup_kinematics.hpp) from
  // the seven legs and T4's distances against the six design legs alone, same readings.
  double sum3 = 0, sum4 = 0, worst_ratio = 0;
  for (const LegReadings& r : data.readings) {
    LegReadings design_only = r;
    design_only.extra_legs.clear();
    const FourCupDkpRequest request4 =
        readings_dkp_request(data.base_sides, data.tool_fixture(), r);
    const FourCupDkpRequest request3 =
        readings_dkp_request(data.base_sides, data.tool_fixture(), design_only);
    ASSERT_TRUE(request4.tool.fourth);
    ASSERT_FALSE(request3.tool.fourth);
    const FourCupDkpResult fit4 = solve_four_cup_dkp(request4);
    const FourCupDkpResult fit3 = solve_four_cup_dkp(request3);
    ASSERT_EQ(fit4.status, FourCupDkpStatus::Ok) << fit4.message;
    ASSERT_EQ(fit3.status, FourCupDkpStatus::Ok) << fit3.message;
    // The planned mode's solution: the three-cup one of that start, the four-cup one nearest it.
    const auto mode3 = std::find_if(fit3.solutions.begin(), fit3.solutions.end(),
                                    [&](const FourCupSolution& s) { return s.mode == r.mode; });
    ASSERT_NE(mode3, fit3.solutions.end());
    const auto gap = [&](const FourCupSolution& s) {
      double g = 0;
      for (int j = 0; j < 3; ++j) g = std::max(g, (s.tool_cups[j] - mode3->tool_cups[j]).norm());
      return g;
    };
    const FourCupSolution& s4 = *std::min_element(
        fit4.solutions.begin(), fit4.solutions.end(),
        [&](const FourCupSolution& a, const FourCupSolution& b) { return gap(a) < gap(b); });
    ASSERT_LT(gap(s4), 0.01);
    EXPECT_LT(s4.rms_residual_mm, 0.005);  // the seventh leg agrees with the other six
    for (int j = 0; j < 3; ++j) {
      EXPECT_LE(s4.uncertainty[j].norm, mode3->uncertainty[j].norm * (1 + 1e-9)) << r.config;
      sum3 += mode3->uncertainty[j].norm;
      sum4 += s4.uncertainty[j].norm;
      worst_ratio = std::max(worst_ratio, s4.uncertainty[j].norm / mode3->uncertainty[j].norm);
    }
  }
  std::printf(
      "tool-cup uncertainty over %zu poses, mean σ multiple: three cups %.3f, four cups %.3f "
      "(worst ratio %.3f)\n",
      data.readings.size(), sum3 / (3.0 * n), sum4 / (3.0 * n), worst_ratio);
  // Measured 2.715 → 2.677 σ (−1.4 %): of the four new distances (d14, d24, d34 and the leg)
  // three fix T4, so one is redundant among 16 — a small gain, and never a loss (worst ratio 1).
  EXPECT_LT(sum4, 0.99 * sum3);
  EXPECT_LE(worst_ratio, 1 + 1e-9);
}

TEST(HexapodFourthCup, PlanFileRoundTripAndSessionStepsWithResume) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  const HexapodPlan plan = plan_hexapod(model, cell_request(true));
  const nlohmann::json text = hexapod_plan_json(plan);
  EXPECT_EQ(text["tool_cup4_mm"][1].get<double>(), kTool4[1]);
  const HexapodPlan back = parse_hexapod_plan(text, "plan.json");
  ASSERT_TRUE(back.cell);
  EXPECT_EQ(back.cell->geometry.tool_cup4_mm, std::optional(kTool4));
  EXPECT_EQ(back.session.tool_cup4_mm, std::optional(kTool4));
  ASSERT_EQ(back.session.configurations.size(), plan.session.configurations.size());
  for (size_t c = 0; c < plan.session.configurations.size(); ++c)
    for (size_t l = 0; l < 7; ++l)
      EXPECT_EQ(back.session.configurations[c].legs.at(l).name(),
                plan.session.configurations[c].legs.at(l).name());
  EXPECT_EQ(hexapod_plan_json(back), text);

  // The session asks T4's distances at their own set-ups, then every leg, T4's included.
  Session session(back.session);
  std::vector<SessionStep> steps;
  for (int k = 0; k < 25; ++k) {
    steps.push_back(session.next_step().value());
    session.record(steps.back().nominal_mm);
  }
  EXPECT_EQ(steps[3].key, "tool/T1-T4");
  EXPECT_NEAR(steps[3].nominal_mm, 2 * kCircumradius, 1e-12);
  EXPECT_NE(steps[3].prompt.find("Set the ballbar up at 173.2"), std::string::npos);
  EXPECT_EQ(steps[5].key, "tool/T3-T4");
  EXPECT_EQ(steps[6].key, "base/B1-B2");
  const SessionConfiguration& first = back.session.configurations[0];
  EXPECT_EQ(steps[15].key, "leg/1/" + first.legs[6].name());
  EXPECT_EQ(first.legs[6].name().substr(2), "-T4");
  EXPECT_EQ(steps[16].key, "leg/2/" + back.session.configurations[1].legs[0].name());

  // Killed after 20 readings and resumed: the journal replays to the same step.
  const auto path = std::filesystem::temp_directory_path() / "robcal_test_cup4_resume.jsonl";
  std::filesystem::remove(path);
  {
    SessionJournal journal = SessionJournal::create(path);
    for (int k = 0; k < 20; ++k) journal.append(steps[k].key, steps[k].nominal_mm);
  }
  Session resumed(back.session);
  SessionJournal journal = SessionJournal::open_for_resume(path);
  EXPECT_EQ(journal.replay(resumed), 20);
  EXPECT_EQ(resumed.next_step().value().key, steps[20].key);
  std::filesystem::remove(path);
}

TEST(HexapodFourthCup, BadFourthCupsAndLegsAreRefusedNamingTheFlagOrFileKey) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  HexapodPlanRequest request = cell_request(false);
  // On the line T1T2, halfway: collinear.
  request.geometry.tool_cup4_mm = std::array<double, 3>{75, 75, 75 * std::numbers::sqrt3};
  EXPECT_REFUSED(plan_hexapod(model, request), InputError,
                 "--tool-cup4-mm: tool fixture: the fourth cup T4 is collinear with T1 and T2");
  // 10 mm from T1 (T4 at (0, −10, 0)): the cups collide; at 0 mm it is no distance at all.
  const auto from_t1 = [](double y) {
    const Eigen::Vector3d t4(0, -y, 0), t2(150, 0, 0), t3(75, 75 * std::numbers::sqrt3, 0);
    return std::array<double, 3>{y, (t4 - t2).norm(), (t4 - t3).norm()};
  };
  request.geometry.tool_cup4_mm = from_t1(10);
  EXPECT_REFUSED(plan_hexapod(model, request), InputError,
                 "--tool-cup4-mm: tool cup T4 is 10 mm from T1, closer than a cup diameter "
                 "(25 mm): the cups collide");
  request.geometry.tool_cup4_mm = std::array<double, 3>{0, 150, 150};
  EXPECT_REFUSED(plan_hexapod(model, request), InputError, "d14 = 0 mm is not a positive length");
  // Distances no point has.
  request.geometry.tool_cup4_mm = std::array<double, 3>{100, 100, 60};
  EXPECT_REFUSED(plan_hexapod(model, request), InputError, "--tool-cup4-mm: no point is");
  // The centroid, 86.6 mm from every cup: no leg of any pose within ±2.5 mm of 300 mm.
  request.geometry.tool_cup4_mm =
      std::array<double, 3>{kCircumradius, kCircumradius, kCircumradius};
  const std::string far = test::refusal_message([&] { plan_hexapod(model, request); });
  EXPECT_NE(far.find("--tool-cup4-mm: no pose that can be set up has a leg to T4"),
            std::string::npos)
      << far;

  // Plan files: a leg naming a cup the fixtures lack, a collinear fourth cup.
  const nlohmann::json good = hexapod_plan_json(plan_hexapod(model, cell_request(true)));
  nlohmann::json bad = good;
  bad.erase("tool_cup4_mm");
  EXPECT_REFUSED(parse_hexapod_plan(bad, "plan.json"), InputError,
                 "plan.json (configurations[0].legs): leg '");
  EXPECT_REFUSED(parse_hexapod_plan(bad, "plan.json"), InputError,
                 "T4 only with a fourth tool cup, tool_cup4_mm");
  bad = good;
  bad["configurations"][0]["legs"][6] = "B4-T1";
  EXPECT_REFUSED(parse_hexapod_plan(bad, "plan.json"), InputError,
                 "plan.json (configurations[0].legs): leg 'B4-T1': expected Bi-Tj with i in 1..3, "
                 "j in 1..4");
  bad = good;
  bad["tool_cup4_mm"] = {75, 75, 75 * std::numbers::sqrt3};
  EXPECT_REFUSED(parse_hexapod_plan(bad, "plan.json"), InputError,
                 "plan.json (tool_cup4_mm): tool fixture: the fourth cup T4 is collinear");
  // Three-cup plans of before read as they did: six legs, no fourth cup.
  const HexapodPlan three =
      parse_hexapod_plan(hexapod_plan_json(plan_hexapod(model, cell_request(false))), "old.json");
  EXPECT_FALSE(three.session.tool_cup4_mm);
  EXPECT_EQ(three.session.configurations.front().legs.size(), 6u);
}

TEST(HexapodFourthCup, SimulatedEndToEndReadsT4AtTheNoiseFloor) {
  // `robcal hexapod simulate --gauge-range-mm 5 [--tool-cup4-mm …]`, same seed: every
  // configuration readable, and with T4 each reads its seventh leg.
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  const auto run = [&](bool fourth_cup) {
    EndToEndOptions settings;
    settings.validation_configurations = 300;
    const EndToEndOptions o = end_to_end_options(cell_request(fourth_cup), settings);
    std::mt19937_64 rng(5);
    return run_end_to_end(model, o, rng);
  };
  const EndToEndReport three = run(false), four = run(true);
  for (const EndToEndReport* r : {&three, &four}) {
    EXPECT_EQ(r->retried, 0);
    EXPECT_EQ(r->measured_first, r->configurations_planned);
    EXPECT_GT(r->measured_first, 50);
  }
  EXPECT_EQ(four.configurations_planned, three.configurations_planned);
  const int n = four.measured_first;
  EXPECT_EQ(three.legs_read, 6 * three.measured_first);
  EXPECT_EQ(three.legs_read_fourth_cup, 0);
  EXPECT_EQ(four.legs_read, 7 * n);  // T4 on the circumcircle: one leg to it in every pose
  EXPECT_EQ(four.legs_read_fourth_cup, n);
  const double floor_mm = EndToEndOptions{}.tracker_sigma_mm * std::sqrt(8 / M_PI);
  std::printf(
      "simulate: %d configurations, legs read three cups %d, four cups %d; validation mean mm "
      "three cups poses %.4f legs %.4f, four cups poses %.4f legs %.4f (floor %.4f)\n",
      n, three.legs_read, four.legs_read, three.final_pose_fit.validation.absolute.mean,
      three.leg_fit.validation.absolute.mean, four.final_pose_fit.validation.absolute.mean,
      four.leg_fit.validation.absolute.mean, floor_mm);
  for (const CalibrationStage* s : {&four.final_pose_fit, &four.leg_fit}) {
    EXPECT_TRUE(s->converged);
    EXPECT_GT(s->validation.absolute.mean, 0.95 * floor_mm);
    EXPECT_LT(s->validation.absolute.mean, 1.2 * floor_mm);
  }
  EXPECT_GT(four.nominal.absolute.mean, 0.3);

  // A bad T4 is refused as `hexapod plan` refuses it, before anything is simulated.
  HexapodPlanRequest collinear = cell_request(false);
  collinear.geometry.tool_cup4_mm = std::array<double, 3>{75, 75, 75 * std::numbers::sqrt3};
  std::mt19937_64 rng(5);
  EXPECT_REFUSED(run_end_to_end(model, end_to_end_options(collinear), rng), InputError,
                 "--tool-cup4-mm: tool fixture: the fourth cup T4 is collinear with T1 and T2");
}

TEST(HexapodFourthCup, PlacementPredictionUsesTheFourCupAmplification) {
  // The worst tool-cup GUM uncertainty over the planned poses: three cups at least the published
  // 3.2 σ of the nominal poses (§4; the base-cup permutations kept reach 3.52 σ), lower with the
  // seventh leg and T4's distances (measured 3.47 σ: one redundant distance, a small gain).
  HexapodPlanRequest request = cell_request(true);
  const HexapodGeometry& g = request.geometry;
  const WorstToolCupUncertainty worst =
      worst_tool_cup_uncertainty(plannable_poses(g, request.gauge.range_mm, request.angle_deg,
                                                 request.distance_mm, request.cups)
                                     .kept,
                                 g);
  std::printf("worst tool-cup σ multiple over the planned poses: design legs %.4f, all legs %.4f\n",
              worst.design_legs, worst.all_legs);
  // A second computation: at the unpermuted nominal pose of each assembly mode (rotation-only
  // numbering, base B1 B2 B3), the least-squares GUM of the six design legs is the cascade's
  // autodiff GUM (uncertainty.hpp: the same 12 distances, an exactly determined system).
  const std::vector<ModeUncertainty> cascade = dkp_uncertainty(g);
  int compared = 0;
  for (const HexapodPose& pose : enumerate_poses(g, ToolRelabelling::Rotations)) {
    if (pose.rotation_deg != 0 || pose.description().find("base B1 B2 B3") == std::string::npos)
      continue;
    HexapodPose design_only = pose;
    design_only.legs.resize(kDesignLegs.size());
    for (const ModeUncertainty& m : cascade)
      if (m.mode == pose.mode) {
        double expected = 0;
        for (const CupUncertainty& c : m.cups) expected = std::max(expected, c.norm);
        EXPECT_NEAR(worst_tool_cup_uncertainty({design_only}, g).design_legs, expected,
                    1e-6 * expected)
            << pose.description();
        ++compared;
      }
  }
  EXPECT_EQ(compared, 4);
  EXPECT_GT(worst.design_legs, 3.2);
  EXPECT_LT(worst.design_legs, 3.6);
  EXPECT_LT(worst.all_legs, 0.995 * worst.design_legs);
  EXPECT_GT(worst.all_legs, 0.9 * worst.design_legs);

  // The placement search scales the pose σ by that ratio; the same configurations (T4 refuses
  // no pose here), so the predicted errors scale by it too (C = σ²(JᵀJ)⁻¹ is linear in σ).
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  PlacementSearchRequest search;
  search.plan = cell_request(false);
  search.validation_configurations = 200;
  search.best = 1;
  const PlacementSearchResult r3 = search_placements(model, search);
  search.plan = request;
  const PlacementSearchResult r4 = search_placements(model, search);
  const double ratio = worst.all_legs / worst.design_legs;
  EXPECT_NEAR(r3.pose_sigma_mm, 3.2 * request.gauge.sigma_mm, 1e-15);
  EXPECT_NEAR(r4.pose_sigma_mm, r3.pose_sigma_mm * ratio, 1e-15);
  ASSERT_EQ(r4.ranked.front().configurations, r3.ranked.front().configurations);
  EXPECT_NEAR(r4.ranked.front().predicted_mean_mm, r3.ranked.front().predicted_mean_mm * ratio,
              1e-9 * r3.ranked.front().predicted_mean_mm);

  // `hexapod design` takes T4 from the plans (the same σ); plans whose tool fixtures differ in
  // the fourth cup are refused.
  const auto dir = std::filesystem::temp_directory_path() / "robcal_test_cup4_design";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_hexapod_plan(dir / "four.json", plan_hexapod(model, request));
  HexapodPlanRequest other = cell_request(false);
  other.placement = {350, 0, 300, 0};
  write_hexapod_plan(dir / "three.json", plan_hexapod(model, other));
  PlacementsDesignRequest design;
  design.plan_files = {(dir / "four.json").string(), (dir / "three.json").string()};
  design.validation_configurations = 200;
  EXPECT_REFUSED(design_placements(design), InputError,
                 "three.json (tool): this plan's tool fixture is not the one of");
  design.plan_files.pop_back();
  design.count = r4.ranked.front().configurations;
  const PlacementsDesignResult one = design_placements(design);
  // Every configuration of the plan chosen: the search's prediction of that placement, with the
  // four-cup σ.
  EXPECT_NEAR(one.design.predicted_mean_mm, r4.ranked.front().predicted_mean_mm,
              1e-8 * r4.ranked.front().predicted_mean_mm);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace robcal::hexapod
