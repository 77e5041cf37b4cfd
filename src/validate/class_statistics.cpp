#include "robcal/validate/class_statistics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "robcal/kinematics/inverse_kinematics.hpp"

namespace robcal {
namespace {

/// One row per class: rows `r` with class_of(r) == c go to class c (−1: none).
template <typename ClassOf>
ClassTable table(std::string name, const std::vector<std::string>& labels,
                 const PositionErrors& errors, ClassOf class_of) {
  ClassTable out{std::move(name), {}};
  const bool poses = errors.kind == MeasurementKind::Poses;
  for (size_t c = 0; c < labels.size(); ++c) {
    std::vector<double> position, orientation;
    for (size_t r = 0; r < errors.position_error_mm.size(); ++r)
      if (class_of(r) == static_cast<int>(c)) {
        position.push_back(errors.position_error_mm[r]);
        if (poses) orientation.push_back(errors.orientation_error_deg[r]);
      }
    out.rows.push_back({labels[c], error_statistics(position), error_statistics(orientation)});
  }
  return out;
}

}  // namespace

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
                                     const std::vector<double>& region_edges_mm) {
  if (region_edges_mm.empty() || region_edges_mm.front() <= 0 ||
      !std::is_sorted(region_edges_mm.begin(), region_edges_mm.end(), std::less_equal<>()))
    throw std::invalid_argument("class_tables: region edges must be positive and ascending");
  std::vector<ArmConfig> configs;
  for (size_t r = 0; r < set.size(); ++r)
    configs.push_back(arm_config(robot.model, row_joints(set, r)));

  std::vector<ClassTable> out;
  out.push_back(table("front/back", {"front", "back"}, errors,
                      [&](size_t r) { return configs[r].back ? 1 : 0; }));
  out.push_back(
      table("up/down", {"up", "down"}, errors, [&](size_t r) { return configs[r].down ? 1 : 0; }));
  out.push_back(table("flip/no-flip", {"no-flip", "flip"}, errors,
                      [&](size_t r) { return configs[r].flip ? 1 : 0; }));
  if (set.kind == MeasurementKind::Points) {
    std::vector<std::string> names;
    for (const Target& t : robot.tool.targets) names.push_back(t.name);
    out.push_back(table("target", names, errors, [&](size_t r) { return set.points[r].target; }));
  } else {
    out.push_back(table("target", {"tcp"}, errors, [](size_t) { return 0; }));
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
    out.push_back(table("region", labels, errors, [&](size_t r) {
      return static_cast<int>(
          std::upper_bound(region_edges_mm.begin(), region_edges_mm.end(), distance[r]) -
          region_edges_mm.begin());
    }));
  }
  return out;
}

std::string value_or_no_data(const ErrorStatistics& s, double value, int decimals) {
  return s.count == 0 ? std::string("no data") : fmt::format("{:.{}f}", value, decimals);
}

}  // namespace robcal
