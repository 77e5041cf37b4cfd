// Hexapod uncertainty (ISO/IEC Guide 98-3) and the world frame from the base cups
// (docs/method/07-hexapod.md).

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/hexapod/uncertainty.hpp"
#include "robcal/hexapod/world_frame.hpp"
#include "test_support.hpp"

namespace robcal::hexapod {
namespace {

TEST(HexapodUncertainty, SensitivitiesMatchFiniteDifferences) {
  const HexapodGeometry g{{301, 299, 300.5}, {150, 151, 149.5}, 300};
  const std::vector<ModeUncertainty> modes = dkp_uncertainty(g);
  ASSERT_EQ(modes.size(), 4u);
  const Distances<double> d0 = nominal_distances(g);
  for (const ModeUncertainty& m : modes) {
    const auto f = [&](const Eigen::VectorXd& x) {
      Distances<double> d;
      for (int i = 0; i < kDistanceCount; ++i) d[i] = x[i];
      const auto cups = cups_from_distances(d, mode_signs(m.mode));
      Eigen::VectorXd out(9);
      for (int j = 0; j < 3; ++j) out.segment<3>(3 * j) = (*cups)[j];
      return out;
    };
    const Eigen::MatrixXd numeric =
        test::numerical_jacobian(f, Eigen::Map<const Eigen::VectorXd>(d0.data(), 12), 1e-5);
    EXPECT_LT((numeric - m.sensitivity).cwiseAbs().maxCoeff(), 1e-6) << "mode " << m.mode;
    // Per-axis σ is the RSS of the sensitivities; the norm the RSS of the three axes.
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(m.cups[j].per_axis.x(), numeric.row(3 * j).norm(), 1e-6);
      EXPECT_NEAR(m.cups[j].norm, numeric.middleRows(3 * j, 3).norm(), 1e-6);
    }
  }
}

TEST(HexapodUncertainty, AnalyticAgreesWithMonteCarloWithinTwoPercent) {
  const HexapodGeometry g;  // 300 / 150 / 300
  const uint64_t seed = 7;
  SCOPED_TRACE(seed);
  auto rng = test::seeded_rng(seed);
  const double sigma = 0.51e-3;
  const std::vector<ModeUncertainty> analytic = dkp_uncertainty(g);
  const std::vector<ModeUncertainty> mc = dkp_uncertainty_monte_carlo(g, sigma, 40000, rng);
  ASSERT_EQ(analytic.size(), 4u);
  ASSERT_EQ(mc.size(), 4u);
  double worst = 0, worst_ratio = 0;
  for (size_t m = 0; m < 4; ++m)
    for (int j = 0; j < 3; ++j) {
      worst = std::max(worst, analytic[m].cups[j].norm);
      const double ratio = mc[m].cups[j].norm / analytic[m].cups[j].norm;
      worst_ratio = std::max(worst_ratio, std::abs(ratio - 1));
      EXPECT_NEAR(ratio, 1, 0.02) << "mode " << analytic[m].mode << " T" << j + 1;
      for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(mc[m].cups[j].per_axis[a], analytic[m].cups[j].per_axis[a],
                    0.02 * analytic[m].cups[j].per_axis[a] + 0.02)
            << "mode " << analytic[m].mode << " T" << j + 1 << " axis " << a;
    }
  std::printf("worst-case norm %.3f sigma (published about 3.2); MC agreement %.2f%%\n", worst,
              100 * worst_ratio);
  // T1 hangs from the base alone: its uncertainty is the same in every mode.
  for (size_t m = 1; m < 4; ++m)
    EXPECT_NEAR(analytic[m].cups[0].norm, analytic[0].cups[0].norm, 1e-12);
}

TEST(HexapodWorldFrame, RecoversAKnownPlanarTransform) {
  const TriangleSides sides{300.004, 299.991, 300.012};
  const Cups<double> q = fixture_cups(sides, "base");
  // The robot's points: the true triangle moved by a planar (x, y, φ), in a tilted plane.
  const Eigen::Vector3d truth(0.3, -0.2, deg2rad(0.05));
  Pose<double> plane;
  plane.R = (Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 0.5).normalized())).toRotationMatrix();
  plane.p = Eigen::Vector3d(450, -120, 80);
  Cups<double> p;
  const double c = std::cos(truth[2]), s = std::sin(truth[2]);
  for (int i = 0; i < 3; ++i)
    p[i] = plane * Eigen::Vector3d(c * q[i].x() - s * q[i].y() + truth[0],
                                   s * q[i].x() + c * q[i].y() + truth[1], 0);
  const WorldFrameFit fit = fit_world_frame(p, sides);
  EXPECT_TRUE(fit.converged);
  EXPECT_LT(fit.rms_mm, 1e-10);
  for (int i = 0; i < 3; ++i) EXPECT_LT((fit.corrected[i] - p[i]).norm(), 1e-10);
  // The world frame is the fixture frame of the true triangle.
  const Pose<double> expected = frame_from_cups(p);
  EXPECT_LT((fit.robot_T_fixture.R - expected.R).norm(), 1e-12);
  EXPECT_LT((fit.robot_T_fixture.p - expected.p).norm(), 1e-10);
}

TEST(HexapodWorldFrame, NoisyPointsMatchTheClosedFormProcrustesFit) {
  auto rng = test::seeded_rng(11);
  std::normal_distribution<double> noise(0, 0.05);
  const TriangleSides sides{299.95, 300.03, 300.02};
  const Cups<double> q = fixture_cups(sides, "base");
  Cups<double> p;
  for (int i = 0; i < 3; ++i)
    p[i] = q[i] + Eigen::Vector3d(noise(rng) + 40, noise(rng) - 7, noise(rng) * 0.1);
  const WorldFrameFit fit = fit_world_frame(p, sides);
  ASSERT_TRUE(fit.converged);
  EXPECT_LE(fit.iterations, 10);
  // Independent check: 2D Kabsch in the plane of the p's.
  const Pose<double> plane = frame_from_cups(p);
  Eigen::Matrix<double, 2, 3> A, Q;
  for (int i = 0; i < 3; ++i) {
    A.col(i) = (plane.R.transpose() * (p[i] - plane.p)).head<2>();
    Q.col(i) = q[i].head<2>();
  }
  const Eigen::Vector2d ca = A.rowwise().mean(), cq = Q.rowwise().mean();
  const Eigen::Matrix2d H = (Q.colwise() - cq) * (A.colwise() - ca).transpose();
  const double phi = std::atan2(H(0, 1) - H(1, 0), H(0, 0) + H(1, 1));
  Eigen::Matrix2d R;
  R << std::cos(phi), -std::sin(phi), std::sin(phi), std::cos(phi);
  const Eigen::Vector2d t = ca - R * cq;
  EXPECT_NEAR(fit.planar[2], phi, 1e-12);
  EXPECT_NEAR(fit.planar[0], t.x(), 1e-9);
  EXPECT_NEAR(fit.planar[1], t.y(), 1e-9);
  // The corrected triangle keeps the measured sides exactly.
  EXPECT_NEAR((fit.corrected[0] - fit.corrected[1]).norm(), sides.d12, 1e-9);
  EXPECT_NEAR((fit.corrected[1] - fit.corrected[2]).norm(), sides.d23, 1e-9);
  EXPECT_NEAR((fit.corrected[2] - fit.corrected[0]).norm(), sides.d31, 1e-9);
}

TEST(HexapodWorldFrame, CollinearPointsAndBadSidesAreErrors) {
  const Cups<double> line{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(300, 0, 0),
                          Eigen::Vector3d(600, 0, 0)};
  EXPECT_REFUSED(fit_world_frame(line, {300, 300, 300}), InputError,
                 "robot points: the three points the robot placed the base cups at are collinear");
  const Cups<double> p = fixture_cups({300, 300, 300}, "base");
  EXPECT_REFUSED(
      fit_world_frame(p, {300, 10, 10}), InputError,
      "base fixture sides: sides d12 = 300, d23 = 10, d31 = 10 mm break the triangle inequality");
  // The place is named once, not repeated in front of the problem.
  EXPECT_EQ(test::refusal_message([&] {
              (void)fit_world_frame(p, {300, 10, 10});
            }).rfind("base fixture sides: sides", 0),
            0u);
}

TEST(HexapodWorldFrame, SettingBallPointsAreAnEquilateralTriangleAroundThePlacement) {
  Pose<double> rough;
  rough.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  rough.p = Eigen::Vector3d(500, 100, -50);
  const Cups<double> c = setting_ball_points(rough, 300);
  EXPECT_NEAR((c[0] - c[1]).norm(), 300, 1e-12);
  EXPECT_NEAR((c[1] - c[2]).norm(), 300, 1e-12);
  EXPECT_NEAR((c[2] - c[0]).norm(), 300, 1e-12);
  EXPECT_LT((centroid(c) - rough.p).norm(), 1e-12);
  // Counter-clockwise seen from above: the fixture frame's z is the placement's z.
  EXPECT_LT((frame_from_cups(c).R.col(2) - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
}

}  // namespace
}  // namespace robcal::hexapod
