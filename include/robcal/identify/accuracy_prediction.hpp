#pragma once
/// \file
/// Predicted accuracy of a calibrated robot from the parameter covariance (Cramér–Rao,
/// docs/method/04-identification.md §5, 05-observability.md §4): at a configuration v the expected
/// squared position error of the model against the true robot is tr(J_v·C·J_vᵀ), C = σ²·(JᵀJ)⁻¹ the
/// covariance of the identified parameters. It needs only configurations, so it predicts a design's
/// accuracy before measuring.

#include <Eigen/Core>
#include <random>
#include <vector>

#include "robcal/model/robot_model.hpp"

namespace robcal {

/// Stacked 3×|parameters| position Jacobians of flange-frame points at configurations
/// (`targets` has one point per configuration, or a single point for all), in internal units.
Eigen::MatrixXd position_jacobian(const RobotModel& model, const PointMass& payload,
                                  const ParameterVector& params, const std::vector<int>& parameters,
                                  const std::vector<Vector6d>& joints,
                                  const std::vector<Eigen::Vector3d>& targets);

/// σ²·(JᵀJ)⁻¹ (inverse through the column-scaled normal matrix, so mm and rad mix safely).
/// J must have full column rank (see identifiability.hpp).
Eigen::MatrixXd design_covariance(const Eigen::MatrixXd& J, double sigma_mm);

/// Predicted absolute position error (mm) over validation configurations.
struct PredictedAccuracy {
  int configurations = 0;
  /// Against the true robot: e_v = √tr(J_v C J_vᵀ) per configuration; mean, RMS and maximum.
  double mean_mm = 0, rms_mm = 0, max_mm = 0;
  /// Against new measurements, which add their own noise σ per axis: √(e_v² + 3σ²).
  double measurement_sigma_mm = 0;
  double mean_vs_measurements_mm = 0, rms_vs_measurements_mm = 0;
};

/// Prediction for `covariance` over `parameters` (internal units, as from design_covariance
/// or an identification) at the validation configurations (one target per configuration, or
/// a single one).
PredictedAccuracy predict_position_error(const RobotModel& model, const PointMass& payload,
                                         const ParameterVector& params,
                                         const std::vector<int>& parameters,
                                         const Eigen::MatrixXd& covariance,
                                         const std::vector<Vector6d>& validation_joints,
                                         const std::vector<Eigen::Vector3d>& targets,
                                         double measurement_sigma_mm);

/// `count` configurations drawn uniformly inside the box [lower, upper] (controller, rad).
std::vector<Vector6d> sample_configurations(const Vector6d& lower, const Vector6d& upper, int count,
                                            std::mt19937_64& rng);

}  // namespace robcal
