#include "robcal/validate/position_error.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/identify/residuals.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal {
namespace {

/// The flange with the payload the row carried (several payloads, docs/method/03-error-model.md
/// §7), its recorded approach (the backlash group's sign, §6) and temperature (thermal, §8).
Pose<double> world_T_flange(const CalibratedRobot& robot, const MeasurementSet& set, size_t row) {
  const int payload = set.payload(row);
  if (payload >= static_cast<int>(robot.tool.payloads.size()))
    throw InputError({set.file, 0, 0, "payload"},
                     fmt::format("a row carries payload {} but the model's tool has {} payloads",
                                 payload + 1, robot.tool.payloads.size()));
  return flange_pose(robot.model, robot.tool.payload_of(payload), robot.params,
                     row_joints(set, row), row_conditions(robot.model, set, row));
}

Eigen::Vector3d target_position(const CalibratedRobot& robot, const MeasurementSet& set, int target,
                                int line) {
  if (target < 0 || target >= static_cast<int>(robot.tool.targets.size()))
    throw InputError({set.file, line, 0, "target"},
                     fmt::format("target index {} is not a target of the tool", target));
  const Target& t = robot.tool.targets[static_cast<size_t>(target)];
  if (!t.known)
    throw InputError({set.file, line, 0, "target"},
                     fmt::format("target '{}' has no coordinates in the tool (it is to be "
                                 "identified): validate a calibrated model (--model), which holds "
                                 "the identified coordinates",
                                 t.name));
  return t.position_mm;
}

}  // namespace

Eigen::Matrix3Xd predicted_positions(const CalibratedRobot& robot, const MeasurementSet& set) {
  Eigen::Matrix3Xd predicted(3, static_cast<Eigen::Index>(set.size()));
  for (size_t r = 0; r < set.size(); ++r) {
    const auto col = static_cast<Eigen::Index>(r);
    switch (set.kind) {
      case MeasurementKind::Points: {
        const PointMeasurement& m = set.points[r];
        predicted.col(col) =
            world_T_flange(robot, set, r) * target_position(robot, set, m.target, m.line);
        break;
      }
      case MeasurementKind::Poses:
        predicted.col(col) = world_T_flange(robot, set, r) * robot.tool.flange_T_tcp.translation();
        break;
      case MeasurementKind::Distances: {
        const DistanceMeasurement& m = set.distances[r];
        predicted.col(col) =
            world_T_flange(robot, set, r) * target_position(robot, set, m.target, m.line);
        break;
      }
    }
  }
  return predicted;
}

PositionErrors position_errors(const CalibratedRobot& robot, const MeasurementSet& set,
                               double orientation_weight_mm) {
  check_orientation_weight(orientation_weight_mm);
  if (set.kind == MeasurementKind::Distances)
    throw std::invalid_argument(
        "position_errors: a distances (ballbar) set has no positions to compare");
  PositionErrors out;
  out.kind = set.kind;
  out.predicted_mm = predicted_positions(robot, set);
  out.measured_mm.resize(3, static_cast<Eigen::Index>(set.size()));
  for (size_t r = 0; r < set.size(); ++r)
    out.measured_mm.col(static_cast<Eigen::Index>(r)) = set.kind == MeasurementKind::Points
                                                            ? set.points[r].position_mm
                                                            : set.poses[r].world_T_tcp.p;
  out.position_error_mm.resize(set.size());
  for (size_t r = 0; r < set.size(); ++r) {
    const auto col = static_cast<Eigen::Index>(r);
    out.position_error_mm[r] = (out.measured_mm.col(col) - out.predicted_mm.col(col)).norm();
  }
  out.position_mm = error_statistics(out.position_error_mm);

  if (set.kind == MeasurementKind::Points) {
    for (size_t t = 0; t < robot.tool.targets.size(); ++t) {
      std::vector<double> errors;
      for (size_t r = 0; r < set.size(); ++r)
        if (set.points[r].target == static_cast<int>(t)) errors.push_back(out.position_error_mm[r]);
      if (!errors.empty())
        out.per_target.push_back({robot.tool.targets[t].name, error_statistics(errors)});
    }
  } else {
    const Eigen::Matrix3d flange_R_tcp = robot.tool.flange_T_tcp.rotation();
    out.orientation_error_deg.resize(set.size());
    for (size_t r = 0; r < set.size(); ++r) {
      const Eigen::Matrix3d world_R_tcp = world_T_flange(robot, set, r).R * flange_R_tcp;
      out.orientation_error_deg[r] =
          rad2deg(rotation_distance(set.poses[r].world_T_tcp.R, world_R_tcp));
    }
    out.orientation_deg = error_statistics(out.orientation_error_deg);
    out.orientation_weight_mm = orientation_weight_mm;
    out.pose_error_mm.resize(set.size());
    for (size_t r = 0; r < set.size(); ++r)
      out.pose_error_mm[r] = std::hypot(
          out.position_error_mm[r], orientation_weight_mm * deg2rad(out.orientation_error_deg[r]));
    out.pose_mm = error_statistics(out.pose_error_mm);
  }
  return out;
}

}  // namespace robcal
