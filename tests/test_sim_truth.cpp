// The simulator's true robots: the published IRB 120 against the independent reference data
// set, random truths within bounds, the unmodelled effects, and truth files round trip.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/sim/true_robot.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

TEST(SimTruth, PublishedTruthIsTheReferenceDataSetsRobot) {
  const test::ReferenceTruth reference = test::load_reference_truth();
  const TrueRobot truth = published_irb120_truth(reference.model, default_simulation_tool());
  EXPECT_LT((truth.robot.params - reference.params).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_DOUBLE_EQ(truth.robot.tool.payload.mass_kg, reference.payload.mass_kg);
  EXPECT_TRUE(truth.robot.tool.payload.cog_mm.isApprox(reference.payload.cog_mm));
  EXPECT_FALSE(truth.effects.any());
}

TEST(SimTruth, PublishedTruthReproducesTheReferenceTargetPositions) {
  // fk_cases.csv was written by an implementation independent of ours (docs/method/02-frames.md,
  // 03-error-model.md, 11-published-results.md).
  const RobotModel model = load_robot("abb-irb120");
  const TrueRobot truth = published_irb120_truth(model, default_simulation_tool());
  const test::CsvTable cases = test::read_csv(test::data_path("irb120-published/fk_cases.csv"));
  ASSERT_EQ(cases.rows.size(), 200u);
  double worst = 0;
  for (size_t r = 0; r < cases.rows.size(); ++r) {
    Vector6d q;
    for (int j = 0; j < kJointCount; ++j) q[j] = deg2rad(cases.at(r, "j" + std::to_string(j + 1)));
    const Pose<double> flange = true_flange_pose(truth, q);
    for (int t = 1; t <= 3; ++t) {
      const std::string prefix = "true_t" + std::to_string(t) + "_";
      const Eigen::Vector3d expected(cases.at(r, prefix + "x"), cases.at(r, prefix + "y"),
                                     cases.at(r, prefix + "z"));
      worst = std::max(
          worst,
          (flange * truth.robot.tool.targets[static_cast<size_t>(t - 1)].position_mm - expected)
              .norm());
    }
  }
  EXPECT_LT(worst, 1e-6);
}

TEST(SimTruth, ReferenceTruthFileLoadsAsTheSameRobot) {
  const TrueRobot from_file = load_truth(test::data_path("irb120-published/truth.yaml"));
  const TrueRobot published =
      published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
  EXPECT_LT((from_file.robot.params - published.robot.params).cwiseAbs().maxCoeff(), 1e-12);
  ASSERT_EQ(from_file.robot.tool.targets.size(), 3u);
  EXPECT_TRUE(from_file.robot.tool.targets[1].position_mm.isApprox(
      published.robot.tool.targets[1].position_mm));
  EXPECT_DOUBLE_EQ(from_file.robot.model.link_masses[3].mass_kg, 5.0);
  EXPECT_DOUBLE_EQ(from_file.robot.tool.payload.mass_kg, 2.6);
}

TEST(SimTruth, PublishedTruthRefusesAnotherRobot) {
  EXPECT_REFUSED(published_irb120_truth(load_robot("fanuc-lrmate200ic"), Tool{}), InputError,
                 "is an ABB IRB 120; robot 'FANUC LR Mate 200iC' is not");
}

TEST(SimTruth, RandomTruthStaysWithinBoundsAndIsSeeded) {
  const RobotModel model = load_robot("abb-irb120");
  ErrorBounds bounds;
  std::mt19937_64 rng_a(5), rng_b(5), rng_c(6);
  const TrueRobot a = random_truth(model, default_simulation_tool(), bounds, rng_a);
  const TrueRobot b = random_truth(model, default_simulation_tool(), bounds, rng_b);
  const TrueRobot c = random_truth(model, default_simulation_tool(), bounds, rng_c);
  EXPECT_EQ(a.robot.params, b.robot.params);
  EXPECT_NE(a.robot.params, c.robot.params);
  const ParameterVector nominal = model.nominal();
  const auto placement = default_base_placement();
  for (int k = 0; k < 6; ++k) {
    const double offset = a.robot.params[k] - (k < 3 ? placement[k] : deg2rad(placement[k]));
    EXPECT_LE(std::abs(offset), k < 3 ? bounds.base_length_mm : deg2rad(bounds.base_angle_deg));
  }
  for (int link = 2; link <= kJointCount; ++link) {
    for (int k : {0, 2})
      EXPECT_LE(std::abs(a.robot.params[link_param(link, k)] - nominal[link_param(link, k)]),
                deg2rad(bounds.angle_deg));
    for (int k : {1, 3})
      EXPECT_LE(std::abs(a.robot.params[link_param(link, k)] - nominal[link_param(link, k)]),
                bounds.length_mm);
    EXPECT_GE(a.robot.params[compliance_param(link)], 0.0);
    EXPECT_LE(a.robot.params[compliance_param(link)], bounds.compliance_max);
  }
}

TEST(SimTruth, MassErrorStaysWithinTenPercent) {
  const RobotModel model = load_robot("abb-irb120");
  TrueRobot truth = published_irb120_truth(model, default_simulation_tool());
  std::mt19937_64 rng(7);
  apply_mass_error(truth, 0.10, rng);
  EXPECT_DOUBLE_EQ(truth.effects.mass_error, 0.10);
  bool changed = false;
  for (size_t i = 0; i < kJointCount; ++i) {
    const PointMass& nominal = model.link_masses[i];
    const PointMass& real = truth.robot.model.link_masses[i];
    EXPECT_LE(std::abs(real.mass_kg - nominal.mass_kg), 0.10 * nominal.mass_kg + 1e-15);
    for (int k = 0; k < 3; ++k)
      EXPECT_LE(std::abs(real.cog_mm[k] - nominal.cog_mm[k]),
                0.10 * std::abs(nominal.cog_mm[k]) + 1e-15);
    changed = changed || real.mass_kg != nominal.mass_kg;
  }
  EXPECT_TRUE(changed);
  EXPECT_NE(truth.robot.tool.payload.mass_kg, 2.6);
}

TEST(SimTruth, BacklashOnlyWhenApproachedFromAbove) {
  const RobotModel model = load_robot("abb-irb120");
  TrueRobot truth = published_irb120_truth(model, default_simulation_tool());
  const Vector6d q = (Vector6d() << 0.3, 0.5, -0.2, 0.4, 0.6, -0.7).finished();
  const Pose<double> plain = true_flange_pose(truth, q);
  truth.effects.backlash = true;
  MotionState below;
  EXPECT_LT((true_flange_pose(truth, q, below).p - plain.p).norm(), 1e-12);
  // Joint 2 comes down from above, the others from below: only joint 2 sits off by its backlash.
  MotionState moving;
  moving.from_below = false;
  moving.previous_joints = q;
  moving.previous_joints[1] += 0.2;
  moving.previous_joints.tail<4>().array() -= 0.1;
  moving.previous_joints[0] -= 0.1;
  Vector6d shifted = q;
  shifted[1] += deg2rad(truth.effects.backlash_deg[1]);
  const Pose<double> expected =
      flange_pose(truth.robot.model, truth.robot.tool.payload, truth.robot.params, shifted);
  EXPECT_LT((true_flange_pose(truth, q, moving).p - expected.p).norm(), 1e-12);
  EXPECT_GT((expected.p - plain.p).norm(), 0.01);  // 0.01° at ~0.5 m is ~0.09 mm
}

TEST(SimTruth, JointSixPeriodicErrorFollowsItsSine) {
  TrueRobot truth = published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
  truth.effects.j6_periodic = true;
  truth.effects.j6_harmonic = 2;
  truth.effects.j6_amplitude_deg = 0.02;
  Vector6d q = Vector6d::Zero();
  q[5] = std::numbers::pi / 4;  // sin(2·45°) = 1: the full amplitude
  const EffectiveState state = effective_state(truth, q, {});
  EXPECT_NEAR(state.joints[5] - q[5], deg2rad(0.02), 1e-15);
  q[5] = std::numbers::pi / 2;  // sin(180°) = 0
  EXPECT_NEAR(effective_state(truth, q, {}).joints[5], q[5], 1e-15);
}

TEST(SimTruth, ThermalDriftGrowsLinkLengths) {
  TrueRobot truth = published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
  truth.effects.thermal = true;
  const Vector6d q = Vector6d::Zero();
  MotionState motion;
  const double a3 = truth.robot.params[link_param(3, 1)];
  EXPECT_DOUBLE_EQ(effective_state(truth, q, motion).params[link_param(3, 1)], a3);
  motion.time_s = truth.effects.time_constant_s;  // 1 − e^-1 of the rise
  const double expected = a3 * (1 + truth.effects.expansion_per_kelvin *
                                        truth.effects.temperature_rise_k * (1 - std::exp(-1.0)));
  EXPECT_NEAR(effective_state(truth, q, motion).params[link_param(3, 1)], expected, 1e-12);
  // Angles are not lengths: unchanged.
  EXPECT_EQ(effective_state(truth, q, motion).params[link_param(3, 0)],
            truth.robot.params[link_param(3, 0)]);
}

TEST(SimTruth, TruthFileRoundTrips) {
  const RobotModel model = load_robot("abb-irb120");
  std::mt19937_64 rng(8);
  TrueRobot truth = random_truth(model, default_simulation_tool(), ErrorBounds{}, rng);
  truth.robot.params[scale_param(3)] = 1.0002;
  enable_effects(truth, {"backlash", "j6-periodic", "mass-error", "thermal"}, rng);
  truth.effects.j6_phase_deg = 12.5;
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "sim_truth_round_trip.yaml";
  write_file_atomically(path, truth_to_yaml(truth, "abb-irb120"));
  const TrueRobot back = load_truth(path.string());
  EXPECT_LT((back.robot.params - truth.robot.params).cwiseAbs().maxCoeff(),
            1e-11);  // 15 digits of -812.25 mm
  for (size_t i = 0; i < kJointCount; ++i) {
    EXPECT_NEAR(back.robot.model.link_masses[i].mass_kg, truth.robot.model.link_masses[i].mass_kg,
                1e-12);
    EXPECT_LT(
        (back.robot.model.link_masses[i].cog_mm - truth.robot.model.link_masses[i].cog_mm).norm(),
        1e-10);
  }
  EXPECT_NEAR(back.robot.tool.payload.mass_kg, truth.robot.tool.payload.mass_kg, 1e-12);
  EXPECT_TRUE(back.effects.backlash && back.effects.j6_periodic && back.effects.thermal);
  EXPECT_DOUBLE_EQ(back.effects.mass_error, 0.10);
  EXPECT_DOUBLE_EQ(back.effects.j6_phase_deg, 12.5);
  EXPECT_EQ(back.origin, "random");
  // Same robot: same true positions, effects included.
  const Vector6d q = (Vector6d() << 0.1, 0.7, -0.3, 1.0, -0.5, 2.0).finished();
  MotionState motion{false, Vector6d::Constant(0.5), 900};
  EXPECT_LT((true_flange_pose(back, q, motion).p - true_flange_pose(truth, q, motion).p).norm(),
            1e-9);
}

TEST(SimTruth, BadTruthFilesNameTheKey) {
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "sim_truth_bad.yaml";
  std::string text = read_text_file(test::data_path("irb120-published/truth.yaml"));
  text += "effects:\n  warp_drive: 1\n";
  write_file_atomically(path, text);
  try {
    load_truth(path.string());
    FAIL() << "accepted an unknown effect";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("warp_drive"), std::string::npos) << message;
    EXPECT_NE(message.find("sim_truth_bad.yaml"), std::string::npos) << message;
  }
  // Unknown keys anywhere (issue 21), located, with the nearest known key.
  const std::string good = read_text_file(test::data_path("irb120-published/truth.yaml"));
  for (const auto& [from, to, expected] : std::vector<std::array<std::string, 3>>{
           {"gravity_m_s2:", "gravty_m_s2:", "did you mean 'gravity_m_s2'?"},
           {"  y_mm:", "  y_mn:", "(base.y_mn): unknown key 'y_mn': did you mean 'y_mm'?"},
           {"  6: [", "  7: [", "(links.7): unknown key '7'"}}) {
    std::string bad = good;
    bad.replace(bad.find(from), from.size(), to);
    write_file_atomically(path, bad);
    try {
      load_truth(path.string());
      ADD_FAILURE() << "accepted " << to;
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(expected), std::string::npos) << message;
      EXPECT_NE(message.find("sim_truth_bad.yaml:"), std::string::npos) << message;
    }
  }
  std::mt19937_64 rng(1);
  TrueRobot truth;
  EXPECT_REFUSED(enable_effects(truth, {"gremlins"}, rng), InputError,
                 "--effects: unknown effect 'gremlins'; expected backlash");
}

}  // namespace
}  // namespace robcal
