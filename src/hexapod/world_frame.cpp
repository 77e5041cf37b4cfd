#include "robcal/hexapod/world_frame.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "robcal/core/error.hpp"

namespace robcal::hexapod {

WorldFrameFit fit_world_frame(const Cups<double>& p, const TriangleSides& measured) {
  const Cups<double> q = fixture_cups(measured, "base fixture sides");
  const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
  if (!(n.norm() > 1e-6 * (p[1] - p[0]).squaredNorm()))
    throw InputError({"", 0, 0, "robot points"},
                     "the three points the robot placed the base cups at are collinear");
  // The plane of the p's: origin p1, x towards p2. Both triangles are planar there.
  const Pose<double> plane = frame_from_cups(p);
  std::array<Eigen::Vector2d, 3> a, q2;
  for (int i = 0; i < 3; ++i) {
    a[i] = (plane.R.transpose() * (p[i] - plane.p)).head<2>();
    q2[i] = q[i].head<2>();
  }
  WorldFrameFit fit;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  // (x, y, φ), from the identity
  const auto residuals = [&](const Eigen::Vector3d& t, Eigen::Matrix<double, 6, 3>* J) {
    const double c = std::cos(t[2]), s = std::sin(t[2]);
    Eigen::Matrix2d R, R_dot;
    R << c, -s, s, c;
    R_dot << -s, -c, c, -s;
    Eigen::Matrix<double, 6, 1> r;
    for (Eigen::Index i = 0; i < 3; ++i) {
      r.segment<2>(2 * i) = a[i] - (R * q2[i] + t.head<2>());
      if (J) {
        J->block<2, 2>(2 * i, 0) = -Eigen::Matrix2d::Identity();
        J->block<2, 1>(2 * i, 2) = -R_dot * q2[i];
      }
    }
    return r;
  };
  for (fit.iterations = 1; fit.iterations <= 50; ++fit.iterations) {
    Eigen::Matrix<double, 6, 3> J;
    const Eigen::Matrix<double, 6, 1> r = residuals(x, &J);
    const Eigen::Vector3d step = -(J.transpose() * J).ldlt().solve(J.transpose() * r);
    x += step;
    if (step.head<2>().norm() < 1e-12 && std::abs(step[2]) < 1e-15) {
      fit.converged = true;
      break;
    }
  }
  fit.planar = x;
  fit.rms_mm = std::sqrt(residuals(x, nullptr).squaredNorm() / 3);
  const double c = std::cos(x[2]), s = std::sin(x[2]);
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d in_plane(c * q2[i].x() - s * q2[i].y() + x[0],
                                   s * q2[i].x() + c * q2[i].y() + x[1], 0);
    fit.corrected[i] = plane * in_plane;
  }
  fit.robot_T_fixture = frame_from_cups(fit.corrected);
  return fit;
}

Cups<double> setting_ball_points(const Pose<double>& robot_T_rough, double side_mm) {
  const double h = side_mm / (2 * std::sqrt(3.0));
  return {robot_T_rough * Eigen::Vector3d(-side_mm / 2, -h, 0),
          robot_T_rough * Eigen::Vector3d(side_mm / 2, -h, 0),
          robot_T_rough * Eigen::Vector3d(0, 2 * h, 0)};
}

Eigen::Vector3d fourth_setting_ball_point(const Cups<double>& points,
                                          const std::array<double, 3>& base_cup4_mm) {
  const TriangleSides sides{(points[1] - points[0]).norm(), (points[2] - points[1]).norm(),
                            (points[0] - points[2]).norm()};
  return frame_from_cups(points) * fixture_cup_positions({sides, base_cup4_mm})[3];
}

}  // namespace robcal::hexapod
