#pragma once
/// \file
/// Predicted accuracy of a design before measuring (METHOD §5–§6): the covariance of the
/// parameters identified from the chosen configurations, C = σ²·(JᵀJ)⁻¹ (Cramér–Rao bound of
/// an unbiased estimator with independent noise σ per scalar measurement), and the position
/// error it gives over a task region, e_v = √tr(J_v C J_vᵀ).

#include <Eigen/Core>
#include <vector>

#include "robcal/design/design_matrix.hpp"

namespace robcal {

/// Covariance of the design's identifiable parameters (design.parameters, internal units)
/// when the candidates `subset` are measured with noise σ (mm) per scalar row. Computed in the
/// scaled columns and unscaled: C = S·σ²(AᵀA)⁻¹·S with S = diag(column_scale).
Eigen::MatrixXd design_parameter_covariance(const DesignMatrix& design,
                                            const std::vector<int>& subset, double sigma_mm);

struct TaskAccuracy {
  int configurations = 0;
  double mean_mm = 0, max_mm = 0;  ///< of the per-configuration RMS position error e_v
};

/// e_v = √tr(J_v C J_vᵀ) of the flange-frame point `point_flange_mm` at each task
/// configuration (controller joints, rad), J_v over `parameters` at `params`.
TaskAccuracy predict_task_accuracy(const RobotModel& model, const PointMass& payload,
                                   const ParameterVector& params,
                                   const std::vector<int>& parameters,
                                   const Eigen::MatrixXd& covariance,
                                   const std::vector<Vector6d>& task_joints,
                                   const Eigen::Vector3d& point_flange_mm);

}  // namespace robcal
