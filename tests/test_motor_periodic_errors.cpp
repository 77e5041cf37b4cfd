// Periodic errors in motor angle (issue 19, docs/method/03-error-model.md §9): the robot file's
// gear ratio, the forward model against a hand-derived shift of the joint angle, the calibrated
// chain and IK with the group (the analytic identification Jacobian's motor columns are checked
// with every other column against autodiff and finite differences in test_parameter_jacobian.cpp),
// and on simulated true robots: the effect identified (validation error back to the effect-free
// figure, parameters within 3σ), on data without it harmless and not significant; a joint without
// a gear ratio refused by name; aliasing with the joint-angle harmonics shown, never fitted.

#include <ceres/jet.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "refusal.hpp"
#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/core/error.hpp"
#include "robcal/identify/identification.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/simulator.hpp"
#include "test_compensate_support.hpp"
#include "test_error_groups_support.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

/// Joint 6's gear ratio in these tests (motor turns per joint turn).
constexpr double kJoint6Ratio = 101;

RobotModel geared_irb120(double joint6_ratio = kJoint6Ratio) {
  RobotModel model = load_robot("abb-irb120");
  model.gear_ratio[5] = joint6_ratio;
  return model;
}

const GroupSignificance& group_named(const std::vector<GroupSignificance>& groups,
                                     const std::string& name) {
  for (const GroupSignificance& g : groups)
    if (g.group == name) return g;
  throw std::logic_error("no group " + name);
}

TEST(MotorPeriodicErrors, NamesUnitsAndGroups) {
  EXPECT_EQ(kWarmupOffset, 97);
  EXPECT_EQ(parameter_table()[motor_periodic_param(1, 1, false)].name,
            "joint1.motor_periodic1.cos");
  EXPECT_EQ(parameter_table()[motor_periodic_param(6, 2, true)].name, "joint6.motor_periodic2.sin");
  EXPECT_EQ(motor_periodic_param(6, 2, true), kWarmupOffset - 1);
  EXPECT_EQ(parameter_table()[motor_periodic_param(3, 1, true)].unit, "deg");
  EXPECT_EQ(match_parameters("joint6.motor_periodic*").size(), 4u);
  // The joint-angle patterns do not catch the motor's terms.
  EXPECT_EQ(match_parameters("joint6.periodic*").size(), 4u);
  EXPECT_EQ(match_parameters("*.periodic1.*").size(), 12u);
  EXPECT_EQ(opt_in_group_parameters("periodic").size(), 24u);
  EXPECT_EQ(opt_in_group_parameters("motor_periodic").size(), 24u);
  EXPECT_EQ(opt_in_group_parameters("joint6.motor_periodic").size(), 4u);
  EXPECT_EQ(opt_in_group_parameters("groups").size(),
            static_cast<size_t>(kParameterCount - kPeriodicOffset));
  ASSERT_EQ(opt_in_groups().size(), 22u);
  EXPECT_EQ(opt_in_groups()[19].name, "joint6.motor_periodic");
  EXPECT_TRUE(is_opt_in(motor_periodic_param(1, 1, false)));
  for (int i : level_parameters(CalibrationLevel::Full)) EXPECT_FALSE(is_opt_in(i));
}

TEST(MotorPeriodicErrors, RobotFileGearRatioRoundTripAndRange) {
  RobotModel model = load_robot("abb-irb120");
  model.gear_ratio = {121, 0, 0, 50, 51.5, 101};
  const std::string text = robot_to_yaml(model);
  EXPECT_NE(text.find("gear_ratio: [121, ~, ~, 50, 51.5, 101]"), std::string::npos) << text;
  const RobotModel back = parse_robot(yaml::parse(text, "robot.yaml"));
  EXPECT_EQ(back.gear_ratio, model.gear_ratio);
  // Without the key: every ratio unknown, and none written.
  EXPECT_EQ(load_robot("abb-irb120").gear_ratio, RobotModel{}.gear_ratio);
  EXPECT_EQ(robot_to_yaml(load_robot("abb-irb120")).find("gear_ratio"), std::string::npos);
  std::string bad = text;
  bad.replace(bad.find("51.5"), 4, "0.25");
  EXPECT_REFUSED(parse_robot(yaml::parse(bad, "robot.yaml")), InputError, "0.25");
  bad = text;
  bad.replace(bad.find(", 101]"), 6, "]");
  EXPECT_REFUSED(parse_robot(yaml::parse(bad, "robot.yaml")), InputError,
                 "expected 6 entries, each a gear ratio or ~ (unknown)");
}

// The motor's error is a shift of the joint angle by δ = Σ C_h·cos(h·r·q) + S_h·sin(h·r·q): the
// same pose as the robot whose joint offset (link theta; base gamma for joint 1) moves by δ.
TEST(MotorPeriodicErrors, ForwardModelShiftsTheJointAngleAtTheMotorAngle) {
  RobotModel model = load_robot("abb-irb120");
  model.gear_ratio = {121, 121, 81, 50, 51.5, 101};
  const PointMass payload{2.6, Eigen::Vector3d(-23, 0, 100)};
  const Vector6d q = (Vector6d() << 0.4, 0.3, -0.2, 1.1, -0.7, 2.5).finished();
  const double e[4] = {deg2rad(0.002), deg2rad(-0.001), deg2rad(0.0015), deg2rad(0.003)};
  for (int joint = 1; joint <= kJointCount; ++joint) {
    ParameterVector x = model.nominal(), shifted = model.nominal();
    for (int k = 0; k < 4; ++k) x[motor_periodic_param(joint, 1, false) + k] = e[k];
    const double m = model.gear_ratio[static_cast<size_t>(joint - 1)] * q[joint - 1];
    const double delta =
        e[0] * std::cos(m) + e[1] * std::sin(m) + e[2] * std::cos(2 * m) + e[3] * std::sin(2 * m);
    shifted[joint == 1 ? 5 : link_param(joint, 2)] += delta;
    const Pose<double> got = flange_pose(model, payload, x, q);
    const Pose<double> want = flange_pose(model, payload, shifted, q);
    EXPECT_LT((got.p - want.p).norm(), 1e-10) << "joint " << joint;
    EXPECT_LT((got.R - want.R).norm(), 1e-13) << "joint " << joint;
    EXPECT_GT(std::abs(delta), 1e-6) << "joint " << joint;  // the check is not vacuous
  }
  // A joint without a gear ratio ignores its motor terms.
  RobotModel gearless = model;
  gearless.gear_ratio[2] = 0;
  ParameterVector x = model.nominal();
  x[motor_periodic_param(3, 1, false)] = deg2rad(0.01);
  EXPECT_LT((flange_pose(gearless, payload, x, q).p -
             flange_pose(gearless, payload, model.nominal(), q).p)
                .norm(),
            1e-12);
}

CalibratedRobot calibrated_with_motor_errors(const char* name, std::mt19937_64& rng) {
  CalibratedRobot robot = test::random_calibrated(name, rng);
  robot.model.gear_ratio = {121, 121, 81, 50, 51.5, 101};
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = kPeriodicOffset; i < kBacklashOffset; ++i) robot.params[i] = deg2rad(0.03 * u(rng));
  for (int i = kMotorPeriodicOffset; i < kWarmupOffset; ++i)
    robot.params[i] = deg2rad(0.005 * u(rng));
  return robot;
}

TEST(MotorPeriodicErrors, CalibratedChainMatchesTheForwardModelAndItsJacobian) {
  auto rng = test::seeded_rng(1931);
  for (const char* name : test::kRobots)
    test::expect_chain_matches_forward_model(calibrated_with_motor_errors(name, rng), rng, name);
}

TEST(MotorPeriodicErrors, CalibratedIkRoundTrip) {
  auto rng = test::seeded_rng(1932);
  for (const char* name : test::kRobots) {
    SCOPED_TRACE(name);
    test::expect_calibrated_ik_round_trips(calibrated_with_motor_errors(name, rng), rng);
  }
}

// --- Simulated true robots -------------------------------------------------------------------

using Campaign = test::GroupCampaign;

/// The published IRB 120 with joint 6 geared kJoint6Ratio:1; `motor_error`: its motor adds
/// δθ6 = A·sin(r·q6 + φ), A = 0.01°, φ = 40° (a motor-side eccentricity seen at the joint).
TrueRobot published_truth(bool motor_error, double joint6_ratio = kJoint6Ratio) {
  TrueRobot truth = published_irb120_truth(geared_irb120(joint6_ratio), default_simulation_tool());
  if (motor_error) {
    const double A = deg2rad(0.01), phi = deg2rad(40);
    truth.robot.params[motor_periodic_param(6, 1, false)] = A * std::sin(phi);
    truth.robot.params[motor_periodic_param(6, 1, true)] = A * std::cos(phi);
  }
  return truth;
}

/// 100 calibration and 60 validation positions (σ = 0.01 mm tracker) drawn at random over the
/// published joint box: joint 6 spans hundreds of degrees, r·q6 thousands of motor turns, so the
/// motor phases of the rows are spread uniformly (docs/method/03-error-model.md §9). `joint6_box`
/// (degrees, when given) narrows joint 6's range.
Campaign simulate(const TrueRobot& truth, uint64_t seed,
                  std::optional<std::array<double, 2>> joint6_box = {}) {
  std::array<JointLimit, kJointCount> box = published_joint_box(truth.robot.model);
  if (joint6_box) box[5] = {deg2rad((*joint6_box)[0]), deg2rad((*joint6_box)[1])};
  return test::simulate_campaign(truth, 0.01, seed, box);
}

const std::vector<std::string> kMotorGroup = {"joint6.motor_periodic*"};

// The check: with the effect in the true robot, the group brings the validation error to
// within 10 % of the effect-free case at the same noise; without it the error is clearly larger.
TEST(MotorPeriodicErrors, SimulatedMotorErrorIdentifiedAndCompensated) {
  const Campaign clean = simulate(published_truth(false), 1941);
  const Campaign motor = simulate(published_truth(true), 1941);
  const test::GroupEffect effect = test::group_effect(clean, motor, kMotorGroup, geared_irb120());
  EXPECT_GT(effect.without_group, 1.15 * effect.free_of_effect);
  EXPECT_LT(effect.with_group, 1.10 * effect.free_of_effect);
  const auto groups = group_significance(effect.with.robot);
  const GroupSignificance& g = group_named(groups, "joint6.motor_periodic");
  EXPECT_TRUE(g.enabled);
  EXPECT_EQ(g.identified, 4);
  EXPECT_TRUE(g.significant) << "W = " << g.wald;
  EXPECT_FALSE(group_named(groups, "joint6.periodic").enabled);
}

// Seeded Monte Carlo: every motor term of joint 6 recovered within 3σ (σ as reported) in each of
// 4 simulated campaigns; the normalised errors' RMS near 1 says the σ are honest.
TEST(MotorPeriodicErrors, MonteCarloRecoveryWithin3Sigma) {
  const TrueRobot truth = published_truth(true);
  test::NormalisedErrors z;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const IdentificationResult r =
        test::fit_full(simulate(truth, 1950 + seed).calibration, kMotorGroup, geared_irb120());
    for (int k = 0; k < 4; ++k) {
      const int i = motor_periodic_param(6, 1, false) + k;
      z.add(r, i, truth.robot.params[i], seed);
    }
  }
  std::printf("normalised motor periodic errors: RMS %.2f over %d estimates\n", z.rms(), z.count);
  EXPECT_LT(z.rms(), 1.8);
}

// Model-selection guard: on data without the effect, enabling the group worsens the
// cross-validated error by less than 2 % and the group is reported not significant.
TEST(MotorPeriodicErrors, GroupOnDataWithoutTheEffectIsHarmlessAndNotSignificant) {
  const Campaign clean = simulate(published_truth(false), 1942);
  const auto [without, with_group] =
      test::cross_validated_cost(clean.calibration, kMotorGroup, geared_irb120());
  EXPECT_LT(with_group, 1.02 * without);
  const IdentificationResult with = test::fit_full(clean.calibration, kMotorGroup, geared_irb120());
  const GroupSignificance& g = group_named(group_significance(with.robot), "joint6.motor_periodic");
  EXPECT_TRUE(g.enabled);
  EXPECT_EQ(g.identified, 4);
  EXPECT_FALSE(g.significant) << "W = " << g.wald << ", p = " << g.p_value;
}

// A joint whose gear ratio the robot file does not give: asking for its motor group is refused
// naming the joint; the family names ('motor_periodic', 'groups') leave it out.
TEST(MotorPeriodicErrors, JointWithoutGearRatioRefusedByName) {
  const MeasurementSet data = simulate(published_truth(false), 1943).calibration;
  for (const char* pattern : {"joint5.motor_periodic*", "joint5.motor_periodic"})
    EXPECT_REFUSED(test::fit_full(data, {pattern}, geared_irb120()), InputError,
                   fmt::format("'{}' asks for the motor-angle periodic error of joint 5, whose "
                               "gear ratio the robot file does not give",
                               pattern));
  const IdentificationResult family = test::fit_full(data, {"motor_periodic"}, geared_irb120());
  for (int joint = 1; joint <= kJointCount; ++joint)
    EXPECT_EQ(
        group_named(group_significance(family.robot), fmt::format("joint{}.motor_periodic", joint))
            .enabled,
        joint == 6)
        << "joint " << joint;
}

// Aliasing (docs/method/03-error-model.md §9). With r = 2 the motor's first harmonic is the
// joint's second, the model's own redundancy: the rank test drops the motor's first-harmonic
// terms naming the dependency (never identified), the second harmonic (4·q6) stays. With r = 101
// but joint 6 held within 0.3° (r·range ≈ 0.5 rad) the motor terms look like joint 6's offset:
// the rank test holds three of them naming link6.theta, the fourth's σ is several times the
// whole-range one, and the group is not significant: no silent fit.
TEST(MotorPeriodicErrors, AliasingWithJointHarmonicsShowsAsNotIdentifiable) {
  {
    const RobotModel model = geared_irb120(2);
    const MeasurementSet data = simulate(published_truth(false, 2), 1944).calibration;
    const IdentificationResult r =
        test::fit_full(data, {"joint6.periodic*", "joint6.motor_periodic*"}, model);
    for (const bool sine : {false, true}) {
      const auto i = static_cast<size_t>(motor_periodic_param(6, 1, sine));
      EXPECT_EQ(r.robot.status[i], ParameterStatus::Dropped) << parameter_table()[i].name;
      EXPECT_NE(r.robot.reason[i].find(sine ? "joint6.periodic2.sin" : "joint6.periodic2.cos"),
                std::string::npos)
          << r.robot.reason[i];
      const auto second = static_cast<size_t>(motor_periodic_param(6, 2, sine));
      EXPECT_EQ(r.robot.status[second], ParameterStatus::Identified)
          << parameter_table()[second].name;
    }
  }
  const RobotModel model = geared_irb120();
  const IdentificationResult wide =
      test::fit_full(simulate(published_truth(false), 1945).calibration, kMotorGroup, model);
  const MeasurementSet narrow_data =
      simulate(published_truth(false), 1945, std::array<double, 2>{30, 30.3}).calibration;
  const IdentificationResult narrow = test::fit_full(narrow_data, kMotorGroup, model);
  const GroupSignificance& g =
      group_named(group_significance(narrow.robot), "joint6.motor_periodic");
  EXPECT_FALSE(g.significant) << "W = " << g.wald;
  int held = 0;
  for (int k = 0; k < 4; ++k) {
    const int i = motor_periodic_param(6, 1, false) + k;
    const auto s = static_cast<size_t>(i);
    if (narrow.robot.status[s] == ParameterStatus::Dropped) {
      ++held;
      EXPECT_NE(narrow.robot.reason[s].find("link6.theta"), std::string::npos)
          << narrow.robot.reason[s];
      continue;
    }
    const double sigma_wide = std::sqrt(wide.robot.covariance(i, i));
    const double sigma_narrow = std::sqrt(narrow.robot.covariance(i, i));
    std::printf("%s: σ %.3g° over the whole range, %.3g° within 0.3°\n",
                parameter_table()[i].name.c_str(), rad2deg(sigma_wide), rad2deg(sigma_narrow));
    EXPECT_GT(sigma_narrow, 4 * sigma_wide) << parameter_table()[i].name;
  }
  EXPECT_GE(held, 3);
}

// A true robot may carry motor errors: the truth file writes them (degrees) under
// motor_periodic_deg and reads them back; a joint without a gear ratio is refused.
TEST(MotorPeriodicErrors, TruthFileRoundTrip) {
  RobotModel model = geared_irb120();
  const std::string robot_path =
      (std::filesystem::temp_directory_path() / "robcal_test_geared_irb120.yaml").string();
  std::ofstream(robot_path) << robot_to_yaml(model);
  TrueRobot truth = published_truth(true);
  const std::string text = truth_to_yaml(truth, robot_path);
  EXPECT_NE(text.find("motor_periodic_deg:\n  6: ["), std::string::npos) << text;
  const TrueRobot back = parse_truth(yaml::parse(text, "truth.yaml"));
  EXPECT_EQ(back.robot.model.gear_ratio[5], kJoint6Ratio);
  for (int i = kMotorPeriodicOffset; i < kWarmupOffset; ++i)
    EXPECT_NEAR(back.robot.params[i], truth.robot.params[i], 1e-15) << parameter_table()[i].name;
  std::string bad = text;
  const size_t at = bad.find("motor_periodic_deg:\n  6:");
  ASSERT_NE(at, std::string::npos);
  bad[at + 22] = '5';  // joint 5 has no gear ratio
  EXPECT_REFUSED(parse_truth(yaml::parse(bad, "truth.yaml")), InputError,
                 "joint 5 has no gear_ratio in the robot file: its motor angle is unknown");
}

TEST(MotorPeriodicErrors, ModelFileShowsTheGroupWithSigmaAndRoundTrips) {
  const Campaign motor = simulate(published_truth(true), 1946);
  const IdentificationResult with = test::fit_full(motor.calibration, kMotorGroup, geared_irb120());
  const std::string text = calibrated_robot_to_yaml(with.robot);
  EXPECT_NE(text.find("joint6.motor_periodic1.sin"), std::string::npos);
  EXPECT_EQ(text.find("joint5.motor_periodic"), std::string::npos);
  EXPECT_NE(text.find("name: joint6.motor_periodic"), std::string::npos);
  EXPECT_NE(text.find("gear_ratio: [~, ~, ~, ~, ~, 101]"), std::string::npos);
  const std::string path =
      (std::filesystem::temp_directory_path() / "robcal_test_motor_model.yaml").string();
  std::ofstream(path) << text;
  const CalibratedRobot back = load_calibrated_robot(path);
  EXPECT_EQ(back.model.gear_ratio[5], kJoint6Ratio);
  for (int i = 0; i < kParameterCount; ++i)
    EXPECT_NEAR(back.params[i], with.robot.params[i], 1e-12 * (1 + std::abs(back.params[i])))
        << parameter_table()[i].name;
  const int s1 = motor_periodic_param(6, 1, true);
  EXPECT_NEAR(back.covariance(s1, s1), with.robot.covariance(s1, s1),
              1e-9 * with.robot.covariance(s1, s1));
}

}  // namespace
}  // namespace robcal
