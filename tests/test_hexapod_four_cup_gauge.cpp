// The hexapod's length gauge as a parameter (issue 20): its range and σ checked, the fixture
// sides it can measure, and a ±5 mm gauge reaching every planned pose of an uncalibrated robot.

#include <gtest/gtest.h>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/hexapod/gauge.hpp"
#include "robcal/hexapod/simulation.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal::hexapod {
namespace {

std::string gauge_error(const LengthGauge& gauge) {
  try {
    check_gauge(gauge, "--gauge-range-mm", "--gauge-sigma-mm");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(HexapodGauge, RangeAndSigmaAreCheckedNamingTheFlag) {
  EXPECT_EQ(gauge_error({}), "");
  EXPECT_EQ(gauge_error({5, 0.002}), "");
  std::string e = gauge_error({0, 0.002});
  EXPECT_NE(e.find("--gauge-range-mm"), std::string::npos) << e;
  EXPECT_NE(e.find("gauge range 0 mm is not a positive length"), std::string::npos) << e;
  e = gauge_error({5, std::nan("")});
  EXPECT_NE(e.find("--gauge-sigma-mm"), std::string::npos) << e;
  EXPECT_NE(e.find("gauge σ nan mm is not a positive length"), std::string::npos) << e;
  e = gauge_error({1, 2});  // σ given in µm by mistake
  EXPECT_NE(e.find("gauge σ 2 mm is not below its range ±1 mm"), std::string::npos) << e;
}

TEST(HexapodGauge, FixtureSidesMustBeWithinTheGaugeReach) {
  const HexapodGeometry g{{300.4, 299.2, 303}, {150, 149.5, 150.9}, 300};
  EXPECT_EQ(fixture_range_problem(g, 150, {5, 0.002}), "");
  EXPECT_EQ(fixture_range_problem(g, 150, {1, 0.00051}),
            "fixture side b31 = 303 mm is out of the gauge's reach 300 ± 1 mm: make the fixture "
            "sides within the range of the set-up length or use a longer-range gauge");
  // A tool fixture built for a 100 mm set-up, measured at the 150 mm one.
  EXPECT_NE(fixture_range_problem({g.base, {100, 100, 100}, 300}, 150, {5, 0.002})
                .find("fixture side t12 = 100 mm is out of the gauge's reach 150 ± 5 mm"),
            std::string::npos);
}

/// Configurations of the plan with a leg the gauge cannot read when the robot goes where its
/// nominal model says (the first pass of docs/method/07-hexapod.md §5, before any preliminary
/// calibration).
int unreadable_with_nominal_model(double range_mm, int* planned) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  auto rng = test::seeded_rng(5);
  HexapodCellOptions o;
  o.placement.p = Eigen::Vector3d(450, 0, 300);
  o.range_mm = range_mm;
  const TrueRobot truth = levelled_random_truth(model, PointMass{2.6, Eigen::Vector3d(50, 25, 100)},
                                                ErrorBounds{0.3, 0.1, 0.05e-6, 1.0, 0.1}, rng);
  const SimulatedHexapodCell cell = set_up_simulated_cell(truth, model, o, rng);
  const HexapodGeometry measured{cell.base_sides, cell.tool_sides, o.design.leg_mm};
  const std::vector<HexapodPose> kept = prune_redundant(enumerate_poses(measured), deg2rad(30), 50);
  const PlanSummary plan =
      plan_poses(model, cell.cell, fixture_cups(cell.base_sides, "base"), kept);
  *planned = plan.configurations;
  int unreadable = 0;
  for (const PosePlan& p : plan.poses)
    for (const PoseConfiguration& c : p.configurations)
      unreadable += !simulate_legs(cell, p.pose, c.joints, rng).has_value();
  return unreadable;
}

TEST(HexapodGauge, AFiveMillimetreGaugeReadsEveryPlannedPoseOfTheUncalibratedRobot) {
  int planned_1 = 0, planned_5 = 0;
  const int unreadable_1 = unreadable_with_nominal_model(1.0, &planned_1);
  const int unreadable_5 = unreadable_with_nominal_model(5.0, &planned_5);
  EXPECT_EQ(planned_1, planned_5);
  EXPECT_GT(planned_5, 20);
  EXPECT_GT(unreadable_1, 0);  // the ±1 mm ballbar needs the preliminary calibration
  EXPECT_EQ(unreadable_5, 0);  // the ±5 mm gauge does not
  std::printf(
      "LR Mate 200iC, seed 5: %d planned configurations, %d unreadable at ±1 mm, %d at ±5 mm\n",
      planned_1, unreadable_1, unreadable_5);
}

}  // namespace
}  // namespace robcal::hexapod
