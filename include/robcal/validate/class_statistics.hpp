#pragma once
/// \file
/// Validation errors split by class, as the published tables split them
/// (docs/method/09-validation.md, §10: the front/up subsets): by arm configuration (front/back,
/// up/down, flip/no-flip of the row's joints, ArmConfig's definitions in
/// kinematics/inverse_kinematics.hpp), by target, and by region (the distance from the row's
/// measured position to the nearest calibration position). Every class of a table has a row; a
/// class without validation rows has count 0, which printers show as "no data" (never a mean of
/// nothing). The configuration classes also carry the distance errors over the pairs of rows
/// both in the class, as the published front/up subsets split them.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/validate/error_statistics.hpp"
#include "robcal/validate/pairwise_distance.hpp"
#include "robcal/validate/position_error.hpp"

namespace robcal {

struct ClassRow {
  std::string label;                ///< "front", "no-flip", a target's name, "25–50 mm"…
  ErrorStatistics position_mm;      ///< count 0: no data
  ErrorStatistics orientation_deg;  ///< poses sets only (count 0 otherwise)
  /// Configuration tables: distance errors over the pairs of rows both in the class
  /// (stats.count 0, "no data", for fewer than two rows); empty for the other tables.
  std::optional<PairwiseDistanceErrors> pairs;
};

struct ClassTable {
  std::string name;  ///< "front/back", "up/down", "flip/no-flip", "target", "region"
  std::vector<ClassRow> rows;
};

/// A configuration table's classes and each row's class (an index into `labels`).
struct ClassPartition {
  std::string name;  ///< "front/back", "up/down", "flip/no-flip"
  std::vector<std::string> labels;
  std::vector<int> class_of_row;
};

/// The three configuration partitions of the rows of any set (ArmConfig on `model` at each row's
/// joints).
std::vector<ClassPartition> configuration_partitions(const RobotModel& model,
                                                     const MeasurementSet& set);

/// Region edges (mm from the nearest calibration position): classes [0, 25), [25, 50),
/// [50, 100), [100, 200), ≥ 200.
inline const std::vector<double> kDefaultRegionEdgesMm = {25, 50, 100, 200};

/// Distance from each column of `positions_mm` to the nearest column of `anchors_mm`
/// (brute force, O(N·M)). std::invalid_argument when there are no anchors.
std::vector<double> distance_to_nearest(const Eigen::Matrix3Xd& positions_mm,
                                        const Eigen::Matrix3Xd& anchors_mm);

/// Measured positions of a points or poses set (targets or TCP), one column per row.
Eigen::Matrix3Xd measured_positions(const MeasurementSet& set);

/// The class tables of `errors` (position_errors of `robot` over `set`): configuration
/// (classified on robot.model at each row's joints), target (every target of the tool, or
/// "tcp" for poses) and, when `calibration_mm` holds the calibration set's measured positions,
/// region by `region_edges_mm` (ascending, positive). `threads` only changes the speed of the
/// configuration classes' pair distances.
/// \throws std::invalid_argument for region edges that are not ascending and positive
std::vector<ClassTable> class_tables(
    const CalibratedRobot& robot, const MeasurementSet& set, const PositionErrors& errors,
    const std::optional<Eigen::Matrix3Xd>& calibration_mm,
    const std::vector<double>& region_edges_mm = kDefaultRegionEdgesMm, int threads = 1);

/// "no data" for a class without rows, else the value with `decimals` decimals.
std::string value_or_no_data(const ErrorStatistics& s, double value, int decimals = 4);

}  // namespace robcal
