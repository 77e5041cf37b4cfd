#include "robcal/measure/instrument.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal {
namespace {

/// Angle (rad) between two non-zero vectors, robust near 0 and π (atan2 of |a×b| and a·b).
double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Visibility edges are inclusive; a tolerance keeps a target placed exactly on the cone's edge
// visible despite the rounding of the rotations that put it there.
constexpr double kEdgeTolerance = 1e-12;

}  // namespace

Eigen::Vector3d smr_axis_flange(const LaserTracker& tracker, const Tool& tool, int target) {
  if (target >= 0 && static_cast<size_t>(target) < tracker.smr_axes_flange.size())
    return tracker.smr_axes_flange[static_cast<size_t>(target)].normalized();
  const Eigen::Vector3d& p = tool.targets.at(static_cast<size_t>(target)).position_mm;
  return p.norm() > 1e-9 ? Eigen::Vector3d(p.normalized()) : Eigen::Vector3d::UnitZ();
}

bool smr_visible(const LaserTracker& tracker, const Eigen::Vector3d& smr_mm,
                 const Eigen::Vector3d& smr_axis) {
  const Eigen::Vector3d line_of_sight = tracker.position_mm - smr_mm;
  const double range = line_of_sight.norm();
  if (range < tracker.min_range_mm || range > tracker.max_range_mm || range == 0) return false;
  return angle_between(smr_axis, line_of_sight) <=
         deg2rad(tracker.cone_half_angle_deg) + kEdgeTolerance;
}

std::vector<int> visible_targets(const LaserTracker& tracker, const Pose<double>& frame_T_flange,
                                 const Tool& tool) {
  std::vector<int> visible;
  for (size_t t = 0; t < tool.targets.size(); ++t) {
    if (!tool.targets[t].known) continue;
    const int index = static_cast<int>(t);
    if (smr_visible(tracker, frame_T_flange * tool.targets[t].position_mm,
                    frame_T_flange.R * smr_axis_flange(tracker, tool, index)))
      visible.push_back(index);
  }
  return visible;
}

Eigen::Vector3d read_point(const LaserTracker& tracker, const Eigen::Vector3d& smr_mm,
                           std::mt19937_64& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  Eigen::Vector3d reading = smr_mm;
  for (int k = 0; k < 3; ++k) reading[k] += tracker.sigma_mm[k] * unit(rng);
  return reading;
}

std::optional<int> facing_face(const OpticalCmm& cmm, const Pose<double>& frame_T_flange,
                               const Tool& tool) {
  const Eigen::Vector3d tcp = frame_T_flange * Eigen::Vector3d(tool.flange_T_tcp.translation());
  const Eigen::Vector3d line_of_sight = cmm.position_mm - tcp;
  const double range = line_of_sight.norm();
  if (range < cmm.min_range_mm || range > cmm.max_range_mm || range == 0) return std::nullopt;
  std::optional<int> best;
  double best_angle = deg2rad(cmm.facing_limit_deg) + kEdgeTolerance;
  for (size_t f = 0; f < cmm.face_normals_flange.size(); ++f) {
    const double angle =
        angle_between(frame_T_flange.R * cmm.face_normals_flange[f], line_of_sight);
    if (angle <= best_angle) {
      best_angle = angle;
      best = static_cast<int>(f);
    }
  }
  return best;
}

bool cmm_sees_tool(const OpticalCmm& cmm, const Pose<double>& frame_T_flange, const Tool& tool) {
  return facing_face(cmm, frame_T_flange, tool).has_value();
}

Pose<double> read_pose(const OpticalCmm& cmm, const Pose<double>& frame_T_tcp,
                       std::mt19937_64& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  Pose<double> reading = frame_T_tcp;
  for (int k = 0; k < 3; ++k) reading.p[k] += cmm.sigma_mm * unit(rng);
  Eigen::Vector3d rotation_vector;
  for (int k = 0; k < 3; ++k) rotation_vector[k] = deg2rad(cmm.sigma_orientation_deg) * unit(rng);
  const double angle = rotation_vector.norm();
  if (angle > 0)
    reading.R =
        frame_T_tcp.R * Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
  return reading;
}

bool ballbar_readable(const Ballbar& ballbar, double length_mm) {
  return std::abs(length_mm - ballbar.nominal_length_mm) <= ballbar.range_mm + kEdgeTolerance;
}

std::optional<double> read_length(const Ballbar& ballbar, const Eigen::Vector3d& cup_mm,
                                  std::mt19937_64& rng) {
  const double length = (cup_mm - ballbar.centre_mm).norm();
  if (!ballbar_readable(ballbar, length)) return std::nullopt;
  std::normal_distribution<double> unit(0.0, 1.0);
  return length + ballbar.sigma_mm * unit(rng);
}

InstrumentKind parse_instrument_kind(const std::string& name, const std::string& flag) {
  if (name == "laser-tracker") return InstrumentKind::LaserTracker;
  if (name == "optical-cmm") return InstrumentKind::OpticalCmm;
  if (name == "ballbar") return InstrumentKind::Ballbar;
  throw InputError({"", 0, 0, flag}, "unknown instrument '" + name +
                                         "'; expected laser-tracker, optical-cmm or ballbar");
}

std::string instrument_name(InstrumentKind kind) {
  switch (kind) {
    case InstrumentKind::LaserTracker:
      return "laser-tracker";
    case InstrumentKind::OpticalCmm:
      return "optical-cmm";
    case InstrumentKind::Ballbar:
      return "ballbar";
  }
  return "";
}

}  // namespace robcal
