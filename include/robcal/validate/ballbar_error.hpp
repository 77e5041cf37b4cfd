#pragma once
/// \file
/// Ballbar validation (docs/method/09-validation.md): the length error of each row of a distances
/// file, e_i = measured length − |p_i − c|, with p_i the model's target position at the row's
/// joints and c the ballbar's fixed centre, either given (in the model's frame) or identified from
/// these rows by least squares (3 unknowns absorbed by the fit, which the report says).

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/validate/error_statistics.hpp"
#include "robcal/validate/position_error.hpp"

namespace robcal {

struct BallbarErrors {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  ///< in the model's frame
  bool centre_fitted = false;
  std::vector<double> length_error_mm;  ///< per row, signed: measured − modelled
  ErrorStatistics absolute_mm;          ///< of |e_i|
  double signed_mean_mm = 0, signed_std_mm = 0;
  double positive_share = 0;  ///< share of rows with e_i > 0 (measured the longer), 0..1
  std::vector<TargetErrorStatistics> per_target;  ///< of |e_i|, targets in the tool's order
};

/// Length errors of a distances set. Without `centre`, the centre minimising Σ e_i² (closed-form
/// start, then Ceres).
/// \throws InputError when the set is not a distances set, a target has no coordinates, or
///   (centre to identify) the rows do not fix a centre: fewer than four, or all on one plane
BallbarErrors ballbar_errors(const CalibratedRobot& robot, const MeasurementSet& set,
                             const std::optional<Eigen::Vector3d>& centre);

}  // namespace robcal
