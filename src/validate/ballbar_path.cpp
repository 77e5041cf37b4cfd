#include "robcal/validate/ballbar_path.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal {
namespace {

/// The robot with its TCP at the ball: the flange_T_tcp translation is the target's position.
CalibratedRobot ball_as_tcp(CalibratedRobot robot, int target) {
  robot.tool.flange_T_tcp.translation() =
      robot.tool.targets[static_cast<size_t>(target)].position_mm;
  return robot;
}

}  // namespace

int BallbarPath::problems() const {
  return static_cast<int>(std::count_if(
      points.begin(), points.end(), [](const BallbarPathPoint& p) { return !p.problem.empty(); }));
}

BallbarPath ballbar_path(const BallbarPathRequest& request) {
  if (!(request.length_mm > 0))
    throw InputError({"", 0, 0, "--length"},
                     fmt::format("expected a positive length in mm, found {}", request.length_mm));
  if (!(request.range_mm > 0))
    throw InputError({"", 0, 0, "--range"},
                     fmt::format("expected a positive range in mm, found {}", request.range_mm));
  if (request.range_mm >= request.length_mm)
    throw InputError({"", 0, 0, "--range"},
                     fmt::format("the bar reads --length ± --range: a range of {:g} mm must be "
                                 "below the length, {:g} mm",
                                 request.range_mm, request.length_mm));
  if (request.points_per_ring < 3)
    throw InputError({"", 0, 0, "--points"}, "at least 3 points per ring");
  if (!(request.axis.norm() > 0) || !request.axis.allFinite())
    throw InputError({"", 0, 0, "--axis"}, "the axis must be a non-zero direction");
  for (const double e : request.elevations_deg)
    if (!(std::abs(e) < 90))
      throw InputError({"", 0, 0, "--elevations"},
                       fmt::format("elevations must lie strictly within ±90°, found {}°", e));
  const auto& targets = request.robot.tool.targets;
  if (request.target < 0 || request.target >= static_cast<int>(targets.size()) ||
      !targets[static_cast<size_t>(request.target)].known)
    throw InputError({"", 0, 0, "--target"},
                     fmt::format("the ball's target must be a target of the tool with known "
                                 "coordinates; target index {} is not (the tool has {} targets)",
                                 request.target, targets.size()));

  const CalibratedRobot commanding = ball_as_tcp(request.robot, request.target);
  const CalibratedRobot reading =
      ball_as_tcp(request.reading_model.value_or(request.robot), request.target);
  const Compensator compensator = make_compensator(commanding);
  // An orthonormal frame (e1, e2, axis) for the rings.
  const Eigen::Vector3d axis = request.axis.normalized();
  const Eigen::Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  BallbarPath path;
  Vector6d near = Vector6d::Zero();
  for (const double elevation : request.elevations_deg)
    for (int k = 0; k < request.points_per_ring; ++k) {
      BallbarPathPoint p;
      p.elevation_deg = elevation;
      p.azimuth_deg = 360.0 * k / request.points_per_ring;
      const double el = deg2rad(elevation), az = deg2rad(p.azimuth_deg);
      p.position_mm = request.centre_mm +
                      request.length_mm * (std::cos(el) * (std::cos(az) * e1 + std::sin(az) * e2) +
                                           std::sin(el) * axis);
      const CalibratedIkResult ik =
          calibrated_ik(compensator, {request.world_R_tcp, p.position_mm}, request.config, near);
      p.reachable = ik.ok();
      if (!p.reachable) {
        p.problem =
            fmt::format("not reachable in {}: {}", request.config.label(), to_string(ik.status));
      } else {
        p.joints = ik.joints;
        near = ik.joints;
        const Pose<double> flange =
            flange_pose(reading.model, reading.tool.payload, reading.params, p.joints);
        const Eigen::Vector3d ball = flange * reading.tool.flange_T_tcp.translation();
        p.predicted_offset_mm = (ball - request.centre_mm).norm() - request.length_mm;
        if (std::abs(p.predicted_offset_mm) > request.range_mm)
          p.problem = fmt::format(
              "predicted reading {:+.3f} mm off the bar's length, outside its "
              "±{:g} mm range",
              p.predicted_offset_mm, request.range_mm);
      }
      path.points.push_back(p);
    }
  return path;
}

std::string ballbar_path_csv(const BallbarPath& path, const std::string& target_name) {
  std::string out = "config,target,j1,j2,j3,j4,j5,j6\n";
  int n = 0;
  for (const BallbarPathPoint& p : path.points) {
    if (!p.reachable) continue;
    out += fmt::format("B{},{}", ++n, target_name);
    for (int j = 0; j < kJointCount; ++j) out += fmt::format(",{:.9f}", rad2deg(p.joints[j]));
    out += "\n";
  }
  return out;
}

}  // namespace robcal
