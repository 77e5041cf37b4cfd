#include "robcal/validate/validation.hpp"

#include <algorithm>

namespace robcal {

ValidationReport validate_model(const CalibratedRobot& robot, const MeasurementSet& set,
                                int threads, double orientation_weight_mm,
                                const std::optional<Eigen::Matrix3Xd>& calibration_mm) {
  ValidationReport report;
  report.positions = position_errors(robot, set, orientation_weight_mm);
  // The top edge sits just above the largest error so that it falls inside the last bin.
  const double top = std::max(report.positions.position_mm.max * (1 + 1e-9), 1e-9);
  report.position_histogram =
      make_histogram(report.positions.position_error_mm, kPositionHistogramBins, 0.0, top);
  report.distances = pairwise_distance_errors(report.positions.measured_mm,
                                              report.positions.predicted_mm, threads);
  report.classes =
      class_tables(robot, set, report.positions, calibration_mm, kDefaultRegionEdgesMm, threads);
  return report;
}

}  // namespace robcal
