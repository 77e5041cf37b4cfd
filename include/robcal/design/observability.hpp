#pragma once
/// \file
/// Observability indices of a calibration design (docs/method/05-observability.md §1), from the
/// singular values σ_1 ≥ … ≥ σ_m of the column-scaled identification Jacobian of n configurations:
///   O1 = (σ_1·σ_2·…·σ_m)^(1/m) / √n   (the index of the published method)
///   O2 = σ_min / σ_max,  O3 = σ_min,  O4 = σ_min² / σ_max (noise amplification),
///   O5 = 1 / Σ (1/σ_i).
/// A rank-deficient Jacobian (σ_min = 0) gives 0 for every index, never NaN.

#include <Eigen/Core>
#include <vector>

#include "robcal/design/design_matrix.hpp"

namespace robcal {

struct ObservabilityIndices {
  double O1 = 0, O2 = 0, O3 = 0, O4 = 0, O5 = 0;
};

/// Indices from singular values (any order) of a Jacobian of `configurations` configurations.
ObservabilityIndices observability_from_singular_values(const Eigen::VectorXd& singular_values,
                                                        int configurations);

/// Indices of a scaled Jacobian (SVD computed here).
ObservabilityIndices observability_indices(const Eigen::MatrixXd& scaled_jacobian,
                                           int configurations);

/// Indices of a subset of the candidates of a design matrix.
ObservabilityIndices observability_indices(const DesignMatrix& design,
                                           const std::vector<int>& subset);

}  // namespace robcal
