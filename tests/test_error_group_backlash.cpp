// Joint backlash (issue 19, docs/method/03-error-model.md §6): the forward model against the
// simulator's true robot (an independent statement of the same dead band), the analytic
// regressor's backlash columns against autodiff and finite differences, the calibrated chain and
// IK with an approach, the measurement file's `approach` column, and on simulated true robots:
// the effect identified (validation error back to the effect-free figure, dead bands within 3σ),
// one-sided data refused by name, and on data without backlash the group harmless and not
// significant.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "refusal.hpp"
#include "robcal/compensate/calibrated_ik.hpp"
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

TEST(Backlash, NamesUnitsAndGroups) {
  EXPECT_EQ(parameter_table()[backlash_param(1)].name, "joint1.backlash");
  EXPECT_EQ(parameter_table()[backlash_param(6)].unit, "deg");
  EXPECT_EQ(parameter_index("joint4.backlash"), backlash_param(4));
  EXPECT_EQ(match_parameters("*.backlash").size(), 6u);
  EXPECT_TRUE(is_opt_in(backlash_param(3)));
  for (int i : level_parameters(CalibrationLevel::Full)) EXPECT_NE(i, backlash_param(2));
  const auto& groups = opt_in_groups();
  ASSERT_EQ(groups.size(),
            22u);  // periodic, backlash, joint1.compliance, thermal, motor, warmup, gravity
  EXPECT_EQ(groups[6].name, "joint1.backlash");
  EXPECT_EQ(groups[11].params, std::vector<int>{backlash_param(6)});
}

/// The published IRB 120 as the simulator's true robot, with the simulator's dead bands
/// (0.01° on joints 1–3, 0.015° on 4–6) when `backlash`.
TrueRobot published_truth(bool backlash) {
  TrueRobot truth = published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
  truth.effects.backlash = backlash;
  return truth;
}

/// The calibrated-model statement of a true robot with backlash: the same parameters, each
/// joint's zero moved to the middle of its dead band (θ0 + b/2: the true joint sits at θ0 from
/// below and θ0 + b from above) and the dead bands b.
ParameterVector model_of(const TrueRobot& truth) {
  ParameterVector x = truth.robot.params;
  for (int joint = 1; joint <= kJointCount; ++joint) {
    const double b = deg2rad(truth.effects.backlash_deg[static_cast<size_t>(joint - 1)]);
    x[backlash_param(joint)] = b;
    x[joint == 1 ? 5 : link_param(joint, 2)] += b / 2;
  }
  return x;
}

// The forward model with the dead bands and each joint's side is the simulator's true robot
// (which shifts a joint approached from above by b, from below not at all): to rounding, for
// random configurations and sides.
TEST(Backlash, ForwardModelIsTheSimulatorsDeadBand) {
  const TrueRobot truth = published_truth(true);
  const ParameterVector x = model_of(truth);
  auto rng = test::seeded_rng(1931);
  std::uniform_int_distribution<int> side(0, 1);
  for (int k = 0; k < 20; ++k) {
    const Vector6d q = test::random_joints(truth.robot.model, rng);
    Vector6d approach;
    for (int j = 0; j < kJointCount; ++j) approach[j] = side(rng) ? 1.0 : -1.0;
    MotionState motion;
    motion.from_below = false;
    motion.previous_joints = q - deg2rad(5.0) * approach;
    const Pose<double> real = true_flange_pose(truth, q, motion);
    const Pose<double> model =
        flange_pose(truth.robot.model, truth.robot.tool.payload, x, q, {&approach});
    EXPECT_LT((real.p - model.p).norm(), 1e-9);
    EXPECT_LT((real.R - model.R).norm(), 1e-12);
    // The effect is there: from the other side the flange moves by the dead bands.
    const Vector6d other = -approach;
    EXPECT_GT((flange_pose(truth.robot.model, truth.robot.tool.payload, x, q, {&other}).p - model.p)
                  .norm(),
              1e-3);
  }
  // Unknown side (0): the middle of the band, half-way between the two sides' joint angles.
  const Vector6d q = test::random_joints(truth.robot.model, rng);
  const Vector6d below = Vector6d::Ones(), unknown = Vector6d::Zero();
  ParameterVector middle = x;
  middle.segment<kJointCount>(kBacklashOffset).setZero();
  const Pose<double> mid =
      flange_pose(truth.robot.model, truth.robot.tool.payload, x, q, {&unknown});
  EXPECT_LT((mid.p - flange_pose(truth.robot.model, truth.robot.tool.payload, middle, q).p).norm(),
            1e-12);
  // No approach given: from below.
  EXPECT_EQ(flange_pose(truth.robot.model, truth.robot.tool.payload, x, q).p,
            flange_pose(truth.robot.model, truth.robot.tool.payload, x, q, {&below}).p);
}

// The analytic regressor's backlash columns (the joint column times −s/2) against autodiff of the
// templated forward model and central differences, every side including unknown, on robots with
// and without a joint map that reverses joints.
TEST(Backlash, AnalyticColumnsMatchAutodiffAndFiniteDifferences) {
  auto rng = test::seeded_rng(1932);
  const Eigen::Vector3d target(80, 60, 120);
  for (const char* name : test::kRobots) {
    CalibratedRobot robot = test::random_calibrated(name, rng);
    for (int joint = 1; joint <= kJointCount; ++joint)
      robot.params[backlash_param(joint)] = deg2rad(0.02);
    for (int k = 0; k < 10; ++k) {
      const Vector6d q = test::random_joints(robot.model, rng);
      Vector6d approach;
      for (int j = 0; j < kJointCount; ++j) approach[j] = static_cast<double>((k + j) % 3 - 1);
      Eigen::Vector3d p, p_ad;
      PositionJacobian J, J_ad;
      target_position_jacobian(robot.model, robot.tool.payload, robot.params, q, target, &p, &J,
                               {&approach});
      target_position_jacobian_autodiff(robot.model, robot.tool.payload, robot.params, q, target,
                                        &p_ad, &J_ad, {&approach});
      EXPECT_LT((p - p_ad).norm(), 1e-9) << name;
      for (int joint = 1; joint <= kJointCount; ++joint) {
        const int i = backlash_param(joint);
        EXPECT_LT((J.col(i) - J_ad.col(i)).norm(), 1e-8 * (1 + J_ad.col(i).norm()))
            << name << " " << parameter_table()[i].name;
        constexpr double h = 1e-6;
        ParameterVector up = robot.params, down = robot.params;
        up[i] += h;
        down[i] -= h;
        const Eigen::Vector3d fd =
            (flange_pose(robot.model, robot.tool.payload, up, q, {&approach}) * target -
             flange_pose(robot.model, robot.tool.payload, down, q, {&approach}) * target) /
            (2 * h);
        EXPECT_LT((J.col(i) - fd).norm(), 1e-5 * (1 + fd.norm()))
            << name << " " << parameter_table()[i].name;
        if (approach[joint - 1] == 0) {
          EXPECT_EQ(J.col(i).norm(), 0.0);
        }
      }
    }
  }
}

// The calibrated chain of a target approach equals the forward model with that approach, and the
// calibrated IK solves it back; the default is from below.
TEST(Backlash, CalibratedChainAndIkTakeTheApproach) {
  auto rng = test::seeded_rng(1933);
  for (const char* name : test::kRobots) {
    SCOPED_TRACE(name);
    CalibratedRobot robot = test::random_calibrated(name, rng);
    for (int joint = 1; joint <= kJointCount; ++joint)
      robot.params[backlash_param(joint)] = deg2rad(0.01 * joint);
    const Vector6d above = -Vector6d::Ones();
    const Vector6d mixed = (Vector6d() << 1, -1, 1, -1, 0, 1).finished();
    for (const Vector6d* approach : {static_cast<const Vector6d*>(nullptr), &above, &mixed}) {
      const Compensator comp = make_compensator(robot, std::nullopt, {approach});
      for (int k = 0; k < 10; ++k) {
        const Vector6d q = test::random_joints(robot.model, rng);
        const Pose<double> got = calibrated_tcp_pose(comp.chain, q);
        const Pose<double> want =
            flange_pose(robot.model, robot.tool.payload, robot.params, q, {approach}) *
            comp.flange_T_tcp;
        EXPECT_LT((got.p - want.p).norm(), 1e-9);
        EXPECT_LT((got.R - want.R).norm(), 1e-12);
      }
      const test::RoundTripStats st = test::round_trip(robot, comp, 5, 100'000, rng);
      EXPECT_TRUE(st.first_failure.empty()) << st.first_failure;
      EXPECT_LT(st.worst_mm, 1e-6);
    }
  }
}

// The `approach` column: read per joint, written only when some row is not from below on every
// joint, round trip; bad values refused with file, line and column.
TEST(Backlash, MeasurementFileApproachColumn) {
  const Tool tool = default_simulation_tool();
  const std::string text =
      "config,target,j1,j2,j3,j4,j5,j6,x,y,z,approach\n"
      "c1,1,0,10,20,30,40,50,100,200,300,++-+0-\n"
      "c2,1,5,10,20,30,40,50,100,200,301,++++++\n";
  const MeasurementFile file = parse_measurements_csv(text, "m.csv", tool);
  EXPECT_TRUE(file.warnings.empty());
  const MeasurementSet& set = file.measurements;
  ASSERT_EQ(set.points.size(), 2u);
  EXPECT_EQ(set.points[0].approach, (Vector6d() << 1, 1, -1, 1, 0, -1).finished());
  EXPECT_EQ(set.points[1].approach, Vector6d::Ones());
  const std::string written = write_measurements_csv(set, tool);
  EXPECT_NE(written.find(",approach\n"), std::string::npos) << written;
  const MeasurementSet back = parse_measurements_csv(written, "w.csv", tool).measurements;
  EXPECT_EQ(back.points[0].approach, set.points[0].approach);
  MeasurementSet below = set;
  below.points.pop_back();
  below.points[0].approach = Vector6d::Ones();
  EXPECT_EQ(write_measurements_csv(below, tool).find("approach"), std::string::npos);
  // Without the column, every joint from below.
  EXPECT_EQ(parse_measurements_csv("config,target,j1,j2,j3,j4,j5,j6,x,y,z\nc,1,0,1,2,3,4,5,1,2,3\n",
                                   "n.csv", tool)
                .measurements.points[0]
                .approach,
            Vector6d::Ones());
  for (const char* bad : {"++-+0", "++-+0-+", "++x+++", "", "+1-+++"})
    EXPECT_REFUSED(
        parse_measurements_csv(fmt::format("config,target,j1,j2,j3,j4,j5,j6,x,y,z,approach\n"
                                           "c1,1,0,10,20,30,40,50,100,200,300,{}\n",
                                           bad),
                               "m.csv", tool),
        InputError, "m.csv:2:12 (approach): '");
  EXPECT_REFUSED(parse_approach("++", {"", 0, 0, "--approach"}), InputError,
                 "expected six characters, one per joint");
}

// --- Simulated true robots -------------------------------------------------------------------

using Campaign = test::GroupCampaign;

/// 100 calibration and 60 validation positions on the simulated IRB 120, laser tracker with
/// σ = `noise_mm`; every joint approached from a random side (seeded) when `both_sides`, else
/// from below.
Campaign simulate(const TrueRobot& truth, double noise_mm, uint64_t seed, bool both_sides = true) {
  SimulationOptions sim;
  sim.approach_random = both_sides;
  sim.approach_seed = seed + 100;
  return test::simulate_campaign(truth, noise_mm, seed, published_joint_box(truth.robot.model),
                                 sim);
}

IdentificationResult fit(const MeasurementSet& data, bool backlash) {
  return test::fit_full(
      data, backlash ? std::vector<std::string>{"*.backlash"} : std::vector<std::string>{});
}

// The simulated rows record the side the simulated program used: random sides give both on every
// joint; the straight sequence records the direction of each move.
TEST(Backlash, SimulatedRowsRecordTheApproach) {
  const TrueRobot truth = published_truth(true);
  const Campaign c = simulate(truth, 0.01, 1934);
  for (int j = 0; j < kJointCount; ++j) {
    int above = 0;
    for (const PointMeasurement& m : c.calibration.points) above += m.approach[j] < 0 ? 1 : 0;
    EXPECT_GT(above, 20) << "joint " << j + 1;
    EXPECT_LT(above, 80) << "joint " << j + 1;
  }
  for (const PointMeasurement& m : simulate(truth, 0.01, 1934, false).calibration.points)
    EXPECT_EQ(m.approach, Vector6d::Ones());
}

// The check: with backlash in the true robot and data from both sides, the group brings
// the validation error to within 10 % of the effect-free case at the same noise; without it the
// error is today's (clearly larger); every group significant.
TEST(Backlash, SimulatedBacklashIdentifiedAndCompensated) {
  constexpr double kNoise = 0.01;
  const Campaign clean = simulate(published_truth(false), kNoise, 1935);
  const Campaign worn = simulate(published_truth(true), kNoise, 1935);
  const test::GroupEffect effect = test::group_effect(clean, worn, {"*.backlash"});
  const double free_of_effect = effect.free_of_effect, today = effect.without_group,
               enabled = effect.with_group;
  const IdentificationResult& with = effect.with;
  EXPECT_GT(today, 1.3 * free_of_effect);
  EXPECT_LT(enabled, 1.10 * free_of_effect);
  const auto groups = group_significance(with.robot);
  for (int joint = 1; joint <= kJointCount; ++joint) {
    const GroupSignificance& g = groups[static_cast<size_t>(5 + joint)];
    EXPECT_EQ(g.group, fmt::format("joint{}.backlash", joint));
    EXPECT_TRUE(g.enabled);
    EXPECT_EQ(g.identified, 1);
    EXPECT_TRUE(g.significant) << g.group << " W = " << g.wald;
  }
}

// Seeded Monte Carlo: every dead band recovered within 3σ (σ as reported) in each of 5 simulated
// campaigns; the normalised errors' RMS near 1 says the σ are honest.
TEST(Backlash, MonteCarloRecoveryWithin3Sigma) {
  const TrueRobot truth = published_truth(true);
  test::NormalisedErrors z;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    const IdentificationResult r = fit(simulate(truth, 0.01, 1940 + seed).calibration, true);
    for (int joint = 1; joint <= kJointCount; ++joint) {
      const double b = deg2rad(truth.effects.backlash_deg[static_cast<size_t>(joint - 1)]);
      const double sigma = z.add(r, backlash_param(joint), b, seed);
      EXPECT_LT(sigma, b / 3) << "joint " << joint;  // clearly resolved
    }
  }
  const double rms_z = z.rms();
  const int count = z.count;
  std::printf("normalised backlash errors: RMS %.2f over %d estimates\n", rms_z, count);
  EXPECT_LT(rms_z, 1.8);
}

// Model-selection guard: on data without backlash (from both sides), enabling the group worsens
// the cross-validated error by less than 2 % and no joint's group is reported significant.
TEST(Backlash, GroupOnDataWithoutTheEffectIsHarmlessAndNotSignificant) {
  const Campaign clean = simulate(published_truth(false), 0.01, 1936);
  const auto [without, with_group] = test::cross_validated_cost(clean.calibration, {"*.backlash"});
  EXPECT_LT(with_group, 1.02 * without);
  const auto groups = group_significance(fit(clean.calibration, true).robot);
  for (int joint = 1; joint <= kJointCount; ++joint) {
    const GroupSignificance& g = groups[static_cast<size_t>(5 + joint)];
    EXPECT_TRUE(g.enabled);
    EXPECT_FALSE(g.significant) << g.group << " W = " << g.wald << ", p = " << g.p_value;
  }
}

// Identifiability: rows all approached from below only shift each joint's zero, so the dead band
// is dropped with its named reason (never "identified") and the rest is fitted.
TEST(Backlash, OneSidedDataDropTheGroupWithTheReason) {
  const Campaign below = simulate(published_truth(true), 0.01, 1937, false);
  const IdentificationResult r = fit(below.calibration, true);
  for (int joint = 1; joint <= kJointCount; ++joint) {
    const auto i = static_cast<size_t>(backlash_param(joint));
    EXPECT_EQ(r.robot.status[i], ParameterStatus::Dropped);
    EXPECT_NE(
        r.robot.reason[i].find(fmt::format("every row approaches joint {} from below", joint)),
        std::string::npos)
        << r.robot.reason[i];
    EXPECT_NE(r.robot.reason[i].find("only the sum of the backlash and the joint's zero offset"),
              std::string::npos);
  }
  bool warned = false;
  for (const std::string& w : r.warnings) warned = warned || w.starts_with("joint3.backlash");
  EXPECT_TRUE(warned);
  // Asked for, so shown (with the dropped parameter and its reason), but nothing identified.
  const auto groups = group_significance(r.robot);
  for (int joint = 1; joint <= kJointCount; ++joint) {
    const GroupSignificance& g = groups[static_cast<size_t>(5 + joint)];
    EXPECT_TRUE(g.enabled) << g.group;
    EXPECT_EQ(g.identified, 0) << g.group;
    EXPECT_FALSE(g.significant) << g.group;
  }
  EXPECT_EQ(r.robot.status[static_cast<size_t>(link_param(3, 2))], ParameterStatus::Identified);
}

}  // namespace
}  // namespace robcal
