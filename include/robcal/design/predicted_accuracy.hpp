#pragma once
/// \file
/// Predicted accuracy of a design before measuring (docs/method/04-identification.md §5,
/// 05-observability.md §4): the covariance of the parameters identified from the chosen
/// configurations, C = σ²·(JᵀJ)⁻¹ (Cramér–Rao bound of an unbiased estimator with independent noise
/// σ per scalar measurement), to be turned into the position error over a task region by identify's
/// predict_position_error (identify/accuracy_prediction.hpp).

#include <Eigen/Core>
#include <vector>

#include "robcal/design/design_matrix.hpp"

namespace robcal {

/// Covariance of the design's identifiable parameters (design.parameters, internal units)
/// when the candidates `subset` are measured with noise σ (mm) per scalar row: identify's
/// design_covariance of the unscaled stacked Jacobian.
Eigen::MatrixXd design_parameter_covariance(const DesignMatrix& design,
                                            const std::vector<int>& subset, double sigma_mm);

}  // namespace robcal
