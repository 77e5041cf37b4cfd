#pragma once
/// \file
/// Ballbar test path for a real set-up (docs/method/09-validation.md §3): TCP positions (the ball)
/// on a circle or on rings of a sphere of the bar's length around a taught centre, all with one
/// tool orientation; joint targets through the compensation IK of the commanding model (compensate/
/// calibrated_ik.hpp). Before anything moves, every point is checked: reachable in the asked
/// configuration, and the reading predicted by a second model (the best knowledge of the real
/// robot, e.g. a calibrated model while the nominal one commands) inside the bar's measuring
/// range: ||p_reading(q) − c| − L| ≤ range.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"

namespace robcal {

struct BallbarPathRequest {
  CalibratedRobot robot;  ///< commands the path (its world frame is the centre's)
  int target = 0;         ///< the tool's target that carries the ball (its coordinates known)
  /// Predicts the readings; default: `robot` itself (readings then exactly L).
  std::optional<CalibratedRobot> reading_model;
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  ///< taught centre, world
  double length_mm = 100;                               ///< the bar's nominal length
  double range_mm = 1.0;                                ///< the bar reads L ± range
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();      ///< the circle's normal / sphere's pole
  std::vector<double> elevations_deg = {0};             ///< rings; {0}: one circle
  int points_per_ring = 12;
  Eigen::Matrix3d world_R_tcp = Eigen::Matrix3d::Identity();
  ArmConfig config{false, false, false};
};

struct BallbarPathPoint {
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();  ///< commanded ball centre, world
  double elevation_deg = 0, azimuth_deg = 0;
  bool reachable = false;
  std::string problem;                 ///< why not reachable / out of range; empty when fine
  Vector6d joints = Vector6d::Zero();  ///< rad, when reachable
  double predicted_offset_mm = 0;      ///< predicted reading − L, when reachable
};

struct BallbarPath {
  std::vector<BallbarPathPoint> points;
  [[nodiscard]] int problems() const;
};

/// The path and its checks (problems are reported per point, not thrown).
/// \throws InputError for a length or range that is not positive, fewer than 3 points per ring,
///   an axis of zero length, an elevation outside (−90°, 90°), or a target that is not a known
///   target of the tool
BallbarPath ballbar_path(const BallbarPathRequest& request);

/// The reachable points as configurations `config,target,j1..j6` (degrees; what `robcal plan`
/// writes and `robcal simulate --configs` reads), config "B1", "B2"…
std::string ballbar_path_csv(const BallbarPath& path, const std::string& target_name);

}  // namespace robcal
