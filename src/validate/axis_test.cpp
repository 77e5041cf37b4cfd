#include "robcal/validate/axis_test.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal {
namespace {

/// Residual std with `unknowns` fitted: √(Σ e² / (n − unknowns)).
double residual_sigma(const Eigen::VectorXd& e, int unknowns) {
  return std::sqrt(e.squaredNorm() / static_cast<double>(e.size() - unknowns));
}

ErrorStatistics absolute_statistics(const Eigen::VectorXd& e) {
  std::vector<double> v(static_cast<size_t>(e.size()));
  for (Eigen::Index i = 0; i < e.size(); ++i) v[static_cast<size_t>(i)] = std::abs(e[i]);
  return error_statistics(v);
}

/// Geometric circle fit of 2-D points: centre and radius minimising Σ(|q − c| − r)².
void fit_circle(const Eigen::Matrix2Xd& q, Eigen::Vector2d& centre, double& radius) {
  // Algebraic start: |q|² = 2 q·c + (r² − |c|²), linear in (c, k).
  const Eigen::Index n = q.cols();
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    A.row(i) << 2 * q(0, i), 2 * q(1, i), 1.0;
    b[i] = q.col(i).squaredNorm();
  }
  const Eigen::Vector3d x = A.colPivHouseholderQr().solve(b);
  centre = x.head<2>();
  radius = std::sqrt(std::max(0.0, x[2] + centre.squaredNorm()));
  for (int iteration = 0; iteration < 20; ++iteration) {
    Eigen::MatrixXd J(n, 3);
    Eigen::VectorXd r(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Vector2d d = q.col(i) - centre;
      const double length = d.norm();
      r[i] = length - radius;
      J.row(i) << -d.x() / length, -d.y() / length, -1.0;
    }
    const Eigen::Vector3d step = J.colPivHouseholderQr().solve(-r);
    centre += step.head<2>();
    radius += step[2];
    if (step.norm() < 1e-13 * (1 + radius)) break;
  }
}

}  // namespace

std::vector<AxisTestMove> axis_test_moves(const AxisTestPlanRequest& request) {
  if (request.joint < 0 || request.joint >= kJointCount)
    throw InputError({"", 0, 0, "--joint"}, "expected a joint 1..6");
  if (request.steps < 3)
    throw InputError({"", 0, 0, "--steps"},
                     fmt::format("expected at least 3 positions, found {}", request.steps));
  if (!(request.to_rad > request.from_rad))
    throw InputError({"", 0, 0, "--range"}, "expected a range from < to");
  if (!(request.approach_rad > 0))
    throw InputError({"", 0, 0, "--approach"},
                     fmt::format("expected an approach distance > 0 deg, found {:g} deg",
                                 rad2deg(request.approach_rad)));
  std::vector<AxisTestMove> moves;
  for (int k = 0; k < request.steps; ++k) {
    Vector6d q = request.home;
    q[request.joint] = request.from_rad + (request.to_rad - request.from_rad) * k /
                                              static_cast<double>(request.steps - 1);
    for (const bool above : {false, true}) {
      AxisTestMove m{q, q, above};
      m.approach_from[request.joint] += above ? request.approach_rad : -request.approach_rad;
      moves.push_back(m);
    }
  }
  return moves;
}

std::string axis_test_moves_csv(const std::vector<AxisTestMove>& moves) {
  std::string csv = "move,side,j1,j2,j3,j4,j5,j6\n";
  int move = 0;
  for (const AxisTestMove& m : moves)
    for (const bool approach : {true, false}) {
      const Vector6d& q = approach ? m.approach_from : m.joints;
      csv +=
          fmt::format("{},{}", ++move, approach ? "approach" : (m.from_above ? "above" : "below"));
      for (int j = 0; j < kJointCount; ++j) csv += fmt::format(",{:.6f}", rad2deg(q[j]));
      csv += "\n";
    }
  return csv;
}

AxisTestResult axis_test_analyse(const std::vector<AxisTestSample>& input) {
  if (input.size() < 6)
    throw InputError(
        {"", 0, 0, ""},
        fmt::format("an axis test needs at least 6 positions, found {}", input.size()));
  const auto above = std::count_if(input.begin(), input.end(),
                                   [](const AxisTestSample& s) { return s.from_above; });
  if (above == 0 || above == static_cast<long>(input.size()))
    throw InputError({"", 0, 0, "side"},
                     fmt::format("the backlash needs positions approached from below and from "
                                 "above, found only '{}' rows",
                                 above == 0 ? "below" : "above"));
  // Joint order, for unwrapping the angle.
  std::vector<AxisTestSample> samples = input;
  std::stable_sort(
      samples.begin(), samples.end(),
      [](const AxisTestSample& a, const AxisTestSample& b) { return a.joint_rad < b.joint_rad; });
  if (samples.back().joint_rad - samples.front().joint_rad < deg2rad(1.0))
    throw InputError({"", 0, 0, ""}, "the joint range of an axis test must exceed 1°");
  const auto n = static_cast<Eigen::Index>(samples.size());
  Eigen::Matrix3Xd p(3, n);
  for (Eigen::Index i = 0; i < n; ++i) p.col(i) = samples[static_cast<size_t>(i)].position_mm;

  // 1. Plane.
  const Eigen::Vector3d mean = p.rowwise().mean();
  const Eigen::Matrix3Xd centred = p.colwise() - mean;
  const Eigen::JacobiSVD<Eigen::Matrix3Xd> svd(centred, Eigen::ComputeFullU);
  if (svd.singularValues()[1] < 1e-9 * (1 + svd.singularValues()[0]))
    throw InputError({"", 0, 0, ""}, "the axis test's positions lie on a line, not a circle");
  Eigen::Vector3d u = svd.matrixU().col(0), v = svd.matrixU().col(1);
  Eigen::Vector3d normal = u.cross(v);

  // 2. Circle in the plane.
  Eigen::Matrix2Xd q(2, n);
  q.row(0) = u.transpose() * centred;
  q.row(1) = v.transpose() * centred;
  Eigen::Vector2d centre;
  double radius = 0;
  fit_circle(q, centre, radius);

  // 3. Angle law, with the normal turned so that φ grows with θ.
  Eigen::VectorXd phi(n);
  const auto angles = [&] {
    for (Eigen::Index i = 0; i < n; ++i) {
      phi[i] = std::atan2(q(1, i) - centre.y(), q(0, i) - centre.x());
      if (i > 0)  // consecutive positions are less than half a turn apart
        phi[i] -= 2 * std::numbers::pi * std::round((phi[i] - phi[i - 1]) / (2 * std::numbers::pi));
    }
  };
  angles();
  if (phi[n - 1] < phi[0]) {  // reverse the plane's orientation: v → −v
    v = -v;
    normal = -normal;
    q.row(1) = -q.row(1);
    centre.y() = -centre.y();
    angles();
  }
  Eigen::MatrixXd A(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const AxisTestSample& s = samples[static_cast<size_t>(i)];
    A.row(i) << 1.0, s.joint_rad, s.from_above ? 1.0 : 0.0;
  }
  const Eigen::Vector3d law = A.colPivHouseholderQr().solve(phi);
  const Eigen::VectorXd angle_residual = phi - A * law;
  const Eigen::Matrix3d covariance =
      (A.transpose() * A).inverse() * angle_residual.squaredNorm() / static_cast<double>(n - 3);

  AxisTestResult out;
  out.samples = static_cast<int>(n);
  out.axis_direction = normal.normalized();
  out.axis_point_mm = mean + u * centre.x() + v * centre.y();
  out.radius_mm = radius;
  out.scale = law[1];
  out.backlash_deg = rad2deg(law[2] / law[1]);
  out.backlash_sigma_deg = rad2deg(std::sqrt(covariance(2, 2)) / std::abs(law[1]));

  Eigen::VectorXd axial(n), radial(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    axial[i] = normal.dot(centred.col(i));
    radial[i] = (q.col(i) - centre).norm() - radius;
  }
  const Eigen::VectorXd tangential = radius * angle_residual;
  out.axial_mm = absolute_statistics(axial);
  out.radial_mm = absolute_statistics(radial);
  out.tangential_mm = absolute_statistics(tangential);
  out.axial_sigma_mm = residual_sigma(axial, 3);
  out.radial_sigma_mm = residual_sigma(radial, 3);
  out.tangential_sigma_mm = residual_sigma(tangential, 3);
  const double s1 = q.row(0).squaredNorm(), s2 = q.row(1).squaredNorm();
  out.tilt_sigma_deg = rad2deg(out.axial_sigma_mm * std::sqrt(1 / s1 + 1 / s2));
  return out;
}

double axis_tilt_deg(const AxisTestResult& result, const Eigen::Vector3d& reference_direction) {
  const double c = std::abs(result.axis_direction.dot(reference_direction.normalized()));
  return rad2deg(std::acos(std::min(1.0, c)));
}

}  // namespace robcal
