#pragma once
/// \file
/// What instruments deliver, in memory: one record per CSV row (docs/method/04-identification.md
/// §1, 06-instruments.md §1). Joints are the controller's values in rad (files hold degrees);
/// positions in mm in the instrument's (world) frame.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

enum class MeasurementKind {
  Points,    ///< laser tracker / CMM probe: one target position per row
  Poses,     ///< optical CMM / hexapod: 6D pose of the tool (TCP) frame per row
  Distances  ///< ballbar: distance from a target to a fixed centre per row
};

/// `config,target,j1..j6,x,y,z` (+ `approach`: how the program reached the configuration, each
/// joint from below or above, which the backlash group needs, docs/method/03-error-model.md §6;
/// from below when the file does not say, the measurement programs' practice).
struct PointMeasurement {
  std::string config;  ///< configuration label as written in the file
  int target = 0;      ///< index into Tool::targets
  Vector6d joints = Vector6d::Zero();
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();
  int line = 0;                          ///< 1-based line in the source file (0: not from a file)
  Vector6d approach = Vector6d::Ones();  ///< per joint: +1 from below, −1 from above, 0 unknown
  int payload = -1;  ///< index into Tool::payloads (`payload` column); -1: the tool's payload
  /// The arm's temperature (°C, `temperature` column), the thermal group's input
  /// (docs/method/03-error-model.md §8); none: at the robot's reference temperature.
  std::optional<double> temperature_c{};
  /// When the row was measured (s since the arm started working, `time_s` column), the warm-up
  /// group's input when no temperature is recorded (docs/method/03-error-model.md §10); none:
  /// cold.
  std::optional<double> time_s{};
};

/// `config,j1..j6,x,y,z,qw,qx,qy,qz`: world_T_tcp.
struct PoseMeasurement {
  std::string config;
  Vector6d joints = Vector6d::Zero();
  Pose<double> world_T_tcp;
  int line = 0;
  Vector6d approach = Vector6d::Ones();   ///< as PointMeasurement::approach
  int payload = -1;                       ///< as PointMeasurement::payload
  std::optional<double> temperature_c{};  ///< as PointMeasurement::temperature_c
  std::optional<double> time_s{};         ///< as PointMeasurement::time_s
};

/// `config,target,j1..j6,length`: |p_target − centre| in mm.
struct DistanceMeasurement {
  std::string config;
  int target = 0;
  Vector6d joints = Vector6d::Zero();
  double length_mm = 0;
  int line = 0;
  Vector6d approach = Vector6d::Ones();   ///< as PointMeasurement::approach
  int payload = -1;                       ///< as PointMeasurement::payload
  std::optional<double> temperature_c{};  ///< as PointMeasurement::temperature_c
  std::optional<double> time_s{};         ///< as PointMeasurement::time_s
};

/// The rows of one measurement file; exactly one of the three vectors is filled.
struct MeasurementSet {
  MeasurementKind kind = MeasurementKind::Points;
  std::string file;  ///< where the rows came from (for messages)
  std::vector<PointMeasurement> points;
  std::vector<PoseMeasurement> poses;
  std::vector<DistanceMeasurement> distances;

  [[nodiscard]] size_t size() const {
    switch (kind) {
      case MeasurementKind::Points:
        return points.size();
      case MeasurementKind::Poses:
        return poses.size();
      case MeasurementKind::Distances:
        return distances.size();
    }
    return 0;
  }
  /// The payload row `row` carried (any kind): index into Tool::payloads, -1 the tool's own.
  [[nodiscard]] int payload(size_t row) const {
    switch (kind) {
      case MeasurementKind::Points:
        return points[row].payload;
      case MeasurementKind::Poses:
        return poses[row].payload;
      case MeasurementKind::Distances:
        return distances[row].payload;
    }
    return -1;
  }
  void set_payload(size_t row, int payload) {
    switch (kind) {
      case MeasurementKind::Points:
        points[row].payload = payload;
        return;
      case MeasurementKind::Poses:
        poses[row].payload = payload;
        return;
      case MeasurementKind::Distances:
        distances[row].payload = payload;
        return;
    }
  }
  /// The temperature row `row` recorded (any kind), °C; none when the file has no such column.
  [[nodiscard]] const std::optional<double>& temperature_c(size_t row) const {
    switch (kind) {
      case MeasurementKind::Poses:
        return poses[row].temperature_c;
      case MeasurementKind::Distances:
        return distances[row].temperature_c;
      case MeasurementKind::Points:
        break;
    }
    return points[row].temperature_c;
  }
  void set_temperature_c(size_t row, std::optional<double> temperature_c) {
    switch (kind) {
      case MeasurementKind::Points:
        points[row].temperature_c = temperature_c;
        return;
      case MeasurementKind::Poses:
        poses[row].temperature_c = temperature_c;
        return;
      case MeasurementKind::Distances:
        distances[row].temperature_c = temperature_c;
        return;
    }
  }
  /// The time row `row` recorded (any kind), s; none when the file has no such column.
  [[nodiscard]] const std::optional<double>& time_s(size_t row) const {
    switch (kind) {
      case MeasurementKind::Poses:
        return poses[row].time_s;
      case MeasurementKind::Distances:
        return distances[row].time_s;
      case MeasurementKind::Points:
        break;
    }
    return points[row].time_s;
  }
  void set_time_s(size_t row, std::optional<double> time_s) {
    switch (kind) {
      case MeasurementKind::Points:
        points[row].time_s = time_s;
        return;
      case MeasurementKind::Poses:
        poses[row].time_s = time_s;
        return;
      case MeasurementKind::Distances:
        distances[row].time_s = time_s;
        return;
    }
  }
  /// Scalar residuals one row gives: 3, 6 or 1.
  [[nodiscard]] int residuals_per_row() const {
    return kind == MeasurementKind::Points ? 3 : kind == MeasurementKind::Poses ? 6 : 1;
  }
};

}  // namespace robcal
