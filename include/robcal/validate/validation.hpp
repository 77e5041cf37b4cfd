#pragma once
/// \file
/// The whole validation of docs/method/09-validation.md §1–§2 for one model and one measurement
/// set: absolute position errors (per row, overall, per target, histogram), the same by class
/// (configuration, target, region) and distance errors over every pair of rows (absolute and
/// signed).

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/validate/class_statistics.hpp"
#include "robcal/validate/histogram.hpp"
#include "robcal/validate/pairwise_distance.hpp"
#include "robcal/validate/position_error.hpp"

namespace robcal {

struct ValidationReport {
  PositionErrors positions;
  Histogram position_histogram;      ///< kPositionHistogramBins bins over [0, max error]
  PairwiseDistanceErrors distances;  ///< 128 bins
  std::vector<ClassTable> classes;   ///< class_tables of the position (and orientation) errors
};

inline constexpr int kPositionHistogramBins = 16;

/// Validates `robot` against a points or poses set. `threads` only changes the speed.
/// Position errors of a robot whose base was never fitted compare frames that were never
/// related: callers should refuse them (the distance errors remain meaningful).
/// `calibration_mm`: the calibration set's measured positions, for the region classes.
ValidationReport validate_model(const CalibratedRobot& robot, const MeasurementSet& set,
                                int threads = 2,
                                double orientation_weight_mm = kDefaultOrientationWeightMm,
                                const std::optional<Eigen::Matrix3Xd>& calibration_mm = {});

}  // namespace robcal
