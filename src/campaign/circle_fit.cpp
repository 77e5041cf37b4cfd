#include "robcal/campaign/circle_fit.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>

#include "robcal/core/error.hpp"

namespace robcal::campaign {
namespace {

/// Two unit vectors completing `n` to a right-handed orthonormal basis (u, v, n).
void tangent_basis(const Eigen::Vector3d& n, Eigen::Vector3d& u, Eigen::Vector3d& v) {
  const Eigen::Vector3d helper =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  u = n.cross(helper).normalized();
  v = n.cross(u);
}

}  // namespace

CircleFit fit_circle(const std::vector<Eigen::Vector3d>& points,
                     const std::vector<double>& angles_rad) {
  const int n_points = static_cast<int>(points.size());
  if (n_points < 4)
    throw InputError(fmt::format("a circle fit needs at least 4 points, got {}", n_points));
  if (angles_rad.size() != points.size())
    throw InputError(
        fmt::format("{} points but {} joint angles", points.size(), angles_rad.size()));

  // Plane: the smallest principal direction of the centred points.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= n_points;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : points) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  const Eigen::Vector3d& spread = eigen.eigenvalues();  // ascending
  if (spread[1] <= 1e-12 * std::max(spread[2], 1e-300))
    throw InputError("the points lie on one line: a circle needs an arc that spans a plane");
  Eigen::Vector3d n = eigen.eigenvectors().col(0);

  // Orientation: the points must turn positively about n as the angle grows.
  double turning = 0;
  for (int i = 1; i < n_points; ++i)
    turning += std::copysign(1.0, angles_rad[i] - angles_rad[i - 1]) *
               n.dot((points[i - 1] - mean).cross(points[i] - mean)) *
               (angles_rad[i] != angles_rad[i - 1] ? 1.0 : 0.0);
  if (turning == 0)
    throw InputError("the joint angles of the sweep do not change: cannot orient the axis");
  if (turning < 0) n = -n;

  // Kåsa: x² + y² + D x + E y + F = 0 in the plane, linear least squares.
  Eigen::Vector3d u, v;
  tangent_basis(n, u, v);
  Eigen::MatrixXd A(n_points, 3);
  Eigen::VectorXd b(n_points);
  for (int i = 0; i < n_points; ++i) {
    const double x = u.dot(points[i] - mean), y = v.dot(points[i] - mean);
    A.row(i) << x, y, 1.0;
    b[i] = -(x * x + y * y);
  }
  const Eigen::Vector3d kasa = A.colPivHouseholderQr().solve(b);
  CircleFit fit;
  fit.centre_mm = mean - 0.5 * kasa[0] * u - 0.5 * kasa[1] * v;
  fit.radius_mm =
      std::sqrt(std::max(0.25 * (kasa[0] * kasa[0] + kasa[1] * kasa[1]) - kasa[2], 0.0));
  fit.axis = n;
  fit.points = n_points;

  // Gauss-Newton on (c, a, b, r) with n = normalise(n0 + a·u + b·v), re-based every step.
  Eigen::MatrixXd J(2 * n_points, 6);
  Eigen::VectorXd e(2 * n_points);
  const auto residuals = [&](bool with_jacobian) {
    for (int i = 0; i < n_points; ++i) {
      const Eigen::Vector3d d = points[i] - fit.centre_mm;
      const double h = fit.axis.dot(d);
      const Eigen::Vector3d w = d - h * fit.axis;
      const double rho = w.norm();
      e[2 * i] = h;
      e[2 * i + 1] = rho - fit.radius_mm;
      if (!with_jacobian) continue;
      const Eigen::Vector3d w_hat = rho > 0 ? Eigen::Vector3d(w / rho) : Eigen::Vector3d::Zero();
      J.row(2 * i) << -fit.axis.transpose(), u.dot(d), v.dot(d), 0.0;
      J.row(2 * i + 1) << -w_hat.transpose(), -h * w_hat.dot(u), -h * w_hat.dot(v), -1.0;
    }
  };
  for (fit.iterations = 1; fit.iterations <= 50; ++fit.iterations) {
    tangent_basis(fit.axis, u, v);
    residuals(true);
    const Eigen::Matrix<double, 6, 1> step = J.colPivHouseholderQr().solve(-e);
    fit.centre_mm += step.head<3>();
    fit.axis = (fit.axis + step[3] * u + step[4] * v).normalized();
    fit.radius_mm += step[5];
    if (step.norm() < 1e-13 * (1.0 + fit.radius_mm)) break;
  }
  residuals(false);
  fit.rms_mm = std::sqrt(e.squaredNorm() / e.size());
  fit.sigma_mm = n_points > 3 ? std::sqrt(e.squaredNorm() / (e.size() - 6)) : 0.0;
  return fit;
}

}  // namespace robcal::campaign
