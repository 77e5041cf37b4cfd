// The direction of gravity identified (issue 19, docs/method/03-error-model.md §11): the group's
// names, the forward model against a second computation (the same robot with the tilted vector
// written into the robot file), the calibrated chain and IK with a tilt (the identification
// Jacobian's columns are checked against autodiff and finite differences in
// test_parameter_jacobian.cpp), and a simulated wall-mounted IRB 120 whose wall is not plumb: the
// tilt recovered within 3σ and the validation error back to that of the plumb wall, the group
// dropped by name when no compliance is identified.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "robcal/identify/cross_validation.hpp"
#include "robcal/identify/identification.hpp"
#include "robcal/sim/simulator.hpp"
#include "robcal/validate/validation.hpp"
#include "test_compensate_support.hpp"
#include "test_error_groups_support.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

const Eigen::Vector3d kWall(0, -9.81, 0);  // mounting_deg [90, 0]

TEST(GravityDirection, NamesUnitsAndGroup) {
  EXPECT_EQ(parameter_table()[kGravityTiltA].name, "gravity.tilt_a");
  EXPECT_EQ(parameter_table()[kGravityTiltB].unit, "deg");
  EXPECT_EQ(parameter_index("gravity.tilt_b"), kGravityTiltB);
  EXPECT_EQ(opt_in_group_parameters("gravity"), (std::vector<int>{kGravityTiltA, kGravityTiltB}));
  EXPECT_EQ(opt_in_groups().back().name, "gravity");
  EXPECT_TRUE(is_opt_in(kGravityTiltA));
  for (int i : level_parameters(CalibrationLevel::Full)) EXPECT_NE(i, kGravityTiltB);
}

// The tilts turn the robot file's vector about two axes perpendicular to it: the pose equals
// that of the same robot whose file gives the turned vector (computed here with Eigen's
// AngleAxis), for gravity in the world and in the base frame, with compliance on every joint.
TEST(GravityDirection, TiltIsTheTurnedVector) {
  auto rng = test::seeded_rng(1971);
  for (const bool in_base : {false, true}) {
    CalibratedRobot robot = test::random_calibrated("abb-irb120", rng);
    robot.model.gravity_in_base = in_base;
    robot.model.gravity_m_s2 =
        in_base ? Eigen::Vector3d(1.0, -9.0, 3.0) : Eigen::Vector3d(0, 0, -9.81);
    robot.params[kJoint1Compliance] = 3e-7;
    robot.params[kGravityTiltA] = deg2rad(4.0);
    robot.params[kGravityTiltB] = deg2rad(-7.0);
    const Eigen::Vector3d u = robot.model.gravity_m_s2.normalized();
    const std::array<Eigen::Vector3d, 2> axes = gravity_tilt_axes(robot.model.gravity_m_s2);
    EXPECT_LT(std::abs(axes[0].dot(u)) + std::abs(axes[1].dot(u)) + std::abs(axes[0].dot(axes[1])),
              1e-12);
    RobotModel turned = robot.model;
    turned.gravity_m_s2 = Eigen::AngleAxisd(deg2rad(4.0), axes[0]) *
                          (Eigen::AngleAxisd(deg2rad(-7.0), axes[1]) * robot.model.gravity_m_s2);
    ParameterVector untilted = robot.params;
    untilted[kGravityTiltA] = untilted[kGravityTiltB] = 0;
    double moved = 0;
    for (int k = 0; k < 20; ++k) {
      const Vector6d q = test::random_joints(robot.model, rng);
      const Pose<double> a = flange_pose(robot.model, robot.tool.payload, robot.params, q);
      const Pose<double> b = flange_pose(turned, robot.tool.payload, untilted, q);
      const Pose<double> c = flange_pose(robot.model, robot.tool.payload, untilted, q);
      EXPECT_LT((a.p - b.p).norm(), 1e-9);
      EXPECT_LT((a.R - b.R).norm(), 1e-12);
      moved = std::max(moved, (a.p - c.p).norm());
    }
    EXPECT_GT(moved, 0.01) << "the tilt must move the flange";  // a test that can fail
    test::expect_chain_matches_forward_model(robot, rng, in_base ? "base" : "world");
    test::expect_calibrated_ik_round_trips(robot, rng);
  }
}

/// 100 calibration and 60 validation positions on the published IRB 120 on a wall (joint 1 as
/// compliant as 1e-7 rad/N·mm) whose plate is turned by tilts (a, b) from plumb, σ = 0.01 mm.
test::GroupCampaign wall_campaign(double a_deg, double b_deg, uint64_t seed) {
  TrueRobot truth = published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
  truth.robot.model.gravity_m_s2 = kWall;
  truth.robot.model.gravity_in_base = true;
  truth.robot.params[kJoint1Compliance] = 1e-7;
  truth.robot.params[kGravityTiltA] = deg2rad(a_deg);
  truth.robot.params[kGravityTiltB] = deg2rad(b_deg);
  return test::simulate_campaign(truth, 0.01, seed, published_joint_box(truth.robot.model));
}

IdentificationResult fit_wall(const MeasurementSet& data, std::vector<std::string> identify) {
  RobotModel wall = load_robot("abb-irb120");
  wall.gravity_m_s2 = kWall;
  wall.gravity_in_base = true;
  identify.emplace_back("joint1.compliance");
  return test::fit_full(data, identify, wall);
}

// The check for the group: a wall 5° and 3° off plumb, calibrated with the plumb wall
// given, validates within 10 % of the plumb wall's figure when the group is enabled, and the tilt
// comes back within 3σ (seeded Monte Carlo); without the group the figure is worse.
TEST(GravityDirection, WallOffPlumbIdentified) {
  double plumb = 0, without = 0, with = 0;
  test::NormalisedErrors z;
  constexpr int kSeeds = 4;
  for (uint64_t seed = 1972; seed < 1972 + kSeeds; ++seed) {
    const test::GroupCampaign ideal = wall_campaign(0, 0, seed);
    const test::GroupCampaign off = wall_campaign(5, -3, seed);
    plumb += test::validation_mean_mm(fit_wall(ideal.calibration, {}), ideal.validation) / kSeeds;
    without += test::validation_mean_mm(fit_wall(off.calibration, {}), off.validation) / kSeeds;
    const IdentificationResult r = fit_wall(off.calibration, {"gravity"});

    with += test::validation_mean_mm(r, off.validation) / kSeeds;
    const double sx = z.add(r, kGravityTiltA, deg2rad(5.0), seed);
    const double sy = z.add(r, kGravityTiltB, deg2rad(-3.0), seed);
    std::printf("seed %llu: gravity.tilt_a %.3f ± %.3f deg, gravity.tilt_b %.3f ± %.3f deg\n",
                static_cast<unsigned long long>(seed), rad2deg(r.robot.params[kGravityTiltA]),
                rad2deg(sx), rad2deg(r.robot.params[kGravityTiltB]), rad2deg(sy));
  }
  std::printf(
      "validation mean: plumb wall %.4f mm; off plumb %.4f mm without the group, %.4f mm "
      "with it; normalised errors rms %.2f over %d\n",
      plumb, without, with, z.rms(), z.count);
  EXPECT_LT(with, 1.10 * plumb);
  EXPECT_GT(without, 1.2 * with);
}

// The model-selection guard: on a plumb wall (nothing to find), enabling the group costs at most
// 2 % of the cross-validated error and the group is reported as not significant.
TEST(GravityDirection, GroupOnPlumbWallIsHarmlessAndNotSignificant) {
  const test::GroupCampaign c = wall_campaign(0, 0, 1990);
  RobotModel wall = load_robot("abb-irb120");
  wall.gravity_m_s2 = kWall;
  wall.gravity_in_base = true;
  IdentifyOptions without;
  without.level = CalibrationLevel::Full;
  without.identify = {"joint1.compliance"};
  IdentifyOptions with = without;
  with.identify.emplace_back("gravity");
  const Tool tool = default_simulation_tool();
  const double a = cross_validate(wall, tool, c.calibration, without, 5, 7).mean_mm;
  const double b = cross_validate(wall, tool, c.calibration, with, 5, 7).mean_mm;
  std::printf("cross-validated mean on a plumb wall: %.4f mm without, %.4f mm with the group\n", a,
              b);
  EXPECT_LT(b, 1.02 * a);
  const IdentificationResult r = fit_wall(c.calibration, {"gravity"});
  bool reported = false;
  for (const GroupSignificance& g : group_significance(r.robot))
    if (g.group == "gravity") {
      reported = true;
      EXPECT_FALSE(g.significant) << "Wald " << g.wald;
    }
  EXPECT_TRUE(reported);
}

// Gravity reaches the measurements only through the compliances: without them (level
// kinematic) the group is dropped by name, not fitted as noise.
TEST(GravityDirection, DroppedWithoutCompliance) {
  const test::GroupCampaign c = wall_campaign(5, -3, 1980);
  IdentifyOptions options;
  options.level = CalibrationLevel::Kinematic;
  options.identify = {"gravity"};
  RobotModel wall = load_robot("abb-irb120");
  wall.gravity_m_s2 = kWall;
  wall.gravity_in_base = true;
  const IdentificationResult r = calibrate(wall, default_simulation_tool(), c.calibration, options);
  EXPECT_NE(r.robot.status[kGravityTiltA], ParameterStatus::Identified);
  bool named = false;
  for (const std::string& w : r.warnings)
    named = named || w.starts_with(
                         "gravity.tilt_a not identified: the direction of gravity is seen "
                         "only through the joint compliances");
  EXPECT_TRUE(named);
}

}  // namespace
}  // namespace robcal
