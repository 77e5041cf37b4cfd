#include "robcal/validate/class_statistics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "robcal/kinematics/inverse_kinematics.hpp"

namespace robcal {
namespace {

/// One row per class: row r goes to class class_of_row[r] (−1: none).
ClassTable table(std::string name, const std::vector<std::string>& labels,
                 const PositionErrors& errors, const std::vector<int>& class_of_row) {
  ClassTable out{std::move(name), {}};
  const bool poses = errors.kind == MeasurementKind::Poses;
  for (size_t c = 0; c < labels.size(); ++c) {
    std::vector<double> position, orientation;
    for (size_t r = 0; r < errors.position_error_mm.size(); ++r)
      if (class_of_row[r] == static_cast<int>(c)) {
        position.push_back(errors.position_error_mm[r]);
        if (poses) orientation.push_back(errors.orientation_error_deg[r]);
      }
    out.rows.push_back({labels[c], error_statistics(position), error_statistics(orientation), {}});
  }
  return out;
}

/// The columns of `positions` whose row is in class `c`.
Eigen::Matrix3Xd columns_of_class(const Eigen::Matrix3Xd& positions,
                                  const std::vector<int>& class_of_row, int c) {
  std::vector<Eigen::Index> columns;
  for (size_t r = 0; r < class_of_row.size(); ++r)
    if (class_of_row[r] == c) columns.push_back(static_cast<Eigen::Index>(r));
  return positions(Eigen::all, columns);
}

}  // namespace

std::vector<ClassPartition> configuration_partitions(const RobotModel& model,
                                                     const MeasurementSet& set) {
  std::vector<ClassPartition> out = {{"front/back", {"front", "back"}, {}},
                                     {"up/down", {"up", "down"}, {}},
                                     {"flip/no-flip", {"no-flip", "flip"}, {}}};
  for (ClassPartition& p : out) p.class_of_row.reserve(set.size());
  for (size_t r = 0; r < set.size(); ++r) {
    const ArmConfig config = arm_config(model, row_joints(set, r));
    out[0].class_of_row.push_back(config.back ? 1 : 0);
    out[1].class_of_row.push_back(config.down ? 1 : 0);
    out[2].class_of_row.push_back(config.flip ? 1 : 0);
  }
  return out;
}

std::vector<double> distance_to_nearest(const Eigen::Matrix3Xd& positions_mm,
                                        const Eigen::Matrix3Xd& anchors_mm) {
  if (anchors_mm.cols() == 0)
    throw std::invalid_argument("distance_to_nearest: no anchor positions");
  std::vector<double> out(static_cast<size_t>(positions_mm.cols()));
  for (Eigen::Index i = 0; i < positions_mm.cols(); ++i)
    out[static_cast<size_t>(i)] =
        std::sqrt((anchors_mm.colwise() - positions_mm.col(i)).colwise().squaredNorm().minCoeff());
  return out;
}

Eigen::Matrix3Xd measured_positions(const MeasurementSet& set) {
  if (set.kind == MeasurementKind::Distances)
    throw std::invalid_argument("measured_positions: a distances set holds no positions");
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(set.size()));
  for (size_t r = 0; r < set.size(); ++r)
    out.col(static_cast<Eigen::Index>(r)) = set.kind == MeasurementKind::Points
                                                ? set.points[r].position_mm
                                                : set.poses[r].world_T_tcp.p;
  return out;
}

std::vector<ClassTable> class_tables(const CalibratedRobot& robot, const MeasurementSet& set,
                                     const PositionErrors& errors,
                                     const std::optional<Eigen::Matrix3Xd>& calibration_mm,
                                     const std::vector<double>& region_edges_mm, int threads) {
  if (region_edges_mm.empty() || region_edges_mm.front() <= 0 ||
      !std::is_sorted(region_edges_mm.begin(), region_edges_mm.end(), std::less_equal<>()))
    throw std::invalid_argument("class_tables: region edges must be positive and ascending");
  std::vector<ClassTable> out;
  for (const ClassPartition& p : configuration_partitions(robot.model, set)) {
    ClassTable t = table(p.name, p.labels, errors, p.class_of_row);
    for (size_t c = 0; c < t.rows.size(); ++c)
      t.rows[c].pairs = pairwise_distance_errors(
          columns_of_class(errors.measured_mm, p.class_of_row, static_cast<int>(c)),
          columns_of_class(errors.predicted_mm, p.class_of_row, static_cast<int>(c)), threads);
    out.push_back(std::move(t));
  }
  if (set.kind == MeasurementKind::Points) {
    std::vector<std::string> names;
    std::vector<int> target_of_row;
    names.reserve(robot.tool.targets.size());
    target_of_row.reserve(set.points.size());
    for (const Target& t : robot.tool.targets) names.push_back(t.name);
    for (const PointMeasurement& m : set.points) target_of_row.push_back(m.target);
    out.push_back(table("target", names, errors, target_of_row));
  } else {
    out.push_back(table("target", {"tcp"}, errors, std::vector<int>(set.size(), 0)));
  }
  if (calibration_mm) {
    const std::vector<double> distance = distance_to_nearest(errors.measured_mm, *calibration_mm);
    std::vector<std::string> labels;
    double lower = 0;
    for (const double edge : region_edges_mm) {
      labels.push_back(fmt::format("{:g}–{:g} mm", lower, edge));
      lower = edge;
    }
    labels.push_back(fmt::format("≥ {:g} mm", lower));
    std::vector<int> region_of_row;
    region_of_row.reserve(distance.size());
    for (const double d : distance)
      region_of_row.push_back(
          static_cast<int>(std::upper_bound(region_edges_mm.begin(), region_edges_mm.end(), d) -
                           region_edges_mm.begin()));
    out.push_back(table("region", labels, errors, region_of_row));
  }
  return out;
}

std::string value_or_no_data(const ErrorStatistics& s, double value, int decimals) {
  return s.count == 0 ? std::string("no data") : fmt::format("{:.{}f}", value, decimals);
}

}  // namespace robcal
