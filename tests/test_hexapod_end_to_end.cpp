// The simulated hexapod calibration end to end (fast version of `robcal hexapod simulate`):
// planning, ballbar readings, preliminary and final calibration through `calibrate`, the fit from
// the raw legs, laser-tracker validation. The pose fit (base identified) must match the raw-leg
// fit; the published relative model (base held) must not.

#include <gtest/gtest.h>

#include <cmath>

#include "robcal/hexapod/end_to_end.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal::hexapod {
namespace {

EndToEndReport run(bool relative_pose_fit) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  EndToEndOptions o;
  o.cell.placement.p = Eigen::Vector3d(450, 0, 300);
  o.validation_configurations = 300;
  o.relative_pose_fit = relative_pose_fit;
  auto rng = test::seeded_rng(5);
  return run_end_to_end(model, o, rng);
}

TEST(HexapodEndToEnd, LrMatePoseFitMatchesTheRawLegFit) {
  const EndToEndReport r = run(false);
  EXPECT_GT(r.measured_first, 20);
  EXPECT_EQ(r.measured_first + r.retried, r.configurations_planned);
  EXPECT_LE(r.measured_after_replan, r.retried);
  EXPECT_TRUE(r.preliminary.converged);
  EXPECT_TRUE(r.final_pose_fit.converged);
  EXPECT_TRUE(r.leg_fit.converged);
  EXPECT_GT(r.nominal.absolute.mean, 0.3);
  EXPECT_EQ(r.nominal.pairs.count, 300u * 299u / 2u);
  // The validation tracker alone (σ per axis) gives a mean error of σ·√(8/π) (the mean of a
  // Maxwell distribution), 0.0351 mm, known to ±0.001 mm (1σ) from 300 points: every fit must be
  // within 20% of that floor (a model error of 0.02 mm rms would already exceed it), and the
  // pose fit within 10% of the leg fit (mean and max).
  const double floor_mm = EndToEndOptions{}.tracker_sigma_mm * std::sqrt(8 / M_PI);
  for (const CalibrationStage* s : {&r.preliminary, &r.final_pose_fit, &r.leg_fit}) {
    EXPECT_GT(s->validation.absolute.mean, 0.95 * floor_mm);
    EXPECT_LT(s->validation.absolute.mean, 1.2 * floor_mm);
    EXPECT_LT(s->validation.absolute.max, 0.15);
    // A distance error is the noise of two points along their line, N(0, 2σ²): mean 2σ/√π.
    EXPECT_LT(s->validation.pairs.mean,
              1.2 * 2 * EndToEndOptions{}.tracker_sigma_mm / std::sqrt(M_PI));
  }
  EXPECT_LT(r.final_pose_fit.validation.absolute.mean, 1.1 * r.leg_fit.validation.absolute.mean);
  EXPECT_LT(r.final_pose_fit.validation.absolute.max, 1.1 * r.leg_fit.validation.absolute.max);
  EXPECT_LT(r.leg_fit.validation.absolute.mean, 1.1 * r.final_pose_fit.validation.absolute.mean);
  // With the preliminary model most of the out-of-range configurations become measurable.
  EXPECT_GT(r.measured_after_replan, r.retried / 2);
  std::printf(
      "e2e: %d configurations (%d first, %d after re-planning); world frame off by %.3f mm, "
      "%.4f deg; absolute mean/max error nominal %.3f/%.3f, preliminary %.4f/%.4f, final poses "
      "%.4f/%.4f, raw legs %.4f/%.4f mm; pairs mean %.3f -> %.4f (poses), %.4f (legs) mm\n",
      r.measured_first + r.measured_after_replan, r.measured_first, r.measured_after_replan,
      r.world_frame_error_mm, r.world_frame_error_deg, r.nominal.absolute.mean,
      r.nominal.absolute.max, r.preliminary.validation.absolute.mean,
      r.preliminary.validation.absolute.max, r.final_pose_fit.validation.absolute.mean,
      r.final_pose_fit.validation.absolute.max, r.leg_fit.validation.absolute.mean,
      r.leg_fit.validation.absolute.max, r.nominal.pairs.mean,
      r.final_pose_fit.validation.pairs.mean, r.leg_fit.validation.pairs.mean);
}

TEST(HexapodEndToEnd, RelativePoseFitKeepsTheWorldFrameError) {
  // The published relative model (base held): the world frame from cups the uncalibrated robot
  // placed is off by its error there, which the link parameters cannot absorb.
  const EndToEndReport r = run(true);
  EXPECT_GT(r.world_frame_error_mm, 0.2);
  EXPECT_GT(r.final_pose_fit.validation.absolute.mean, 5 * r.leg_fit.validation.absolute.mean);
  EXPECT_LT(r.final_pose_fit.validation.absolute.mean, r.nominal.absolute.mean);
  std::printf(
      "relative pose fit: world frame off by %.3f mm, %.4f deg; final mean/max %.4f/%.4f "
      "mm vs raw legs %.4f/%.4f mm\n",
      r.world_frame_error_mm, r.world_frame_error_deg, r.final_pose_fit.validation.absolute.mean,
      r.final_pose_fit.validation.absolute.max, r.leg_fit.validation.absolute.mean,
      r.leg_fit.validation.absolute.max);
}

}  // namespace
}  // namespace robcal::hexapod
