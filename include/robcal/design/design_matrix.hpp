#pragma once
/// \file
/// The column-scaled identification Jacobian of every candidate measurement
/// (docs/method/04-identification.md §1, 05-observability.md §1), the matrix every observability
/// index and selection algorithm works on.
///
/// Rows per candidate: 3 for points (target position, mm), 6 for poses (TCP position, mm, and
/// orientation as a small rotation vector times `orientation_lever_mm`, so its rows are mm
/// too), 1 for distances (ballbar length, mm).
///
/// Column scaling: each parameter's column is divided by its RMS norm per candidate over the
/// whole candidate set, sqrt(Σ_i |A_i e_j|² / N). Every column of a random n-subset then has
/// norm ≈ √n whatever its unit (mm or rad), which is what makes O1 = (Π σ)^(1/m)/√n comparable
/// across sets and parameters. The same scale is used for every subset of the candidates.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "robcal/design/candidates.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/model/robot_model.hpp"
#include "robcal/model/tool.hpp"

namespace robcal {

struct DesignSettings {
  MeasurementKind kind = MeasurementKind::Points;
  std::vector<int> parameters;        ///< layout indices asked for (e.g. level_parameters("full"))
  double orientation_lever_mm = 100;  ///< poses: rotation rows × this
  Eigen::Vector3d ballbar_centre_mm = Eigen::Vector3d::Zero();  ///< distances: fixed centre
  /// Where to linearise (e.g. the robot placed in the instrument's frame); empty: nominal.
  std::optional<ParameterVector> linearisation;
};

struct DesignMatrix {
  int rows_per_candidate = 3;
  std::vector<int> parameters;   ///< identifiable parameters = columns (layout indices)
  std::vector<int> dropped;      ///< asked for but linearly dependent on earlier ones (link3.d)
  Eigen::VectorXd column_scale;  ///< raw column × scale = stored column
  /// Scaled Jacobian rows, candidate i owns rows [i·r, i·r + r).
  Eigen::MatrixXd rows;

  [[nodiscard]] int candidates() const {
    return static_cast<int>(rows.rows()) / rows_per_candidate;
  }
  [[nodiscard]] int columns() const { return static_cast<int>(rows.cols()); }
  [[nodiscard]] auto block(int candidate) const {
    return rows.middleRows(static_cast<Eigen::Index>(candidate) * rows_per_candidate,
                           rows_per_candidate);
  }
  /// The stacked scaled Jacobian of a subset of candidates.
  [[nodiscard]] Eigen::MatrixXd stacked(const std::vector<int>& subset) const;
};

/// Unscaled identification Jacobian rows of one candidate for every layout parameter
/// (rows_per_candidate × kParameterCount) at `params` (used as given).
Eigen::MatrixXd candidate_jacobian(const RobotModel& model, const Tool& tool,
                                   const ParameterVector& params, const Candidate& candidate,
                                   const DesignSettings& settings);

/// Builds the scaled design matrix of all candidates, dropping the asked parameters that are
/// linearly dependent on earlier ones (in layout order) over the whole candidate set.
DesignMatrix build_design_matrix(const RobotModel& model, const Tool& tool,
                                 const std::vector<Candidate>& candidates,
                                 const DesignSettings& settings);

}  // namespace robcal
