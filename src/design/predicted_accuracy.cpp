#include "robcal/design/predicted_accuracy.hpp"

#include "robcal/identify/accuracy_prediction.hpp"

namespace robcal {

Eigen::MatrixXd design_parameter_covariance(const DesignMatrix& design,
                                            const std::vector<int>& subset, double sigma_mm) {
  return design_covariance(design.stacked(subset) * design.column_scale.cwiseInverse().asDiagonal(),
                           sigma_mm);
}

}  // namespace robcal
