// Calibrated inverse kinematics and closed-loop compensation of the UR family and the Fanuc CRX
// (issue 15): the nominal seeds come from the parallel-axes closed form (parallel_axes_ik.hpp) or
// the general 6R inverse (general_6r_ik.hpp) and Newton
// solves its steps by a pivoted LU (the wrist is not spherical). Same guarantees as for the
// ortho-parallel robots (test_compensate_ik.cpp, test_compensate_closed_loop.cpp).

#include <gtest/gtest.h>

#include <numeric>

#include "robcal/compensate/closed_loop.hpp"
#include "robcal/identify/identification.hpp"
#include "robcal/sim/simulator.hpp"
#include "test_compensate_support.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

constexpr const char* kUr10e = "universal-robots-ur10e";
constexpr const char* kCrx = "fanuc-crx10ia";
constexpr const char* kCrxLong = "fanuc-crx10ia-l";

TEST(CompensateAny6r, Ur10eChainMatchesTemplatedForwardKinematics) {
  auto rng = test::seeded_rng(151);
  const CalibratedRobot robot = test::random_calibrated(kUr10e, rng);
  const Compensator comp = make_compensator(robot);
  EXPECT_FALSE(comp.spherical_wrist);
  for (int k = 0; k < 200; ++k) {
    const Vector6d j = test::random_joints(robot.model, rng);
    const Pose<double> want =
        flange_pose(robot.model, robot.tool.payload, robot.params, j) * comp.flange_T_tcp;
    const Pose<double> got = calibrated_tcp_pose(comp.chain, j);
    ASSERT_LT((got.p - want.p).norm(), 1e-9);
    ASSERT_LT((got.R - want.R).norm(), 1e-12);
  }
}

// As CompensateIk.RoundTripEveryConfigurationBothIterationsAgree: 150 poses per
// configuration ≥ 5° from the singular labels, both iterations converge within 1e-6 mm / 1e-6°
// by the calibrated model, recover the drawn joints and agree.
void round_trip_every_configuration(const char* name, std::uint64_t seed) {
  constexpr long kPerConfig = 150;
  auto rng = test::seeded_rng(seed);
  const CalibratedRobot robot = test::random_calibrated(name, rng);
  const Compensator comp = make_compensator(robot);
  const test::RoundTripStats st = test::round_trip(robot, comp, kPerConfig, 2'000'000, rng);
  double worst_agreement = 0;
  for (int i = 0; i < 8; ++i) {
    const ArmConfig config{(i & 4) != 0, (i & 2) != 0, (i & 1) != 0};
    EXPECT_EQ(st.poses[i], kPerConfig) << config.label();
    EXPECT_EQ(st.failures[i], 0) << config.label();
    EXPECT_EQ(st.disagreements[i], 0) << config.label();
    worst_agreement = std::max(worst_agreement, st.worst_agreement_rad[i]);
  }
  EXPECT_TRUE(st.first_failure.empty()) << st.first_failure;
  EXPECT_LT(st.worst_mm, 1e-6);
  EXPECT_LT(st.worst_deg, 1e-6);
  EXPECT_LT(st.worst_recovery_rad, 1e-6);
  EXPECT_EQ(st.other_turn, 0);
  std::printf(
      "[%s] %ld draws; worst %.2e mm %.2e deg, agreement %.1e rad, recovery %.1e rad, "
      "Newton <= %d it, pose shift <= %d it, hand-overs %ld, nominal seed elsewhere %ld\n",
      name, st.draws, st.worst_mm, st.worst_deg, worst_agreement, st.worst_recovery_rad,
      st.max_newton, st.max_shift, std::accumulate(st.handovers.begin(), st.handovers.end(), 0L),
      st.seed_elsewhere);
  EXPECT_LT(st.seed_elsewhere, st.draws / 20);
}

TEST(CompensateAny6r, Ur10eRoundTripEveryConfigurationBothIterationsAgree) {
  round_trip_every_configuration(kUr10e, 152);
}

// The Fanuc CRX-10iA and CRX-10iA/L: nominal seeds from the general 6R inverse
// (general_6r_ik.hpp).
TEST(CompensateAny6r, FanucCrxRoundTripEveryConfigurationBothIterationsAgree) {
  round_trip_every_configuration(kCrx, 157);
}

TEST(CompensateAny6r, FanucCrxLongRoundTripEveryConfigurationBothIterationsAgree) {
  round_trip_every_configuration(kCrxLong, 155);
}

// At the wrist singularity (θ5 = 0) Newton's Jacobian loses rank: a status, never joints
// that miss the pose.
TEST(CompensateAny6r, Ur10eAtTheWristSingularityNeverAWrongAnswer) {
  auto rng = test::seeded_rng(153);
  const CalibratedRobot robot = test::random_calibrated(kUr10e, rng);
  const Compensator comp = make_compensator(robot);
  int converged = 0, reported = 0;
  for (int k = 0; k < 50; ++k) {
    Vector6d q = test::random_joints(robot.model, rng);
    q[4] = 1e-9 * k;  // on and next to the singularity
    const Pose<double> wanted = calibrated_tcp_pose(comp.chain, q);
    const ArmConfig config = arm_config(robot.model, q);
    const CalibratedIkResult r = calibrated_ik(comp, wanted, config, q);
    const Pose<double> reached = calibrated_tcp_pose(comp.chain, r.joints);
    const double miss_mm = (reached.p - wanted.p).norm();
    const double miss_rad = Eigen::AngleAxisd(reached.R.transpose() * wanted.R).angle();
    if (!r.ok()) {
      ++reported;
      continue;
    }
    // Every answer given is right: the calibrated model reaches the pose with these joints.
    ++converged;
    EXPECT_LT(miss_mm, 1e-6) << k;
    EXPECT_LT(miss_rad, deg2rad(1e-6)) << k;
  }
  std::printf("UR10e at θ5 = 0: %d converged (checked), %d reported\n", converged, reported);
  // The check above is not vacuous: a good part of these poses is reached (22 of 50 here).
  EXPECT_GE(converged, 10);
}

// Closing the loop in simulation: a robot with random errors (ErrorBounds defaults), measured
// by a simulated laser tracker (σ = 0.01 mm), calibrated, its corrected targets commanded to
// the true robot: the compensated error is the noise propagated through the fit.
void closed_loop_at_the_noise_floor(const char* name, std::uint64_t seed) {
  const RobotModel model = load_robot(name);
  const Tool tool = default_simulation_tool();
  std::mt19937_64 rng(seed);
  const TrueRobot truth = random_truth(model, tool, ErrorBounds{}, rng);
  const VirtualInstrument tracker = standard_instrument(InstrumentKind::LaserTracker, truth, 0.01);
  RandomConfigurationOptions options;
  options.box = published_joint_box(model);
  const auto configs = random_configurations(truth, tracker, 80, rng, options);
  const SimulationResult sim = simulate_measurements(truth, tracker, configs, rng);
  const CalibratedRobot calibrated =
      calibrate(model, tool, sim.measurements, IdentifyOptions{}).robot;
  const Compensator comp = make_compensator(calibrated);
  std::vector<WantedTarget> wanted;
  for (int k = 0; k < 200;) {
    Vector6d j;
    for (int i = 0; i < kJointCount; ++i)
      j[i] = std::uniform_real_distribution<double>(options.box[i].lower + deg2rad(3),
                                                    options.box[i].upper - deg2rad(3))(rng);
    if (test::near_singular(model, j, 10)) continue;
    ++k;
    WantedTarget w;
    w.name = "w" + std::to_string(k);
    w.world_T_tcp = true_flange_pose(truth, j) * comp.flange_T_tcp;
    w.config = arm_config(model, j);
    wanted.push_back(w);
  }
  const auto corrected = correct_targets(comp, calibrated, wanted, "wanted", IkMethod::Newton);
  const ClosedLoopReport report = closed_loop_check(comp, truth, wanted, corrected);
  std::printf(
      "[%s] closed loop, 200 poses: compensated mean %.4f max %.4f mm (max %.4f deg); "
      "uncompensated mean %.4f max %.4f mm\n",
      name, report.compensated.mean_mm, report.compensated.max_mm, report.compensated.max_deg,
      report.uncompensated.mean_mm, report.uncompensated.max_mm);
  EXPECT_EQ(report.compensated.count, 200);
  EXPECT_GT(report.uncompensated.mean_mm, 0.3);
  EXPECT_LT(report.compensated.max_mm, 0.1);
  EXPECT_LT(report.compensated.mean_mm, 0.05 * report.uncompensated.mean_mm);
}

TEST(CompensateAny6r, Ur10eClosedLoopCompensatedErrorAtTheNoiseFloor) {
  closed_loop_at_the_noise_floor(kUr10e, 154);
}

TEST(CompensateAny6r, FanucCrxClosedLoopCompensatedErrorAtTheNoiseFloor) {
  closed_loop_at_the_noise_floor(kCrx, 158);
}

TEST(CompensateAny6r, FanucCrxLongClosedLoopCompensatedErrorAtTheNoiseFloor) {
  closed_loop_at_the_noise_floor(kCrxLong, 156);
}

}  // namespace
}  // namespace robcal
