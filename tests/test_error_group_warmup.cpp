// Thermal drift without a temperature (issue 19, docs/method/03-error-model.md §10): the warm-up
// group linkI.warmup_growth (mm of link growth at full warm-up) with the first-order warm-up
// φ(t) = 1 − exp(−t/τ) of each row's time. The forward model against the simulator's warming
// true robot, the analytic regressor's columns against autodiff and finite differences, the
// calibrated chain and compensation setup warm, the measurement file's `time_s` column, and on
// simulated true robots whose rows record only their time: the effect identified (validation
// error back to the effect-free figure, growths within 3σ), rows without times refused by name,
// and on data without the effect the group harmless and not significant.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "refusal.hpp"
#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/compensate/compensate_targets.hpp"
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

TEST(Warmup, NamesUnitsAndGroup) {
  EXPECT_EQ(kWarmupOffset, 97);
  EXPECT_EQ(kParameterCount, 104);  // the gravity group follows (§11)
  EXPECT_EQ(parameter_table()[warmup_param(2)].name, "link2.warmup_growth");
  EXPECT_EQ(parameter_table()[warmup_param(6)].unit, "mm");
  EXPECT_EQ(parameter_index("link3.warmup_growth"), warmup_param(3));
  const ParameterGroup& warmup = opt_in_groups()[opt_in_groups().size() - 2];  // before gravity
  EXPECT_EQ(warmup.name, "warmup");
  EXPECT_EQ(warmup.params, (std::vector<int>{97, 98, 99, 100, 101}));
  EXPECT_EQ(opt_in_group_parameters("warmup"), warmup.params);
  EXPECT_TRUE(is_opt_in(warmup_param(4)));
  EXPECT_EQ(RobotModel{}.warmup_time_constant_s, 1800);
}

/// The published IRB 120 as the simulator's true robot warming up by ΔT∞ = `rise_k` with τ = 30
/// min, its links expanding by `expansion` per kelvin, when `thermal`.
TrueRobot published_truth(bool thermal, double rise_k = 10, double expansion = 23e-6) {
  TrueRobot truth = published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
  truth.effects.thermal = thermal;
  truth.effects.temperature_rise_k = rise_k;
  truth.effects.expansion_per_kelvin = expansion;
  return truth;
}

/// The warm-up growth of link `link` the simulator's drift amounts to: its expansion coefficient
/// times ΔT∞ times the link's nominal length (mm).
double true_growth(const TrueRobot& truth, int link) {
  const MdhRow& row = truth.robot.model.mdh[static_cast<size_t>(link - 1)];
  return truth.effects.expansion_per_kelvin * truth.effects.temperature_rise_k *
         std::hypot(row.a, row.d);
}

ParameterVector model_of(const TrueRobot& truth) {
  ParameterVector x = truth.robot.params;
  for (int link = 2; link <= kJointCount; ++link) x[warmup_param(link)] = true_growth(truth, link);
  return x;
}

// The forward model at a row's warm-up φ(t) is the simulator's warming true robot at time t
// (which scales its a_i, d_i by 1 + α·ΔT∞·φ) to rounding; cold (φ = 0) it is the cold robot.
// Links 2 and 5 of the IRB 120 have no nominal length, so the model does not expand them: their
// published sub-millimetre a, d are zeroed here (they grow by 3e-5 mm at most in the truth).
TEST(Warmup, ForwardModelIsTheSimulatorsWarmUp) {
  TrueRobot truth = published_truth(true);
  for (const int link : {2, 5})
    for (const int k : {1, 3}) truth.robot.params[link_param(link, k)] = 0;
  const ParameterVector x = model_of(truth);
  auto rng = test::seeded_rng(2111);
  for (int k = 0; k < 20; ++k) {
    const Vector6d q = test::random_joints(truth.robot.model, rng);
    MotionState motion;
    motion.time_s = 300.0 * k;
    const RowConditions row{nullptr, 0, warmup_fraction(truth.robot.model, motion.time_s)};
    const Pose<double> real = true_flange_pose(truth, q, motion);
    const Pose<double> model = flange_pose(truth.robot.model, truth.robot.tool.payload, x, q, row);
    EXPECT_LT((real.p - model.p).norm(), 1e-9);
    EXPECT_LT((real.R - model.R).norm(), 1e-12);
    const Pose<double> cold = flange_pose(truth.robot.model, truth.robot.tool.payload, x, q);
    if (k > 2) {
      EXPECT_GT((cold.p - model.p).norm(), 1e-2);  // the effect is there: ~0.1 mm warm
    }
  }
}

// The analytic regressor warm (chain rule from the warm lengths to a_i, d_i and w_i) against
// autodiff of the templated forward model, every column, and the growths' columns against
// central differences; cold, the growths' columns are zero.
TEST(Warmup, AnalyticColumnsMatchAutodiffAndFiniteDifferences) {
  auto rng = test::seeded_rng(2112);
  const Eigen::Vector3d target(80, 60, 120);
  std::uniform_real_distribution<double> growth(0.02, 0.2);
  for (const char* name : test::kRobots) {
    CalibratedRobot robot = test::random_calibrated(name, rng);
    for (int link = 2; link <= kJointCount; ++link) {
      robot.params[warmup_param(link)] = growth(rng);
      robot.params[expansion_param(link)] = 10e-6;
    }
    for (int k = 0; k < 6; ++k) {
      const Vector6d q = test::random_joints(robot.model, rng);
      const RowConditions row{nullptr, k == 1 ? 4.0 : 0.0, k == 0 ? 0.0 : 0.2 * k - 0.1};
      Eigen::Vector3d p, p_ad;
      PositionJacobian J, J_ad;
      target_position_jacobian(robot.model, robot.tool.payload, robot.params, q, target, &p, &J,
                               row);
      target_position_jacobian_autodiff(robot.model, robot.tool.payload, robot.params, q, target,
                                        &p_ad, &J_ad, row);
      EXPECT_LT((p - p_ad).norm(), 1e-9) << name;
      for (int i = 0; i < kParameterCount; ++i)
        EXPECT_LT((J.col(i) - J_ad.col(i)).norm(), 1e-8 * (1 + J_ad.col(i).norm()))
            << name << " " << parameter_table()[i].name << " φ " << row.warmup_fraction;
      for (int link = 2; link <= kJointCount; ++link) {
        const int i = warmup_param(link);
        const double h = 1e-4;
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
      if (row.warmup_fraction == 0) {
        EXPECT_EQ(J.middleCols<kThermalParamCount>(kWarmupOffset).norm(), 0.0);
      }
    }
  }
}

// The calibrated chain warm equals the forward model warm; the compensation setup turns
// `--warmup-time-s` into φ with the model's τ, `--warm` into 1, and refuses both together or a
// negative time.
TEST(Warmup, CalibratedChainAndSetupTakeTheWarmUp) {
  auto rng = test::seeded_rng(2113);
  CalibratedRobot robot = test::random_calibrated("abb-irb120", rng);
  for (int link = 2; link <= kJointCount; ++link) robot.params[warmup_param(link)] = 0.1;
  for (const double phi : {0.0, 0.5, 1.0}) {
    const Compensator comp = make_compensator(robot, std::nullopt, {nullptr, 0, phi});
    EXPECT_EQ(comp.condition.warmup_fraction, phi);
    for (int k = 0; k < 10; ++k) {
      const Vector6d q = test::random_joints(robot.model, rng);
      const Pose<double> got = calibrated_tcp_pose(comp.chain, q);
      const Pose<double> want =
          flange_pose(robot.model, robot.tool.payload, robot.params, q, {nullptr, 0, phi}) *
          comp.flange_T_tcp;
      EXPECT_LT((got.p - want.p).norm(), 1e-9);
    }
    const test::RoundTripStats st = test::round_trip(robot, comp, 5, 100'000, rng);
    EXPECT_TRUE(st.first_failure.empty()) << st.first_failure;
    EXPECT_LT(st.worst_mm, 1e-6);
  }
  CompensationSetup setup;
  setup.robot = robot;
  setup.robot.model.warmup_time_constant_s = 1200;
  setup.warmup_time_s = 1200;
  EXPECT_NEAR(prepare_compensation(setup).comp.condition.warmup_fraction, 1 - std::exp(-1.0),
              1e-15);
  setup.warmup_time_s.reset();
  setup.warm = true;
  EXPECT_EQ(prepare_compensation(setup).comp.condition.warmup_fraction, 1.0);
  setup.warmup_time_s = 600;
  EXPECT_REFUSED(prepare_compensation(setup), InputError,
                 "give either the warm-up time or --warm, not both");
  setup.warm = false;
  setup.warmup_time_s = -5;
  EXPECT_REFUSED(prepare_compensation(setup), InputError, "--warmup-time-s");
}

// The `time_s` column: read in seconds (no "not used" warning), an empty field is a row without a
// time, written only when a row has one, round trip; bad values refused with file, line, column.
TEST(Warmup, MeasurementFileTimeColumn) {
  test::expect_optional_measurement_column("time_s", &PointMeasurement::time_s, "125.5", 125.5,
                                           {"soon", "-3", "2e8"});
}

// --- Simulated true robots -------------------------------------------------------------------

using Campaign = test::GroupCampaign;

/// 100 calibration and 60 validation positions on the simulated IRB 120 (20 s apart, from a
/// cold start), laser tracker with σ = 0.01 mm; the rows record their time, not a temperature.
Campaign simulate(const TrueRobot& truth, uint64_t seed) {
  SimulationOptions sim;
  sim.record_time = true;
  return test::simulate_campaign(truth, 0.01, seed, published_joint_box(truth.robot.model), sim);
}

const std::vector<std::string> kWarmup{"warmup"};

const GroupSignificance& warmup_group(const std::vector<GroupSignificance>& groups) {
  const GroupSignificance& warmup = groups[groups.size() - 2];  // the gravity group follows
  EXPECT_EQ(warmup.group, "warmup");
  return warmup;
}

// The simulated rows carry their time (20 s per configuration from a cold start) and no
// temperature.
TEST(Warmup, SimulatedRowsRecordTheirTime) {
  const Campaign c = simulate(published_truth(true), 2114);
  ASSERT_GT(c.calibration.points.size(), 90u);
  for (const PointMeasurement& m : c.calibration.points) {
    ASSERT_TRUE(m.time_s.has_value());
    EXPECT_FALSE(m.temperature_c.has_value());
    EXPECT_NEAR(*m.time_s / 20, std::round(*m.time_s / 20), 1e-9) << m.config;
  }
  EXPECT_EQ(*c.calibration.points.front().time_s, 0);
}

// The check: with a warming true robot (ΔT∞ = 10 K, 23 ppm/K) whose rows record only
// their time, the group brings the validation error to within 10 % of the effect-free case at
// the same noise; without it the error is clearly larger; the group significant; the links
// without length (2 and 5 of the IRB 120) dropped by name.
TEST(Warmup, SimulatedWarmUpIdentifiedAndCompensated) {
  const Campaign clean = simulate(published_truth(false), 2115);
  const Campaign warm = simulate(published_truth(true), 2115);
  const test::GroupEffect effect = test::group_effect(clean, warm, kWarmup);
  EXPECT_GT(effect.without_group, 1.3 * effect.free_of_effect);
  EXPECT_LT(effect.with_group, 1.10 * effect.free_of_effect);
  const IdentificationResult& with = effect.with;
  for (const int link : {2, 5}) {
    const auto i = static_cast<size_t>(warmup_param(link));
    EXPECT_EQ(with.robot.status[i], ParameterStatus::Dropped);
    EXPECT_NE(with.robot.reason[i].find("has no length"), std::string::npos)
        << with.robot.reason[i];
  }
  const GroupSignificance& g = warmup_group(group_significance(with.robot));
  EXPECT_TRUE(g.enabled);
  EXPECT_EQ(g.identified, 3);
  EXPECT_TRUE(g.significant) << "W = " << g.wald;
}

// A targets file's rows at their own time (`time_s` column, docs/method/10-compensation.md §6):
// the warming IRB 120 calibrated with the group from rows that record their time; 48 wanted
// poses, each the true TCP at random joints at one of six times from cold to fully warm. Each
// compensated at its own time reaches its pose on the true robot at that time to the noise floor
// (by hand, and the closed-loop check agrees); the same targets at the run's one time (30 min,
// the time constant) miss by the warm-up the run's time gets wrong.
TEST(Warmup, TargetsCompensatedAtTheirOwnTime) {
  const TrueRobot truth = published_truth(true);
  const IdentificationResult fit = test::fit_full(simulate(truth, 2119).calibration, kWarmup);
  const CalibratedRobot& robot = fit.robot;
  for (const int link : {3, 4, 6})
    ASSERT_EQ(robot.status[static_cast<size_t>(warmup_param(link))], ParameterStatus::Identified);
  const auto box = published_joint_box(truth.robot.model);
  Pose<double> flange_T_tcp;
  flange_T_tcp.R = truth.robot.tool.flange_T_tcp.linear();
  flange_T_tcp.p = truth.robot.tool.flange_T_tcp.translation();
  const double kTimes[] = {0, 300, 900, 1800, 3600, 14400};
  std::mt19937_64 rng(2122);
  std::vector<WantedTarget> wanted;
  while (wanted.size() < 48) {
    Vector6d j;
    for (int i = 0; i < kJointCount; ++i)
      j[i] = std::uniform_real_distribution<double>(box[i].lower + deg2rad(3),
                                                    box[i].upper - deg2rad(3))(rng);
    if (test::near_singular(truth.robot.model, j, 10)) continue;
    MotionState at;
    at.time_s = kTimes[wanted.size() % 6];
    WantedTarget w;
    w.name = "t" + std::to_string(wanted.size());
    w.line = static_cast<int>(wanted.size()) + 2;
    w.world_T_tcp = true_flange_pose(truth, j, at) * flange_T_tcp;
    w.config = arm_config(truth.robot.model, j);
    w.time_s = at.time_s;
    wanted.push_back(w);
  }
  // Mean and largest distance (mm) of the true TCP, at each target's own time, from its pose.
  const auto true_errors_mm = [&](const CompensateTargetsResult& r) {
    double sum = 0, worst = 0;
    for (size_t i = 0; i < r.rows.size(); ++i) {
      MotionState at;
      at.time_s = *wanted[i].time_s;
      const Pose<double> reached = true_flange_pose(truth, r.rows[i].ik.joints, at) * flange_T_tcp;
      const double e = (reached.p - wanted[i].world_T_tcp.p).norm();
      sum += e;
      worst = std::max(worst, e);
    }
    return std::pair{sum / static_cast<double>(r.rows.size()), worst};
  };

  CompensateTargetsRequest request;
  request.setup.robot = robot;
  request.setup.warmup_time_s = 1800;  // the run's, which every row overrides
  request.targets = wanted;
  request.truth = truth;
  const CompensateTargetsResult own = compensate_targets(request);
  ASSERT_EQ(own.rows.size(), wanted.size());
  EXPECT_EQ(own.conditions, 6);
  for (size_t i = 0; i < own.rows.size(); ++i) {
    ASSERT_TRUE(own.rows[i].ik.ok()) << own.rows[i].name;
    EXPECT_EQ(own.rows[i].condition.warmup_time_s, wanted[i].time_s);
    EXPECT_EQ(own.rows[i].condition.warmup_fraction,
              warmup_fraction(robot.model, *wanted[i].time_s));
  }
  const auto [own_mean, own_max] = true_errors_mm(own);
  ASSERT_TRUE(own.closed_loop);
  EXPECT_NEAR(own.closed_loop->compensated.mean_mm, own_mean, 1e-12);
  EXPECT_NEAR(own.closed_loop->compensated.max_mm, own_max, 1e-12);
  // The corrected CSV records each row's time.
  EXPECT_NE(own.csv.find(",approach,temperature,payload,time_s\n"), std::string::npos);
  EXPECT_NE(own.csv.find(",++++++,20,,14400\n"), std::string::npos) << own.csv;

  request.targets = wanted;
  for (WantedTarget& w : request.targets) w.time_s.reset();
  const CompensateTargetsResult run = compensate_targets(request);
  EXPECT_EQ(run.conditions, 1);
  const auto [run_mean, run_max] = true_errors_mm(run);
  request.setup.warmup_time_s.reset();
  request.setup.warm = true;
  const auto [warm_mean, warm_max] = true_errors_mm(compensate_targets(request));
  std::printf(
      "true TCP error at each target's time (mean / max mm), 48 targets at 0 s to 4 h: each "
      "compensated at its own time %.4f / %.4f; at the run's 1800 s %.4f / %.4f; warm %.4f / "
      "%.4f; uncompensated %.4f / %.4f\n",
      own_mean, own_max, run_mean, run_max, warm_mean, warm_max,
      own.closed_loop->uncompensated.mean_mm, own.closed_loop->uncompensated.max_mm);
  // Measured: 0.0087 / 0.016 mm each at its own time; 0.034 / 0.095 at the run's 1800 s;
  // 0.052 / 0.15 warm.
  EXPECT_LT(own_mean, 0.012);  // the noise propagated through the fit (σ = 0.01 mm)
  EXPECT_LT(own_max, 0.03);
  EXPECT_GT(run_mean, 3 * own_mean);
  EXPECT_GT(run_max, 0.06);
  EXPECT_GT(warm_mean, 5 * own_mean);
}

// Seeded Monte Carlo: the growths of the links with length recovered within 3σ (σ as reported)
// in each of 4 simulated campaigns; the normalised errors' RMS near 1.
TEST(Warmup, MonteCarloRecoveryWithin3Sigma) {
  const TrueRobot truth = published_truth(true);
  test::NormalisedErrors z;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const IdentificationResult r =
        test::fit_full(simulate(truth, 2120 + seed).calibration, kWarmup);
    for (const int link : {3, 4, 6}) {
      const double sigma = z.add(r, warmup_param(link), true_growth(truth, link), seed);
      std::printf("seed %d link%d.warmup_growth %.4f ± %.4f mm (true %.4f)\n",
                  static_cast<int>(seed), link, r.robot.params[warmup_param(link)], sigma,
                  true_growth(truth, link));
    }
  }
  std::printf("normalised warm-up growth errors: RMS %.2f over %d estimates\n", z.rms(), z.count);
  EXPECT_LT(z.rms(), 1.8);
}

// An independent statement of the same fit: the campaign measured with a thermometer and
// identified with the thermal group (§8) gives e_i, and w_i = e_i·ΔT∞·L_i since ΔT = ΔT∞·φ(t)
// with the truth's ΔT∞ and τ: the two fits are one reparameterised, estimates and σ alike.
TEST(Warmup, SameFitAsTheThermalGroupWithAThermometer) {
  const TrueRobot truth = published_truth(true);
  const Campaign timed = simulate(truth, 2118);
  const Campaign measured =
      test::simulate_campaign(truth, 0.01, 2118, published_joint_box(truth.robot.model));
  const IdentificationResult warmup = test::fit_full(timed.calibration, kWarmup);
  const IdentificationResult thermal = test::fit_full(measured.calibration, {"thermal"});
  for (const int link : {3, 4, 6}) {
    const MdhRow& row = truth.robot.model.mdh[static_cast<size_t>(link - 1)];
    const double per_expansion = truth.effects.temperature_rise_k * std::hypot(row.a, row.d);
    const int w = warmup_param(link), e = expansion_param(link);
    EXPECT_NEAR(warmup.robot.params[w], thermal.robot.params[e] * per_expansion, 1e-6)
        << "link " << link;
    EXPECT_NEAR(std::sqrt(warmup.robot.covariance(w, w)),
                std::sqrt(thermal.robot.covariance(e, e)) * per_expansion, 1e-6)
        << "link " << link;
  }
}

// Model-selection guard: on rows with times of an arm that does not expand, enabling the group
// worsens the cross-validated error by less than 2 % and the group is reported not significant.
TEST(Warmup, GroupOnDataWithoutTheEffectIsHarmlessAndNotSignificant) {
  const Campaign clean = simulate(published_truth(true, 10, 0.0), 2116);
  const auto [without, with_group] = test::cross_validated_cost(clean.calibration, kWarmup);
  EXPECT_LT(with_group, 1.02 * without);
  const GroupSignificance& g =
      warmup_group(group_significance(test::fit_full(clean.calibration, kWarmup).robot));
  EXPECT_TRUE(g.enabled);
  EXPECT_EQ(g.identified, 3);
  EXPECT_FALSE(g.significant) << "W = " << g.wald << ", p = " << g.p_value;
}

// Rows without times, or all at one time, cannot tell the growth from the lengths: dropped with
// the named reason (never "identified"); the time constant option is range-checked.
TEST(Warmup, DataWithoutTimeSpreadDropTheGroupWithTheReason) {
  const Campaign c = simulate(published_truth(true), 2117);
  MeasurementSet at_once = c.calibration, untimed = c.calibration;
  for (PointMeasurement& m : at_once.points) m.time_s = 600;
  for (PointMeasurement& m : untimed.points) m.time_s.reset();
  const std::pair<const MeasurementSet*, const char*> cases[] = {
      {&at_once, "every row was measured at 600 s"}, {&untimed, "no row records a time"}};
  for (const auto& [data, why] : cases) {
    const IdentificationResult r = test::fit_full(*data, kWarmup);
    for (const int link : {3, 4, 6}) {
      const auto i = static_cast<size_t>(warmup_param(link));
      EXPECT_EQ(r.robot.status[i], ParameterStatus::Dropped);
      EXPECT_NE(r.robot.reason[i].find(why), std::string::npos) << r.robot.reason[i];
    }
  }
  IdentifyOptions options;
  options.identify = kWarmup;
  options.warmup_time_constant_s = 0.5;
  EXPECT_REFUSED(
      calibrate(load_robot("abb-irb120"), default_simulation_tool(), c.calibration, options),
      InputError, "warm-up time constant 0.5 s: expected seconds in [1, 1e6]");
  // The time constant given is the one the calibrated model keeps for compensation.
  options.warmup_time_constant_s = 2400;
  EXPECT_EQ(calibrate(load_robot("abb-irb120"), default_simulation_tool(), c.calibration, options)
                .robot.model.warmup_time_constant_s,
            2400);
}

}  // namespace
}  // namespace robcal
