// Thermal drift (issue 19, docs/method/03-error-model.md §8): the forward model against the
// simulator's true robot (an independent statement of the same link growth), the analytic
// regressor's columns against autodiff and finite differences at a temperature, the calibrated
// chain, IK and compensation setup at the target's temperature, the measurement file's
// `temperature` column, and on simulated true robots: the effect identified (validation error
// back to the effect-free figure, coefficients within 3σ), data without temperatures or at one
// temperature refused by name, and on data without the effect the group harmless and not
// significant.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "refusal.hpp"
#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/compensate/compensation_setup.hpp"
#include "robcal/core/error.hpp"
#include "robcal/identify/identification.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/kinematics/parameter_jacobian.hpp"
#include "robcal/sim/simulator.hpp"
#include "test_compensate_support.hpp"
#include "test_error_groups_support.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

TEST(Thermal, NamesUnitsAndGroup) {
  // After the mounting group: no existing index moves.
  EXPECT_EQ(kMountingOffset, 67);
  EXPECT_EQ(kThermalOffset, 68);
  EXPECT_EQ(kParameterCount, 104);  // the gravity group follows (§11)
  EXPECT_EQ(parameter_table()[expansion_param(2)].name, "link2.expansion");
  EXPECT_EQ(parameter_table()[expansion_param(6)].name, "link6.expansion");
  EXPECT_EQ(parameter_table()[expansion_param(4)].unit, "ppm/K");
  EXPECT_EQ(parameter_table()[expansion_param(4)].to_external(), 1e6);
  EXPECT_EQ(parameter_index("link3.expansion"), expansion_param(3));
  EXPECT_EQ(match_parameters("*.expansion").size(), 5u);
  EXPECT_TRUE(is_opt_in(expansion_param(5)));
  for (int i : level_parameters(CalibrationLevel::Full)) EXPECT_LT(i, kPeriodicOffset);
  const ParameterGroup& group = opt_in_groups()[13];
  EXPECT_EQ(group.name, "thermal");
  EXPECT_EQ(group.params, (std::vector<int>{68, 69, 70, 71, 72}));
}

// A group's name selects it whole in `--identify` and `--fix`: one group, a family, every group.
TEST(Thermal, GroupNamesSelectTheirParameters) {
  const std::vector<int> thermal = opt_in_groups()[13].params;
  EXPECT_EQ(opt_in_group_parameters("thermal"), thermal);
  EXPECT_EQ(opt_in_group_parameters("backlash").size(), 6u);
  EXPECT_EQ(opt_in_group_parameters("periodic").size(), 24u);
  EXPECT_EQ(opt_in_group_parameters("joint6.periodic").size(), 4u);
  EXPECT_EQ(opt_in_group_parameters("mounting"), std::vector<int>{kJoint1Compliance});
  EXPECT_EQ(opt_in_group_parameters("groups").size(),
            static_cast<size_t>(kParameterCount - kPeriodicOffset));
  for (const char* other : {"compliance", "link3.a", "expansion", "*"})
    EXPECT_TRUE(opt_in_group_parameters(other).empty()) << other;
  const UnknownLayout layout =
      make_unknown_layout(default_simulation_tool(), MeasurementKind::Points);
  const std::vector<bool> free =
      select_unknowns(layout, CalibrationLevel::Full, {"groups"}, {"periodic", "joint1.backlash"});
  std::vector<bool> in_level(kParameterCount, false);
  for (int i : level_parameters(CalibrationLevel::Full)) in_level[static_cast<size_t>(i)] = true;
  for (int i = 0; i < kParameterCount; ++i) {
    const bool group = i >= kPeriodicOffset;
    const bool fixed = (i >= kPeriodicOffset && i < kBacklashOffset) || i == backlash_param(1);
    // The level's parameters as the level frees them (the name only adds the groups).
    const bool expected = group ? !fixed : in_level[static_cast<size_t>(i)];
    EXPECT_EQ(free[static_cast<size_t>(i)], expected) << parameter_table()[i].name;
  }
  EXPECT_TRUE(free[static_cast<size_t>(link_param(3, 1))]);
}

/// The published IRB 120 as the simulator's true robot, with its thermal drift (α = 23 ppm/K on
/// every link, ΔT∞ = `rise_k`, τ = 30 min) when `thermal`.
TrueRobot published_truth(bool thermal, double rise_k = 3, double expansion = 23e-6) {
  TrueRobot truth = published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
  truth.effects.thermal = thermal;
  truth.effects.temperature_rise_k = rise_k;
  truth.effects.expansion_per_kelvin = expansion;
  return truth;
}

/// The calibrated-model statement of the simulator's thermal drift: the same parameters and the
/// simulator's α as every link's expansion coefficient.
ParameterVector model_of(const TrueRobot& truth) {
  ParameterVector x = truth.robot.params;
  for (int link = 2; link <= kJointCount; ++link)
    x[expansion_param(link)] = truth.effects.expansion_per_kelvin;
  return x;
}

// The forward model at the thermometer's ΔT is the simulator's warm true robot (which scales its
// parameter vector's a_i, d_i) to rounding; at ΔT = 0 it is the cold robot whatever the
// coefficients.
TEST(Thermal, ForwardModelIsTheSimulatorsGrowth) {
  const TrueRobot truth = published_truth(true);
  const ParameterVector x = model_of(truth);
  auto rng = test::seeded_rng(2011);
  for (int k = 0; k < 20; ++k) {
    const Vector6d q = test::random_joints(truth.robot.model, rng);
    MotionState motion;
    motion.time_s = 300.0 * k;
    const double rise = temperature_rise(truth.effects, motion.time_s);
    const Pose<double> real = true_flange_pose(truth, q, motion);
    const Pose<double> model =
        flange_pose(truth.robot.model, truth.robot.tool.payload, x, q, {nullptr, rise});
    EXPECT_LT((real.p - model.p).norm(), 1e-9);
    EXPECT_LT((real.R - model.R).norm(), 1e-12);
    const Pose<double> cold = flange_pose(truth.robot.model, truth.robot.tool.payload, x, q);
    EXPECT_EQ(cold.p,
              flange_pose(truth.robot.model, truth.robot.tool.payload, truth.robot.params, q).p);
    if (k > 2) {
      EXPECT_GT((cold.p - model.p).norm(), 1e-3);  // the effect is there
    }
  }
}

// The analytic regressor at a temperature (warm lengths, chain rule to a_i, d_i and e_i) against
// autodiff of the templated forward model, every column, and the thermal group's and the lengths'
// columns against central differences, with compliance and backlash on.
TEST(Thermal, AnalyticColumnsMatchAutodiffAndFiniteDifferences) {
  auto rng = test::seeded_rng(2012);
  const Eigen::Vector3d target(80, 60, 120);
  std::uniform_real_distribution<double> coefficient(5e-6, 30e-6);
  for (const char* name : test::kRobots) {
    CalibratedRobot robot = test::random_calibrated(name, rng);
    for (int link = 2; link <= kJointCount; ++link)
      robot.params[expansion_param(link)] = coefficient(rng);
    robot.params[backlash_param(2)] = deg2rad(0.02);
    const Vector6d approach = (Vector6d() << 1, -1, 1, 0, 1, -1).finished();
    for (int k = 0; k < 6; ++k) {
      const Vector6d q = test::random_joints(robot.model, rng);
      const RowConditions row{&approach, -8.0 + 4.0 * k};
      Eigen::Vector3d p, p_ad;
      PositionJacobian J, J_ad;
      target_position_jacobian(robot.model, robot.tool.payload, robot.params, q, target, &p, &J,
                               row);
      target_position_jacobian_autodiff(robot.model, robot.tool.payload, robot.params, q, target,
                                        &p_ad, &J_ad, row);
      EXPECT_LT((p - p_ad).norm(), 1e-9) << name;
      for (int i = 0; i < kParameterCount; ++i)
        EXPECT_LT((J.col(i) - J_ad.col(i)).norm(), 1e-8 * (1 + J_ad.col(i).norm()))
            << name << " " << parameter_table()[i].name << " ΔT " << row.temperature_rise_k;
      for (int link = 2; link <= kJointCount; ++link)
        for (const int i : {expansion_param(link), link_param(link, 1), link_param(link, 3)}) {
          const double h = i >= kThermalOffset ? 1e-5 : 1e-4;  // rounding-limited below
          ParameterVector up = robot.params, down = robot.params;
          up[i] += h;
          down[i] -= h;
          const Eigen::Vector3d fd =
              (flange_pose(robot.model, robot.tool.payload, up, q, row) * target -
               flange_pose(robot.model, robot.tool.payload, down, q, row) * target) /
              (2 * h);
          EXPECT_LT((J.col(i) - fd).norm(), 1e-6 * (1 + fd.norm()))
              << name << " " << parameter_table()[i].name;
        }
      if (row.temperature_rise_k == 0) {
        EXPECT_EQ(J.middleCols<kThermalParamCount>(kThermalOffset).norm(), 0.0);
      }
    }
  }
}

// The calibrated chain at a target temperature equals the forward model there, and the
// calibrated IK solves it back; the compensation setup turns `--temperature-c` into the rise
// over the robot's reference and refuses an implausible one.
TEST(Thermal, CalibratedChainIkAndSetupTakeTheTemperature) {
  auto rng = test::seeded_rng(2013);
  for (const char* name : test::kRobots) {
    SCOPED_TRACE(name);
    CalibratedRobot robot = test::random_calibrated(name, rng);
    for (int link = 2; link <= kJointCount; ++link)
      robot.params[expansion_param(link)] = 20e-6 + 1e-6 * link;
    for (const double rise : {0.0, 15.0, -10.0}) {
      const Compensator comp = make_compensator(robot, std::nullopt, {nullptr, rise});
      EXPECT_EQ(comp.condition.temperature_rise_k, rise);
      for (int k = 0; k < 10; ++k) {
        const Vector6d q = test::random_joints(robot.model, rng);
        const Pose<double> got = calibrated_tcp_pose(comp.chain, q);
        const Pose<double> want =
            flange_pose(robot.model, robot.tool.payload, robot.params, q, {nullptr, rise}) *
            comp.flange_T_tcp;
        EXPECT_LT((got.p - want.p).norm(), 1e-9);
        EXPECT_LT((got.R - want.R).norm(), 1e-12);
      }
      const test::RoundTripStats st = test::round_trip(robot, comp, 5, 100'000, rng);
      EXPECT_TRUE(st.first_failure.empty()) << st.first_failure;
      EXPECT_LT(st.worst_mm, 1e-6);
    }
  }
  CompensationSetup setup;
  setup.robot = test::random_calibrated("abb-irb120", rng);
  setup.robot.model.reference_temperature_c = 22;
  setup.temperature_c = 31.5;
  EXPECT_EQ(prepare_compensation(setup).comp.condition.temperature_rise_k, 9.5);
  setup.temperature_c = 300;  // °F or K for °C
  EXPECT_REFUSED(prepare_compensation(setup), InputError, "--temperature-c");
}

// The `temperature` column: read in °C (no "not used" warning), an empty field is a row without
// a reading, written only when a row has one, round trip; bad values refused with file, line
// and column.
TEST(Thermal, MeasurementFileTemperatureColumn) {
  test::expect_optional_measurement_column("temperature", &PointMeasurement::temperature_c, "21.25",
                                           21.25, {"warm", "nan", "293.15"});
}

// The robot file's reference temperature: read, range-checked, written only when not 20 °C.
TEST(Thermal, RobotFileReferenceTemperature) {
  RobotModel model = load_robot("abb-irb120");
  EXPECT_EQ(model.reference_temperature_c, 20);
  EXPECT_EQ(robot_to_yaml(model).find("reference_temperature_c"), std::string::npos);
  model.reference_temperature_c = 23.5;
  const std::string text = robot_to_yaml(model);
  EXPECT_EQ(parse_robot(yaml::parse(text, "r.yaml")).reference_temperature_c, 23.5);
  std::string bad = text;
  bad.replace(bad.find("23.5"), 4, "296.65");
  EXPECT_REFUSED(parse_robot(yaml::parse(bad, "r.yaml")), InputError, "reference_temperature_c");
}

// --- Simulated true robots -------------------------------------------------------------------

using Campaign = test::GroupCampaign;

/// 100 calibration and 60 validation positions on the simulated IRB 120 (20 s apart, from a
/// cold start), laser tracker with σ = `noise_mm`.
Campaign simulate(const TrueRobot& truth, double noise_mm, uint64_t seed) {
  return test::simulate_campaign(truth, noise_mm, seed, published_joint_box(truth.robot.model));
}

const std::vector<std::string> kThermal{"*.expansion"};

IdentificationResult fit(const MeasurementSet& data, bool thermal) {
  return test::fit_full(data, thermal ? kThermal : std::vector<std::string>{});
}

// The simulated rows carry the arm's temperature: the reference plus the warm-up ΔT(t) at the
// row's time, t = 20 s per configuration (a whole number of them: the inverse of the warm-up
// gives it back), rising from the first row; a truth without drift writes none.
TEST(Thermal, SimulatedRowsRecordTheTemperature) {
  const TrueRobot truth = published_truth(true);
  const Campaign c = simulate(truth, 0.01, 2014);
  ASSERT_GT(c.calibration.points.size(), 90u);
  double previous = 0;
  for (const PointMeasurement& m : c.calibration.points) {
    ASSERT_TRUE(m.temperature_c.has_value());
    const double rise = *m.temperature_c - 20;
    const double t = -truth.effects.time_constant_s * std::log(1 - rise / 3);
    EXPECT_NEAR(t / 20, std::round(t / 20), 1e-6) << m.config;
    EXPECT_GE(rise, previous);
    previous = rise;
  }
  EXPECT_LT(*c.calibration.points.front().temperature_c, 20.2);  // from a cold start
  EXPECT_GT(previous, 1.5);  // 2000 s of a 30 min warm-up to 3 K
  for (const PointMeasurement& m : simulate(published_truth(false), 0.01, 2014).calibration.points)
    EXPECT_FALSE(m.temperature_c.has_value());
}

// The check: with a warming true robot (ΔT∞ = 10 K) the group brings the validation error
// to within 10 % of the effect-free case at the same noise; without it the error is clearly
// larger; the group significant. The links without length (2 and 5 of the IRB 120) are dropped
// by name.
TEST(Thermal, SimulatedDriftIdentifiedAndCompensated) {
  constexpr double kNoise = 0.01;
  const Campaign clean = simulate(published_truth(false), kNoise, 2015);
  const Campaign warm = simulate(published_truth(true, 10), kNoise, 2015);
  const test::GroupEffect effect = test::group_effect(clean, warm, kThermal);
  EXPECT_GT(effect.without_group, 1.3 * effect.free_of_effect);
  EXPECT_LT(effect.with_group, 1.10 * effect.free_of_effect);
  const IdentificationResult& with = effect.with;
  for (const int link : {2, 5}) {
    const auto i = static_cast<size_t>(expansion_param(link));
    EXPECT_EQ(with.robot.status[i], ParameterStatus::Dropped);
    EXPECT_NE(with.robot.reason[i].find("has no length"), std::string::npos)
        << with.robot.reason[i];
  }
  const GroupSignificance g = group_significance(with.robot)[13];
  EXPECT_EQ(g.group, "thermal");
  EXPECT_TRUE(g.enabled);
  EXPECT_EQ(g.identified, 3);
  EXPECT_TRUE(g.significant) << "W = " << g.wald;
}

// Seeded Monte Carlo: the coefficients of the links with length recovered within 3σ (σ as
// reported) in each of 5 simulated campaigns; the normalised errors' RMS near 1.
TEST(Thermal, MonteCarloRecoveryWithin3Sigma) {
  const TrueRobot truth = published_truth(true, 10);
  test::NormalisedErrors z;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    const IdentificationResult r = fit(simulate(truth, 0.01, 2020 + seed).calibration, true);
    for (const int link : {3, 4, 6})
      z.add(r, expansion_param(link), truth.effects.expansion_per_kelvin, seed);
  }
  const double rms_z = z.rms();
  const int count = z.count;
  std::printf("normalised expansion errors: RMS %.2f over %d estimates\n", rms_z, count);
  EXPECT_LT(rms_z, 1.8);
}

// Model-selection guard: on data of a warming arm that does not expand (the thermometer reads
// the warm-up, the links keep their length), enabling the group worsens the cross-validated error
// by less than 2 % and the group is reported not significant.
TEST(Thermal, GroupOnDataWithoutTheEffectIsHarmlessAndNotSignificant) {
  const Campaign clean = simulate(published_truth(true, 10, 0.0), 0.01, 2016);
  const auto [without, with_group] = test::cross_validated_cost(clean.calibration, kThermal);
  EXPECT_LT(with_group, 1.02 * without);
  const GroupSignificance g = group_significance(fit(clean.calibration, true).robot)[13];
  EXPECT_TRUE(g.enabled);
  EXPECT_EQ(g.identified, 3);
  EXPECT_FALSE(g.significant) << "W = " << g.wald << ", p = " << g.p_value;
}

// Identifiability: rows without a temperature, or all at one temperature, cannot tell the
// expansion from the lengths: dropped with the named reason (never "identified"), the rest fitted.
TEST(Thermal, DataWithoutTemperatureSpreadDropTheGroupWithTheReason) {
  Campaign c = simulate(published_truth(true), 0.01, 2017);
  MeasurementSet isothermal = c.calibration, unrecorded = c.calibration;
  for (PointMeasurement& m : isothermal.points) m.temperature_c = 21.5;
  for (PointMeasurement& m : unrecorded.points) m.temperature_c.reset();
  const std::pair<const MeasurementSet*, const char*> cases[] = {
      {&isothermal, "every row was measured at 21.5 °C"},
      {&unrecorded, "no row records a temperature"}};
  for (const auto& [data, why] : cases) {
    const IdentificationResult r = fit(*data, true);
    for (const int link : {3, 4, 6}) {
      const auto i = static_cast<size_t>(expansion_param(link));
      EXPECT_EQ(r.robot.status[i], ParameterStatus::Dropped);
      EXPECT_NE(r.robot.reason[i].find(why), std::string::npos) << r.robot.reason[i];
    }
    bool warned = false;
    for (const std::string& w : r.warnings) warned = warned || w.starts_with("link3.expansion");
    EXPECT_TRUE(warned);
    const GroupSignificance g = group_significance(r.robot)[13];
    EXPECT_TRUE(g.enabled);
    EXPECT_EQ(g.identified, 0);
    EXPECT_FALSE(g.significant);
    EXPECT_EQ(r.robot.status[static_cast<size_t>(link_param(3, 1))], ParameterStatus::Identified);
  }
}

}  // namespace
}  // namespace robcal
