#include "robcal/identify/accuracy_prediction.hpp"

#include <Eigen/Dense>

#include "robcal/kinematics/parameter_jacobian.hpp"

namespace robcal {

Eigen::MatrixXd position_jacobian(const RobotModel& model, const PointMass& payload,
                                  const ParameterVector& params, const std::vector<int>& parameters,
                                  const std::vector<Vector6d>& joints,
                                  const std::vector<Eigen::Vector3d>& targets) {
  const auto n = static_cast<Eigen::Index>(joints.size());
  Eigen::MatrixXd J(3 * n, static_cast<Eigen::Index>(parameters.size()));
  PositionJacobian Jp;
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Vector3d& t = targets.size() == 1 ? targets[0] : targets[static_cast<size_t>(k)];
    target_position_jacobian(model, payload, params, joints[static_cast<size_t>(k)], t, nullptr,
                             &Jp);
    for (size_t c = 0; c < parameters.size(); ++c)
      J.block<3, 1>(3 * k, static_cast<Eigen::Index>(c)) = Jp.col(parameters[c]);
  }
  return J;
}

Eigen::MatrixXd design_covariance(const Eigen::MatrixXd& J, double sigma_mm) {
  const Eigen::VectorXd s = J.colwise().norm().cwiseMax(1e-300).cwiseInverse();
  const Eigen::MatrixXd Js = J * s.asDiagonal();
  const Eigen::MatrixXd N = Js.transpose() * Js;
  const Eigen::MatrixXd inverse = N.ldlt().solve(Eigen::MatrixXd::Identity(N.rows(), N.cols()));
  return sigma_mm * sigma_mm * s.asDiagonal() * inverse * s.asDiagonal();
}

PredictedAccuracy predict_position_error(const RobotModel& model, const PointMass& payload,
                                         const ParameterVector& params,
                                         const std::vector<int>& parameters,
                                         const Eigen::MatrixXd& covariance,
                                         const std::vector<Vector6d>& validation_joints,
                                         const std::vector<Eigen::Vector3d>& targets,
                                         double measurement_sigma_mm) {
  PredictedAccuracy out;
  out.configurations = static_cast<int>(validation_joints.size());
  out.measurement_sigma_mm = measurement_sigma_mm;
  if (validation_joints.empty()) return out;
  PositionJacobian Jp;
  Eigen::MatrixXd Jv(3, static_cast<Eigen::Index>(parameters.size()));
  double sum = 0, sum_sq = 0, sum_new = 0;
  const double noise = 3 * measurement_sigma_mm * measurement_sigma_mm;
  for (size_t k = 0; k < validation_joints.size(); ++k) {
    const Eigen::Vector3d& t = targets.size() == 1 ? targets[0] : targets[k];
    target_position_jacobian(model, payload, params, validation_joints[k], t, nullptr, &Jp);
    for (size_t c = 0; c < parameters.size(); ++c)
      Jv.col(static_cast<Eigen::Index>(c)) = Jp.col(parameters[c]);
    const double e2 = std::max(0.0, (Jv * covariance * Jv.transpose()).trace());
    sum += std::sqrt(e2);
    sum_sq += e2;
    sum_new += std::sqrt(e2 + noise);
    out.max_mm = std::max(out.max_mm, std::sqrt(e2));
  }
  const double n = static_cast<double>(validation_joints.size());
  out.mean_mm = sum / n;
  out.rms_mm = std::sqrt(sum_sq / n);
  out.mean_vs_measurements_mm = sum_new / n;
  out.rms_vs_measurements_mm = std::sqrt(sum_sq / n + noise);
  return out;
}

std::vector<Vector6d> sample_configurations(const Vector6d& lower, const Vector6d& upper, int count,
                                            std::mt19937_64& rng) {
  std::vector<Vector6d> out(static_cast<size_t>(std::max(0, count)));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (Vector6d& q : out)
    for (int i = 0; i < kJointCount; ++i) q[i] = lower[i] + (upper[i] - lower[i]) * unit(rng);
  return out;
}

}  // namespace robcal
