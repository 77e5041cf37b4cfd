// Virtual instruments (docs/method/06-instruments.md): noise statistics against σ, visibility cones
// and ranges at their edges, and the ballbar's ±1 mm window.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/measure/instrument.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

constexpr int kSamples = 20000;

/// Sample mean and standard deviation of each column.
struct ColumnStats {
  Eigen::VectorXd mean;
  Eigen::VectorXd std;
};
ColumnStats column_stats(const Eigen::MatrixXd& samples) {
  ColumnStats s;
  s.mean = samples.colwise().mean();
  const Eigen::MatrixXd centred = samples.rowwise() - s.mean.transpose();
  s.std = (centred.array().square().colwise().sum() / double(samples.rows() - 1)).sqrt();
  return s;
}

/// A unit vector at `angle_deg` from `axis`, turned about a direction perpendicular to it.
Eigen::Vector3d tilted(const Eigen::Vector3d& axis, double angle_deg) {
  const Eigen::Vector3d perpendicular = axis.unitOrthogonal();
  return Eigen::AngleAxisd(deg2rad(angle_deg), perpendicular) * axis.normalized();
}

TEST(InstrumentLaserTracker, NoiseMatchesSigmaPerAxis) {
  LaserTracker tracker;
  tracker.sigma_mm = Eigen::Vector3d(0.022, 0.070, 0.010);
  auto rng = test::seeded_rng(11);
  const Eigen::Vector3d truth(1200.0, -300.0, 450.0);
  Eigen::MatrixXd errors(kSamples, 3);
  for (int i = 0; i < kSamples; ++i) errors.row(i) = (read_point(tracker, truth, rng) - truth);
  const ColumnStats s = column_stats(errors);
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE(k);
    // Mean within 4 standard errors, std within 3 % (its standard error is σ/√(2n) ≈ 0.5 %).
    EXPECT_LT(std::abs(s.mean[k]), 4 * tracker.sigma_mm[k] / std::sqrt(double(kSamples)));
    EXPECT_NEAR(s.std[k] / tracker.sigma_mm[k], 1.0, 0.03);
  }
}

TEST(InstrumentLaserTracker, ConeEdgeIsInclusive) {
  LaserTracker tracker;
  tracker.position_mm = Eigen::Vector3d(2000, 0, 0);
  const Eigen::Vector3d smr(0, 0, 0);
  const Eigen::Vector3d towards = Eigen::Vector3d::UnitX();
  EXPECT_TRUE(smr_visible(tracker, smr, towards));
  EXPECT_TRUE(smr_visible(tracker, smr, tilted(towards, 29.9)));
  EXPECT_TRUE(smr_visible(tracker, smr, tilted(towards, 30.0)));
  EXPECT_FALSE(smr_visible(tracker, smr, tilted(towards, 30.1)));
  EXPECT_FALSE(smr_visible(tracker, smr, -towards));  // facing away
  EXPECT_FALSE(smr_visible(tracker, smr, Eigen::Vector3d::UnitZ()));
  tracker.cone_half_angle_deg = 45;
  EXPECT_TRUE(smr_visible(tracker, smr, tilted(towards, 44.9)));
}

TEST(InstrumentLaserTracker, RangeLimits) {
  LaserTracker tracker;
  tracker.min_range_mm = 1000;
  tracker.max_range_mm = 3000;
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  EXPECT_FALSE(smr_visible(tracker, Eigen::Vector3d(-999, 0, 0), axis));
  EXPECT_TRUE(smr_visible(tracker, Eigen::Vector3d(-1000, 0, 0), axis));
  EXPECT_TRUE(smr_visible(tracker, Eigen::Vector3d(-3000, 0, 0), axis));
  EXPECT_FALSE(smr_visible(tracker, Eigen::Vector3d(-3001, 0, 0), axis));
  EXPECT_FALSE(smr_visible(tracker, tracker.position_mm, axis));  // no line of sight at zero range
}

TEST(InstrumentLaserTracker, TargetsFacingTheTracker) {
  Tool tool;
  tool.targets = {{"1", {0, 0, 125}, true},
                  {"2", {150, 0, 125}, true},
                  {"3", {0, 0, 0}, true},
                  {"4", {0, 0, 0}, false}};
  LaserTracker tracker;
  // Default axes: outwards from the flange origin; the flange z axis for a target at the origin.
  EXPECT_TRUE(smr_axis_flange(tracker, tool, 0).isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(
      smr_axis_flange(tracker, tool, 1).isApprox(Eigen::Vector3d(150, 0, 125).normalized()));
  EXPECT_TRUE(smr_axis_flange(tracker, tool, 2).isApprox(Eigen::Vector3d::UnitZ()));

  // Flange at the origin, its z axis towards a tracker 2 m away on +z: target 2's axis is
  // atan(150/125) = 50.2° off the line of sight, so only targets 1 and 3 face the tracker;
  // target 4 has no known coordinates and is never offered.
  tracker.position_mm = Eigen::Vector3d(0, 0, 2000);
  Pose<double> flange;
  EXPECT_EQ(visible_targets(tracker, flange, tool), (std::vector<int>{0, 2}));
  // Turn the flange about y by -50.19°: target 2 now faces the tracker, target 1 is 50° off.
  flange.R =
      Eigen::AngleAxisd(-std::atan2(150.0, 125.0), Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_EQ(visible_targets(tracker, flange, tool), (std::vector<int>{1}));
  // An explicit axis overrides the default.
  tracker.smr_axes_flange = {Eigen::Vector3d(1, 0, 0)};
  EXPECT_TRUE(smr_axis_flange(tracker, tool, 0).isApprox(Eigen::Vector3d::UnitX()));
}

TEST(InstrumentOpticalCmm, FacingLimitEdges) {
  OpticalCmm cmm;
  cmm.position_mm = Eigen::Vector3d(0, 0, 2500);
  cmm.face_normals_flange = {Eigen::Vector3d::UnitZ()};
  Tool tool;
  Pose<double> flange;  // tool centre at the origin, face normal straight at the camera
  EXPECT_EQ(facing_face(cmm, flange, tool), 0);
  for (const double angle : {14.9, 15.0}) {
    flange.R = Eigen::AngleAxisd(deg2rad(angle), Eigen::Vector3d::UnitX()).toRotationMatrix();
    EXPECT_TRUE(cmm_sees_tool(cmm, flange, tool)) << angle;
  }
  flange.R = Eigen::AngleAxisd(deg2rad(15.1), Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_FALSE(cmm_sees_tool(cmm, flange, tool));
  // Out of the working volume.
  flange.R.setIdentity();
  cmm.position_mm = Eigen::Vector3d(0, 0, 900);
  EXPECT_FALSE(cmm_sees_tool(cmm, flange, tool));
  cmm.position_mm = Eigen::Vector3d(0, 0, 4100);
  EXPECT_FALSE(cmm_sees_tool(cmm, flange, tool));
}

TEST(InstrumentOpticalCmm, PicksTheFaceClosestToTheLineOfSight) {
  OpticalCmm cmm;  // default spatial artifact: +z, +x, -x, +y, -y
  cmm.position_mm = Eigen::Vector3d(-2500, 0, 0);
  Tool tool;
  Pose<double> flange;
  EXPECT_EQ(facing_face(cmm, flange, tool), 2);  // the -x face looks at a camera on -x
  // The tool centre matters, not the flange origin: a TCP 1 m out along +z puts the camera
  // 21.8° off the -x face, beyond the limit.
  tool.flange_T_tcp.translation() = Eigen::Vector3d(0, 0, 1000);
  EXPECT_FALSE(cmm_sees_tool(cmm, flange, tool));
}

TEST(InstrumentOpticalCmm, PoseNoiseMatchesSigma) {
  OpticalCmm cmm;
  cmm.sigma_mm = 0.05;
  cmm.sigma_orientation_deg = 0.03;
  auto rng = test::seeded_rng(12);
  Pose<double> truth;
  truth.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  truth.p = Eigen::Vector3d(400, 100, 600);
  Eigen::MatrixXd errors(kSamples, 6);
  for (int i = 0; i < kSamples; ++i) {
    const Pose<double> reading = read_pose(cmm, truth, rng);
    const Eigen::AngleAxisd delta(truth.R.transpose() * reading.R);  // rotation in the tool frame
    errors.row(i).head<3>() = reading.p - truth.p;
    errors.row(i).tail<3>() = rad2deg(delta.angle()) * delta.axis();
    ASSERT_NEAR((reading.R.transpose() * reading.R - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
  }
  const ColumnStats s = column_stats(errors);
  for (int k = 0; k < 6; ++k) {
    SCOPED_TRACE(k);
    const double sigma = k < 3 ? cmm.sigma_mm : cmm.sigma_orientation_deg;
    EXPECT_LT(std::abs(s.mean[k]), 4 * sigma / std::sqrt(double(kSamples)));
    EXPECT_NEAR(s.std[k] / sigma, 1.0, 0.03);
  }
}

TEST(InstrumentBallbar, ReadableOnlyWithinOneMillimetre) {
  Ballbar ballbar;
  ballbar.centre_mm = Eigen::Vector3d(300, 0, 200);
  ballbar.nominal_length_mm = 150;
  EXPECT_TRUE(ballbar_readable(ballbar, 150.0));
  EXPECT_TRUE(ballbar_readable(ballbar, 150.999));
  EXPECT_TRUE(ballbar_readable(ballbar, 149.0));
  EXPECT_FALSE(ballbar_readable(ballbar, 151.001));
  EXPECT_FALSE(ballbar_readable(ballbar, 148.999));
  auto rng = test::seeded_rng(13);
  EXPECT_FALSE(read_length(ballbar, ballbar.centre_mm + Eigen::Vector3d(0, 0, 151.5), rng));
  EXPECT_TRUE(read_length(ballbar, ballbar.centre_mm + Eigen::Vector3d(0, 0, 150.5), rng));
}

TEST(InstrumentBallbar, NoiseIsHalfAMicrometre) {
  Ballbar ballbar;
  ballbar.centre_mm = Eigen::Vector3d(300, 0, 200);
  auto rng = test::seeded_rng(14);
  const Eigen::Vector3d direction = Eigen::Vector3d(1, -2, 2).normalized();
  const double true_length = 100.4;
  Eigen::MatrixXd errors(kSamples, 1);
  for (int i = 0; i < kSamples; ++i) {
    const auto reading = read_length(ballbar, ballbar.centre_mm + true_length * direction, rng);
    ASSERT_TRUE(reading);
    errors(i, 0) = *reading - true_length;
  }
  const ColumnStats s = column_stats(errors);
  EXPECT_LT(std::abs(s.mean[0]), 4 * 0.00051 / std::sqrt(double(kSamples)));
  EXPECT_NEAR(s.std[0] / 0.00051, 1.0, 0.03);
}

TEST(InstrumentKinds, NamesRoundTripAndBadNamesAreRejected) {
  for (const auto kind :
       {InstrumentKind::LaserTracker, InstrumentKind::OpticalCmm, InstrumentKind::Ballbar})
    EXPECT_EQ(parse_instrument_kind(instrument_name(kind), "--instrument"), kind);
  try {
    parse_instrument_kind("theodolite", "--instrument");
    FAIL() << "accepted an unknown instrument";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--instrument"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("laser-tracker"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace robcal
