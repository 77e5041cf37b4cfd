#pragma once
/// \file
/// The workflow behind `robcal validate` and Python's `validate` (docs/method/09-validation.md
/// §1–§3): a calibrated model (or the nominal robot) against a points, poses or distances (ballbar)
/// set, with the checks that the model belongs to the robot and tool, the optional base fit, and
/// the result's one JSON serializer.

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/identify/residuals.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/validate/ballbar_error.hpp"
#include "robcal/validate/histogram.hpp"
#include "robcal/validate/validation.hpp"

namespace robcal {

struct ValidateOptions {
  /// Fit the 6 base parameters to these rows first: places a model without a world frame,
  /// re-registers a calibrated one (moved robot or instrument). Not for distances sets.
  bool fit_base = false;
  int threads = 2;  ///< all-pairs distance errors; results do not depend on it
  double orientation_weight_mm = kDefaultOrientationWeightMm;  ///< poses sets: mm per rad
  std::optional<Eigen::Vector3d> ballbar_centre_mm;  ///< distances sets; empty: identified
  /// Distances sets: the bar's nominal length (empty: the median reading) and range (empty:
  /// kDefaultBallbarRangeMm); a reading outside length ± range is refused.
  std::optional<double> ballbar_length_mm, ballbar_range_mm;
  /// Measured positions of the calibration set: adds the region classes.
  std::optional<Eigen::Matrix3Xd> calibration_mm;
};

/// The files of one validation, as the CLI names them.
struct ValidateRequest {
  std::string robot;         ///< built-in robot name or robot file
  std::string tool;          ///< tool file
  std::string model;         ///< calibrated model file; empty: the nominal robot
  std::string measurements;  ///< points, poses or distances CSV
  std::string calibration;   ///< calibration points or poses CSV (region classes), optional
  ValidateOptions options;   ///< calibration_mm is read from `calibration` when given
  std::string units;  ///< of both files when they do not declare them (`--units`, as calibrate)
  std::string euler;  ///< rx,ry,rz rotation order (`--euler`, as calibrate)
};

/// How the model's positions were placed in the measurements' frame.
enum class ValidationFrame {
  Model,     ///< the model's own world frame
  Refitted,  ///< a calibrated base re-registered to these rows (fit_base)
  Fitted,    ///< a model without a world frame placed by a rigid fit to these rows (fit_base)
};

struct ValidateResult {
  std::string robot;         ///< the robot's name
  std::string level;         ///< the model's calibration level ("nominal" …)
  std::string measurements;  ///< the measurements' file (or the caller's name for them)
  MeasurementKind kind = MeasurementKind::Points;
  size_t rows = 0;
  ValidationFrame frame = ValidationFrame::Model;
  bool fit_base = false;
  int threads = 2;
  bool region_classes = false;             ///< calibration positions were given
  std::optional<ValidationReport> report;  ///< points and poses sets
  std::optional<BallbarErrors> ballbar;    ///< distances sets
  BallbarRange ballbar_range;              ///< distances sets: what the readings were checked by
  Histogram ballbar_histogram;             ///< of |length error|, kPositionHistogramBins bins
  std::vector<std::string> warnings;       ///< the files' (ignored columns…), poses without a tcp
  std::vector<std::string> notes;  ///< the model's target coordinates used instead of the tool's
};

/// Loads the files and validates. Throws InputError (located) when the model is of another
/// robot or tool, a file is bad, or an option does not fit the set (see the other overload).
ValidateResult validate(const ValidateRequest& request);

/// Validates a loaded model against loaded rows; `measurements` names them in the result and in
/// errors. Throws InputError when the model has no world frame and fit_base is not set, when
/// fit_base or a ballbar option is given for a set of the wrong kind, for a bad weight, or for
/// a ballbar reading outside the bar's range (check_ballbar_readings).
ValidateResult validate(CalibratedRobot robot, const MeasurementSet& set,
                        const ValidateOptions& options, const std::string& measurements);

/// The CLI's `--json` document: points/poses {points, position_error_mm, distance_error_mm,
/// position_histogram_mm, per_target, classes, (orientation_error_deg, pose_error_mm,
/// orientation_weight_mm_per_rad), kind, robot, level, base_fitted_to_measurements, measurements,
/// threads}; distances {rows, kind, length_error_mm, length_error_histogram_mm, ballbar_centre_mm,
/// ballbar_centre, ballbar_length_mm, ballbar_range_mm, ballbar_length, per_target, classes,
/// robot, level, measurements}. Configuration classes of points/poses carry
/// distance_error_mm over the pairs inside the class.
nlohmann::json validate_json(const ValidateResult& result);

}  // namespace robcal
