// The simulated hexapod calibration end to end (fast version of `robcal hexapod simulate`):
// planning, ballbar readings, preliminary and final calibration through `calibrate`, the fit from
// the raw legs, laser-tracker validation.

#include <gtest/gtest.h>

#include "robcal/hexapod/end_to_end.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal::hexapod {
namespace {

TEST(HexapodEndToEnd, LrMateCalibrationBeatsTheNominalModel) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  EndToEndOptions o;
  o.cell.placement.p = Eigen::Vector3d(450, 0, 300);
  o.validation_configurations = 300;
  const uint64_t seed = 5;
  SCOPED_TRACE(seed);
  auto rng = test::seeded_rng(seed);
  const EndToEndReport r = run_end_to_end(model, o, rng);
  EXPECT_GT(r.measured_first, 20);
  EXPECT_EQ(r.measured_first + r.retried, r.configurations_planned);
  EXPECT_LE(r.measured_after_replan, r.retried);
  EXPECT_TRUE(r.final_pose_fit.converged);
  EXPECT_GT(r.nominal.absolute.mean, 0.3);
  // The pose-based fit keeps the world frame the uncalibrated robot gave the base cups (relative
  // model, METHOD §8): it improves on the nominal model but inherits that frame's error. The fit
  // from the raw legs places the cups itself and must be far better.
  EXPECT_LT(r.final_pose_fit.validation.absolute.mean, r.nominal.absolute.mean);
  EXPECT_LT(r.leg_fit.validation.absolute.mean, r.nominal.absolute.mean / 5);
  EXPECT_LT(r.leg_fit.validation.pairs.mean, r.nominal.pairs.mean / 5);
  EXPECT_EQ(r.nominal.pairs.count, 300u * 299u / 2u);
  std::printf(
      "e2e: %d configurations (%d first, %d after re-planning); absolute mean error "
      "nominal %.3f, preliminary %.4f, final %.4f, legs %.4f mm; pairs mean %.3f -> %.4f mm\n",
      r.measured_first + r.measured_after_replan, r.measured_first, r.measured_after_replan,
      r.nominal.absolute.mean, r.preliminary.validation.absolute.mean,
      r.final_pose_fit.validation.absolute.mean, r.leg_fit.validation.absolute.mean,
      r.nominal.pairs.mean, r.final_pose_fit.validation.pairs.mean);
}

}  // namespace
}  // namespace robcal::hexapod
