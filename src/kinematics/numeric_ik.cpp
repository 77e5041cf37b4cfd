#include "robcal/kinematics/numeric_ik.hpp"

#include <ceres/jet.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <array>
#include <cmath>

namespace robcal {
namespace {

using Jet = ceres::Jet<double, kJointCount>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

/// Flange pose and its joint Jacobian (rows: position mm, then the world-frame angular
/// velocity per unit joint rate, rad) at `joints`.
struct Linearization {
  Pose<double> pose;
  Matrix6d jacobian;
};

Linearization linearize(const RobotModel& model, const PointMass& payload,
                        const std::array<Jet, kParameterCount>& params, const Vector6d& joints) {
  std::array<Jet, kJointCount> q;
  for (int i = 0; i < kJointCount; ++i) q[i] = Jet(joints[i], i);
  const Pose<Jet> pose = flange_pose<Jet>(model, payload, params.data(), q.data());
  Linearization out;
  Eigen::Matrix3d R_dot[kJointCount];
  for (int r = 0; r < 3; ++r) {
    out.pose.p[r] = pose.p[r].a;
    out.jacobian.block<1, 6>(r, 0) = pose.p[r].v.transpose();
    for (int c = 0; c < 3; ++c) {
      out.pose.R(r, c) = pose.R(r, c).a;
      for (int j = 0; j < kJointCount; ++j) R_dot[j](r, c) = pose.R(r, c).v[j];
    }
  }
  for (int j = 0; j < kJointCount; ++j) {
    // ω^ = R_dot·Rᵀ is skew-symmetric; take its axial vector.
    const Eigen::Matrix3d W = R_dot[j] * out.pose.R.transpose();
    out.jacobian.block<3, 1>(3, j) =
        0.5 * Eigen::Vector3d(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1));
  }
  return out;
}

/// Pose error (position mm, rotation vector rad) taking `current` to `target`.
Vector6 pose_error(const Pose<double>& target, const Pose<double>& current) {
  Vector6 e;
  e.head<3>() = target.p - current.p;
  const Eigen::AngleAxisd aa(Eigen::Matrix3d(target.R * current.R.transpose()));
  e.tail<3>() = aa.angle() * aa.axis();
  return e;
}

}  // namespace

const char* to_string(NumericIkStatus status) {
  switch (status) {
    case NumericIkStatus::Converged:
      return "converged";
    case NumericIkStatus::MaxIterations:
      return "max iterations";
    case NumericIkStatus::Stalled:
      return "stalled";
  }
  return "unknown";
}

NumericIkResult numeric_ik(const RobotModel& model, const PointMass& payload,
                           const ParameterVector& params, const Pose<double>& world_T_flange,
                           const Vector6d& seed, const NumericIkOptions& options) {
  std::array<Jet, kParameterCount> p;
  for (int i = 0; i < kParameterCount; ++i) p[i] = Jet(params[i]);
  Vector6 weight;
  weight << 1, 1, 1, options.rotation_weight_mm, options.rotation_weight_mm,
      options.rotation_weight_mm;

  NumericIkResult result;
  result.joints = seed;
  Linearization lin = linearize(model, payload, p, seed);
  Vector6 error = pose_error(world_T_flange, lin.pose);
  double cost = error.cwiseProduct(weight).squaredNorm();
  double lambda = options.initial_damping;
  auto converged = [&](const Vector6& e) {
    return e.head<3>().norm() <= options.position_tolerance_mm &&
           e.tail<3>().norm() <= options.orientation_tolerance_rad;
  };
  result.status = NumericIkStatus::MaxIterations;
  for (int it = 0; it < options.max_iterations && !converged(error); ++it) {
    result.iterations = it + 1;
    const Matrix6d J = weight.asDiagonal() * lin.jacobian;
    const Matrix6d JtJ = J.transpose() * J;
    const Vector6 g = J.transpose() * error.cwiseProduct(weight);
    bool improved = false;
    // Raise the damping until a step lowers the cost (bounded: λ grows by 10 each try).
    for (int attempt = 0; attempt < 12 && !improved; ++attempt) {
      Matrix6d A = JtJ;
      A.diagonal() += lambda * (JtJ.diagonal() + Vector6::Ones());
      const Vector6d candidate = result.joints + A.ldlt().solve(g);
      const Linearization trial = linearize(model, payload, p, candidate);
      const Vector6 trial_error = pose_error(world_T_flange, trial.pose);
      const double trial_cost = trial_error.cwiseProduct(weight).squaredNorm();
      if (std::isfinite(trial_cost) && trial_cost < cost) {
        result.joints = candidate;
        lin = trial;
        error = trial_error;
        cost = trial_cost;
        lambda = std::max(lambda * 0.1, 1e-12);
        improved = true;
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) {
      result.status = NumericIkStatus::Stalled;
      break;
    }
  }
  if (converged(error)) result.status = NumericIkStatus::Converged;
  result.position_error_mm = error.head<3>().norm();
  result.orientation_error_rad = error.tail<3>().norm();
  result.within_limits = model.within_limits(result.joints);
  return result;
}

}  // namespace robcal
