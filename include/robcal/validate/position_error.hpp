#pragma once
/// \file
/// Absolute position (and orientation) errors of a model against measurements
/// (docs/method/09-validation.md §1): for every row, |measured − predicted|, where the prediction
/// is the model's target point (points files) or tool centre point (poses files) at the row's
/// joints, in the world frame.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/identify/residuals.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/validate/error_statistics.hpp"

namespace robcal {

struct TargetErrorStatistics {
  std::string target;  ///< the tool's target name
  ErrorStatistics position_mm;
};

struct PositionErrors {
  MeasurementKind kind = MeasurementKind::Points;
  Eigen::Matrix3Xd measured_mm;           ///< per row: measured target / TCP position (world, mm)
  Eigen::Matrix3Xd predicted_mm;          ///< per row: the model's prediction (world, mm)
  std::vector<double> position_error_mm;  ///< per row: |measured − predicted|
  ErrorStatistics position_mm;
  /// Points files: one entry per target that occurs, in the tool's order.
  std::vector<TargetErrorStatistics> per_target;
  std::vector<double> orientation_error_deg;  ///< poses files: rotation angle of R_meas^T R_model
  ErrorStatistics orientation_deg;            ///< poses files only
  /// Poses files: √(|Δp|² + (w·θ)²), position and orientation weighted as the calibration
  /// weighs them (w = orientation_weight_mm, mm per rad; θ the rotation angle).
  double orientation_weight_mm = kDefaultOrientationWeightMm;
  std::vector<double> pose_error_mm;
  ErrorStatistics pose_mm;
};

/// Model predictions per row: world positions of the rows' targets (points, distances) or of
/// the TCP (poses), with the robot's parameters and payload.
/// \throws InputError naming the row's line when a target has no coordinates (a target to be
///   identified, on a robot that was not calibrated)
Eigen::Matrix3Xd predicted_positions(const CalibratedRobot& robot, const MeasurementSet& set);

/// Errors of every row of a points or poses set (std::invalid_argument for distances: a
/// ballbar's lengths are compared with its centre, validate/ballbar_error.hpp).
/// \throws InputError for a weight that is not positive and finite
PositionErrors position_errors(const CalibratedRobot& robot, const MeasurementSet& set,
                               double orientation_weight_mm = kDefaultOrientationWeightMm);

}  // namespace robcal
