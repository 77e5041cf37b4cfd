#pragma once
/// \file
/// Ballbar validation (docs/method/09-validation.md §3): the length error of each row of a
/// distances file, e_i = measured length − |p_i − c|, with p_i the model's target position at the
/// row's joints and c the ballbar's fixed centre, either given (in the model's frame) or identified
/// from these rows by least squares (3 unknowns absorbed by the fit, which the report says).

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/validate/class_statistics.hpp"
#include "robcal/validate/error_statistics.hpp"
#include "robcal/validate/position_error.hpp"

namespace robcal {

/// A QC20-W class bar reads its nominal length ± 1 mm (docs/method/06-instruments.md §1).
inline constexpr double kDefaultBallbarRangeMm = 1.0;

/// The bar's set-up the readings were checked against: it reads only nominal length ± range.
struct BallbarRange {
  double nominal_length_mm = 0;
  double range_mm = kDefaultBallbarRangeMm;
  bool length_given = false;  ///< false: the nominal length is the median reading
};

/// Checks that every reading of a distances set can come from the bar: |length − L| ≤ range.
/// `length_mm` empty: L is the median reading (a set-up at its nominal length reads around it);
/// `range_mm` empty: kDefaultBallbarRangeMm.
/// \throws InputError (key --ballbar-length or --ballbar-range) for a length or range that is
///   not positive and finite or a range not below the length; (file:line, key "length") naming
///   the first reading outside L ± range and how many are
BallbarRange check_ballbar_readings(const MeasurementSet& set, std::optional<double> length_mm,
                                    std::optional<double> range_mm);

struct BallbarErrors {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  ///< in the model's frame
  bool centre_fitted = false;
  std::vector<double> length_error_mm;  ///< per row, signed: measured − modelled
  ErrorStatistics absolute_mm;          ///< of |e_i|
  double signed_mean_mm = 0, signed_std_mm = 0;
  double positive_share = 0;  ///< share of rows with e_i > 0 (measured the longer), 0..1
  std::vector<TargetErrorStatistics> per_target;  ///< of |e_i|, targets in the tool's order
  /// Of |e_i| by configuration class (front/back, up/down, flip/no-flip): position_mm holds
  /// the length errors; count 0 for a class without rows.
  std::vector<ClassTable> classes;
};

/// Length errors of a distances set. Without `centre`, the centre minimising Σ e_i² (closed-form
/// start, then Ceres).
/// \throws InputError when the set is not a distances set, a target has no coordinates, or
///   (centre to identify) the rows do not fix a centre: fewer than four, or all on one plane
BallbarErrors ballbar_errors(const CalibratedRobot& robot, const MeasurementSet& set,
                             const std::optional<Eigen::Vector3d>& centre);

}  // namespace robcal
