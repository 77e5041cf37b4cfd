#include "robcal/design/predicted_accuracy.hpp"

#include <Eigen/Cholesky>
#include <cmath>

#include "robcal/kinematics/parameter_jacobian.hpp"

namespace robcal {

Eigen::MatrixXd design_parameter_covariance(const DesignMatrix& design,
                                            const std::vector<int>& subset, double sigma_mm) {
  const Eigen::MatrixXd A = design.stacked(subset);
  const auto m = A.cols();
  const Eigen::MatrixXd scaled_inverse =
      (A.transpose() * A).llt().solve(Eigen::MatrixXd::Identity(m, m));
  return sigma_mm * sigma_mm * design.column_scale.asDiagonal() * scaled_inverse *
         design.column_scale.asDiagonal();
}

TaskAccuracy predict_task_accuracy(const RobotModel& model, const PointMass& payload,
                                   const ParameterVector& params,
                                   const std::vector<int>& parameters,
                                   const Eigen::MatrixXd& covariance,
                                   const std::vector<Vector6d>& task_joints,
                                   const Eigen::Vector3d& point_flange_mm) {
  TaskAccuracy out;
  out.configurations = static_cast<int>(task_joints.size());
  Eigen::Vector3d p;
  PositionJacobian J;
  Eigen::MatrixXd Jv(3, static_cast<Eigen::Index>(parameters.size()));
  for (const Vector6d& q : task_joints) {
    target_position_jacobian_autodiff(model, payload, params, q, point_flange_mm, &p, &J);
    for (size_t c = 0; c < parameters.size(); ++c)
      Jv.col(static_cast<Eigen::Index>(c)) = J.col(parameters[c]);
    const double e = std::sqrt((Jv * covariance * Jv.transpose()).trace());
    out.mean_mm += e / static_cast<double>(task_joints.size());
    out.max_mm = std::max(out.max_mm, e);
  }
  return out;
}

}  // namespace robcal
