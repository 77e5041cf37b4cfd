// Periodic joint errors (issue 19, docs/method/03-error-model.md §5): the forward model against a
// hand-derived shift of the joint angle, the calibrated chain and IK with the group (the analytic
// identification Jacobian's periodic columns are checked with every other column against autodiff
// and finite differences in test_parameter_jacobian.cpp), and on simulated true robots:
// the effect identified (validation error back to the effect-free figure, parameters within 3σ)
// and, on data without it, the group harmless and reported not significant.

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "refusal.hpp"
#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/core/error.hpp"
#include "robcal/identify/cross_validation.hpp"
#include "robcal/identify/identification.hpp"
#include "robcal/kinematics/parameter_jacobian.hpp"
#include "robcal/sim/simulator.hpp"
#include "robcal/validate/validation.hpp"
#include "test_compensate_support.hpp"
#include "test_error_groups_support.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

TEST(PeriodicErrors, NamesUnitsAndGroups) {
  EXPECT_EQ(kParameterCount, 104);
  EXPECT_EQ(parameter_table()[periodic_param(6, 2, true)].name, "joint6.periodic2.sin");
  EXPECT_EQ(parameter_table()[periodic_param(1, 1, false)].name, "joint1.periodic1.cos");
  EXPECT_EQ(parameter_table()[periodic_param(3, 1, true)].unit, "deg");
  EXPECT_EQ(parameter_index("joint4.periodic2.cos"), periodic_param(4, 2, false));
  EXPECT_EQ(match_parameters("joint6.periodic*").size(), 4u);
  EXPECT_EQ(match_parameters("*.periodic1.*").size(), 12u);
  ASSERT_EQ(opt_in_groups().size(), 22u);
  EXPECT_EQ(opt_in_groups()[5].name, "joint6.periodic");
  EXPECT_FALSE(is_opt_in(scale_param(6)));
  EXPECT_TRUE(is_opt_in(periodic_param(1, 1, false)));
  // No level frees them: they are opt-in.
  for (int i : level_parameters(CalibrationLevel::Full)) EXPECT_FALSE(is_opt_in(i));
}

// The periodic error is a shift of the joint angle: the same pose as the robot whose joint
// offset (link theta; base gamma for joint 1) is moved by δθ = Σ cos_h·cos(hq) + sin_h·sin(hq).
TEST(PeriodicErrors, ForwardModelShiftsTheJointAngle) {
  const RobotModel model = load_robot("abb-irb120");
  const PointMass payload{2.6, Eigen::Vector3d(-23, 0, 100)};
  const Vector6d q = (Vector6d() << 0.4, 0.3, -0.2, 1.1, -0.7, 2.5).finished();
  const double e[4] = {deg2rad(0.02), deg2rad(-0.01), deg2rad(0.015), deg2rad(0.03)};
  for (int joint = 1; joint <= kJointCount; ++joint) {
    ParameterVector x = model.nominal(), shifted = model.nominal();
    for (int k = 0; k < 4; ++k) x[periodic_param(joint, 1, false) + k] = e[k];
    const double a = q[joint - 1];
    const double delta =
        e[0] * std::cos(a) + e[1] * std::sin(a) + e[2] * std::cos(2 * a) + e[3] * std::sin(2 * a);
    shifted[joint == 1 ? 5 : link_param(joint, 2)] += delta;
    const Pose<double> got = flange_pose(model, payload, x, q);
    const Pose<double> want = flange_pose(model, payload, shifted, q);
    EXPECT_LT((got.p - want.p).norm(), 1e-10) << "joint " << joint;
    EXPECT_LT((got.R - want.R).norm(), 1e-13) << "joint " << joint;
    // A point off every axis moves (joint 6 turns the flange origin in place).
    const Eigen::Vector3d t(80, 60, 120);
    EXPECT_GT((got * t - flange_pose(model, payload, model.nominal(), q) * t).norm(), 1e-3)
        << "joint " << joint;
  }
}

CalibratedRobot calibrated_with_periodic(const char* name, std::mt19937_64& rng) {
  CalibratedRobot robot = test::random_calibrated(name, rng);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = kPeriodicOffset; i < kBacklashOffset; ++i) robot.params[i] = deg2rad(0.03 * u(rng));
  return robot;
}

TEST(PeriodicErrors, CalibratedChainMatchesTheForwardModelAndItsJacobian) {
  auto rng = test::seeded_rng(192);
  for (const char* name : test::kRobots) {
    test::expect_chain_matches_forward_model(calibrated_with_periodic(name, rng), rng, name);
  }
}

TEST(PeriodicErrors, CalibratedIkRoundTrip) {
  auto rng = test::seeded_rng(193);
  for (const char* name : test::kRobots) {
    SCOPED_TRACE(name);
    test::expect_calibrated_ik_round_trips(calibrated_with_periodic(name, rng), rng);
  }
}

// --- Simulated true robots -------------------------------------------------------------------

using Campaign = test::GroupCampaign;

/// 100 calibration and 60 validation positions on the simulated IRB 120 of the published work,
/// laser tracker with σ = `noise_mm`, each configuration approached from below. `turn_joint6`
/// false holds joint 6 at 30°.
Campaign simulate(const TrueRobot& truth, double noise_mm, uint64_t seed, bool turn_joint6 = true) {
  std::array<JointLimit, kJointCount> box = published_joint_box(truth.robot.model);
  if (!turn_joint6) box[5] = {deg2rad(30), deg2rad(30)};
  return test::simulate_campaign(truth, noise_mm, seed, box);
}

TrueRobot published_truth(bool periodic) {
  TrueRobot truth = published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
  // δθ6 = A·sin(2·q6 + φ): the simulator's gearbox error, 0.01° as in the figures.
  truth.effects.j6_periodic = periodic;
  truth.effects.j6_amplitude_deg = 0.01;
  truth.effects.j6_harmonic = 2;
  truth.effects.j6_phase_deg = 30;
  return truth;
}

IdentificationResult fit(const MeasurementSet& data, bool periodic) {
  return test::fit_full(
      data, periodic ? std::vector<std::string>{"joint6.periodic*"} : std::vector<std::string>{});
}

const GroupSignificance& joint6_group(const std::vector<GroupSignificance>& groups) {
  return groups[5];
}

// The check: with the effect in the true robot, the group brings the validation error to
// within 10 % of the effect-free case at the same noise; without the group the error is today's
// (clearly larger); the second-harmonic terms are A·sin φ and A·cos φ within 3σ.
TEST(PeriodicErrors, SimulatedGearErrorIdentifiedAndCompensated) {
  constexpr double kNoise = 0.01;
  const Campaign clean = simulate(published_truth(false), kNoise, 1901);
  const Campaign gear = simulate(published_truth(true), kNoise, 1901);
  const test::GroupEffect effect = test::group_effect(clean, gear, {"joint6.periodic*"});
  const double free_of_effect = effect.free_of_effect, today = effect.without_group,
               enabled = effect.with_group;
  const IdentificationResult& with = effect.with;
  EXPECT_GT(today, 1.15 * free_of_effect);  // the effect is visible at this noise (+27 %)
  EXPECT_LT(enabled, 1.10 * free_of_effect);
  const auto groups = group_significance(with.robot);
  EXPECT_TRUE(joint6_group(groups).enabled);
  EXPECT_EQ(joint6_group(groups).identified, 4);
  EXPECT_TRUE(joint6_group(groups).significant) << "W = " << joint6_group(groups).wald;
  for (int k = 0; k < 4; ++k)
    EXPECT_FALSE(groups[static_cast<size_t>(k)].enabled) << groups[static_cast<size_t>(k)].group;
}

// Seeded Monte Carlo: every periodic term of joint 6 recovered within 3σ (σ as reported) in each
// of 6 simulated campaigns; the normalised errors' RMS near 1 says the σ are honest.
TEST(PeriodicErrors, MonteCarloRecoveryWithin3Sigma) {
  const TrueRobot truth = published_truth(true);
  const double A = deg2rad(truth.effects.j6_amplitude_deg),
               phi = deg2rad(truth.effects.j6_phase_deg);
  // A·sin(2q + φ) = A·sin φ·cos 2q + A·cos φ·sin 2q; no first harmonic.
  const double expected[4] = {0, 0, A * std::sin(phi), A * std::cos(phi)};
  test::NormalisedErrors z;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    const IdentificationResult r = fit(simulate(truth, 0.01, 1910 + seed).calibration, true);
    for (int k = 0; k < 4; ++k) z.add(r, periodic_param(6, 1, false) + k, expected[k], seed);
  }
  const double rms_z = z.rms();
  const int count = z.count;
  std::printf("normalised periodic errors: RMS %.2f over %d estimates\n", rms_z, count);
  EXPECT_LT(rms_z, 1.8);
}

// Model-selection guard: on data without the effect, enabling the group worsens the
// cross-validated error by less than 2 % and the group is reported not significant.
TEST(PeriodicErrors, GroupOnDataWithoutTheEffectIsHarmlessAndNotSignificant) {
  const Campaign clean = simulate(published_truth(false), 0.01, 1902);
  const auto [without, with_group] =
      test::cross_validated_cost(clean.calibration, {"joint6.periodic*"});
  EXPECT_LT(with_group, 1.02 * without);
  const IdentificationResult with = fit(clean.calibration, true);
  const GroupSignificance& g = joint6_group(group_significance(with.robot));
  EXPECT_TRUE(g.enabled);
  EXPECT_FALSE(g.significant) << "W = " << g.wald << ", p = " << g.p_value;
}

// Identifiability: when joint 6 never turns, its periodic terms are constants that move the
// chain exactly as its joint offset does; the rank test refuses the design, naming each term
// and what it depends on, never reporting them as identified.
TEST(PeriodicErrors, JointNeverTurnedIsRefusedWithTheDependency) {
  const MeasurementSet data = simulate(published_truth(false), 0.01, 1904, false).calibration;
  try {
    fit(data, true);
    ADD_FAILURE() << "a design with joint 6 held cannot identify its periodic terms";
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const char* name : {"joint6.periodic1.cos", "joint6.periodic1.sin", "joint6.periodic2.cos",
                             "joint6.periodic2.sin"})
      EXPECT_NE(what.find(name), std::string::npos) << what;
    EXPECT_NE(what.find("link6.theta"), std::string::npos) << what;
  }
  // Held with --fix, the rest is identified and the group is not enabled.
  IdentifyOptions options;
  options.identify = {"joint6.periodic*"};
  options.fix = {"joint6.periodic*"};
  const IdentificationResult r =
      calibrate(load_robot("abb-irb120"), default_simulation_tool(), data, options);
  EXPECT_FALSE(joint6_group(group_significance(r.robot)).enabled);
}

// A true robot may carry periodic errors in its parameters: the truth file writes the joints that
// have one (degrees) and reads them back.
TEST(PeriodicErrors, TruthFileRoundTrip) {
  TrueRobot truth = published_truth(false);
  truth.robot.params[periodic_param(2, 1, true)] = deg2rad(0.004);
  truth.robot.params[periodic_param(6, 2, false)] = deg2rad(-0.007);
  const std::string text = truth_to_yaml(truth, "abb-irb120");
  EXPECT_NE(text.find("periodic_deg"), std::string::npos);
  const TrueRobot back = parse_truth(yaml::parse(text, "truth.yaml"));
  for (int i = kPeriodicOffset; i < kBacklashOffset; ++i)
    EXPECT_NEAR(back.robot.params[i], truth.robot.params[i], 1e-15) << parameter_table()[i].name;
  std::string bad = text;
  const size_t at = bad.find("periodic_deg:\n  2:");
  ASSERT_NE(at, std::string::npos) << text;
  bad[at + 16] = '7';  // a joint the robot does not have
  EXPECT_REFUSED(parse_truth(yaml::parse(bad, "truth.yaml")), InputError,
                 "truth.yaml:19:6 (periodic_deg.7): expected a joint number 1..6");
}

TEST(PeriodicErrors, ModelFileShowsTheEnabledGroupOnlyAndRoundTrips) {
  const Campaign gear = simulate(published_truth(true), 0.01, 1903);
  const IdentificationResult with = fit(gear.calibration, true);
  const std::string text = calibrated_robot_to_yaml(with.robot);
  EXPECT_NE(text.find("joint6.periodic2.sin"), std::string::npos);
  EXPECT_EQ(text.find("joint5.periodic"), std::string::npos);
  EXPECT_NE(text.find("groups:"), std::string::npos);
  EXPECT_NE(text.find("name: joint6.periodic"), std::string::npos);
  const std::string path =
      (std::filesystem::temp_directory_path() / "robcal_test_periodic_model.yaml").string();
  std::ofstream(path) << text;
  const CalibratedRobot back = load_calibrated_robot(path);
  for (int i = 0; i < kParameterCount; ++i)
    EXPECT_NEAR(back.params[i], with.robot.params[i], 1e-12 * (1 + std::abs(back.params[i])))
        << parameter_table()[i].name;
  const int s2 = periodic_param(6, 2, true);
  EXPECT_NEAR(back.covariance(s2, s2), with.robot.covariance(s2, s2),
              1e-9 * with.robot.covariance(s2, s2));
  // A model without the group writes none of its rows and no groups section.
  const std::string plain = calibrated_robot_to_yaml(fit(gear.calibration, false).robot);
  EXPECT_EQ(plain.find("periodic"), std::string::npos);
  EXPECT_EQ(plain.find("groups:"), std::string::npos);
}

}  // namespace
}  // namespace robcal
