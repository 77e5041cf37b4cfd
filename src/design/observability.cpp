#include "robcal/design/observability.hpp"

#include <Eigen/SVD>
#include <cmath>

namespace robcal {

ObservabilityIndices observability_from_singular_values(const Eigen::VectorXd& singular_values,
                                                        int configurations) {
  ObservabilityIndices out;
  const Eigen::Index m = singular_values.size();
  if (m == 0 || configurations <= 0) return out;
  const double smin = singular_values.minCoeff();
  const double smax = singular_values.maxCoeff();
  // Numerical rank test: σ_min below 1e-12·σ_max is round-off of an exact zero (a
  // rank-deficient design), which scores 0.
  if (!(smin > 1e-12 * smax)) return out;
  // Geometric mean through logarithms: the product of 30 singular values over- or underflows.
  out.O1 = std::exp(singular_values.array().log().mean()) / std::sqrt(double(configurations));
  out.O2 = smin / smax;
  out.O3 = smin;
  out.O4 = smin * smin / smax;
  out.O5 = 1.0 / singular_values.cwiseInverse().sum();
  return out;
}

ObservabilityIndices observability_indices(const Eigen::MatrixXd& scaled_jacobian,
                                           int configurations) {
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(scaled_jacobian);
  Eigen::VectorXd s = svd.singularValues();
  // A wide Jacobian (fewer rows than parameters) has m − rows zero singular values.
  if (s.size() < scaled_jacobian.cols()) {
    s.conservativeResize(scaled_jacobian.cols());
    s.tail(scaled_jacobian.cols() - svd.singularValues().size()).setZero();
  }
  return observability_from_singular_values(s, configurations);
}

ObservabilityIndices observability_indices(const DesignMatrix& design,
                                           const std::vector<int>& subset) {
  return observability_indices(design.stacked(subset), static_cast<int>(subset.size()));
}

}  // namespace robcal
