#include "robcal/campaign/feasibility.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal::campaign {
namespace {

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

double point_box_distance(const Eigen::Vector3d& p, const KeepOutBox& box) {
  return (box.min_mm - p).cwiseMax(p - box.max_mm).cwiseMax(0.0).norm();
}

/// The reflector axis of target `t` in the flange frame: the cell's, else the tracker model's
/// default (outward from the flange origin).
Eigen::Vector3d target_axis(const Cell& cell, const Tool& tool, int t) {
  for (const auto& [name, axis] : cell.instrument.target_axes_flange)
    if (name == tool.targets[static_cast<size_t>(t)].name) return axis;
  return smr_axis_flange(LaserTracker{}, tool, t);
}

/// One target's line of sight: how far it got (0 range, 1 facing, 2 view, 3 occlusion,
/// 4 visible) and why it stopped.
struct Sight {
  int stage = 0;
  Rejection reason = Rejection::None;
  std::string detail;
};

Sight sight_of(const Cell& cell, const std::vector<Capsule>& capsules, const Tool& tool,
               const Pose<double>& flange, int t) {
  const CellInstrument& in = cell.instrument;
  const std::string& name = tool.targets[static_cast<size_t>(t)].name;
  const Eigen::Vector3d p = flange * tool.targets[static_cast<size_t>(t)].position_mm;
  const Eigen::Vector3d los = in.position_mm - p;
  const double range = los.norm();
  if (range < in.min_range_mm || range > in.max_range_mm)
    return {0, Rejection::OutOfRange,
            fmt::format("target {} is {:.0f} mm from the instrument (range {:.0f}–{:.0f} mm)", name,
                        range, in.min_range_mm, in.max_range_mm)};
  const double facing = rad2deg(angle_between(flange.R * target_axis(cell, tool, t), los));
  const double limit =
      in.kind == InstrumentKind::LaserTracker ? in.cone_half_angle_deg : in.facing_limit_deg;
  if (facing > limit)
    return {1, Rejection::NotFacing,
            fmt::format("target {} faces {:.1f}° away from the instrument (limit {:.1f}°)", name,
                        facing, limit)};
  if (in.kind == InstrumentKind::OpticalCmm) {
    const double off_axis = rad2deg(angle_between(in.view_direction, -los));
    if (off_axis > in.field_of_view_deg)
      return {2, Rejection::OutsideView,
              fmt::format("target {} is {:.1f}° off the camera axis (field of view {:.1f}°)", name,
                          off_axis, in.field_of_view_deg)};
  }
  for (const Capsule& c : capsules)
    if (segment_distance(p, in.position_mm, c.a, c.b) < c.radius_mm)
      return {3, Rejection::Occluded,
              fmt::format("the line of sight to target {} crosses {}", name, c.name)};
  for (const KeepOutBox& box : cell.keep_out)
    if (segment_box_distance(p, in.position_mm, box) == 0)
      return {
          3, Rejection::Occluded,
          fmt::format("the line of sight to target {} crosses keep-out box '{}'", name, box.name)};
  return {4, Rejection::None, ""};
}

}  // namespace

const char* rejection_name(Rejection reason) {
  switch (reason) {
    case Rejection::None:
      return "measurable";
    case Rejection::JointLimits:
      return "joint limits";
    case Rejection::BelowFloor:
      return "below floor";
    case Rejection::Collision:
      return "collision";
    case Rejection::OutOfRange:
      return "out of range";
    case Rejection::NotFacing:
      return "not facing";
    case Rejection::OutsideView:
      return "outside view";
    case Rejection::Occluded:
      return "occluded";
    case Rejection::TooFewTargets:
      return "too few targets";
  }
  return "unknown";
}

double segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& q0, const Eigen::Vector3d& q1) {
  // Closest points of two segments (Ericson, Real-Time Collision Detection §5.1.9).
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  constexpr double kTiny = 1e-18;
  double s = 0, t = 0;
  if (a <= kTiny && e <= kTiny) return r.norm();
  if (a <= kTiny) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kTiny) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > kTiny ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

double segment_box_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const KeepOutBox& box) {
  // Slab test first: a segment that meets the box is at distance 0 exactly.
  double lo = 0, hi = 1;
  const Eigen::Vector3d d = b - a;
  bool meets = true;
  for (int k = 0; k < 3 && meets; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      meets = a[k] >= box.min_mm[k] && a[k] <= box.max_mm[k];
    } else {
      double t0 = (box.min_mm[k] - a[k]) / d[k], t1 = (box.max_mm[k] - a[k]) / d[k];
      if (t0 > t1) std::swap(t0, t1);
      lo = std::max(lo, t0);
      hi = std::min(hi, t1);
      meets = lo <= hi;
    }
  }
  if (meets) return 0;
  // The distance to a convex set is convex along the segment: golden-section search.
  constexpr double kGolden = 0.6180339887498949;
  double x0 = 0, x1 = 1;
  double m1 = x1 - kGolden * (x1 - x0), m2 = x0 + kGolden * (x1 - x0);
  double f1 = point_box_distance(a + m1 * d, box), f2 = point_box_distance(a + m2 * d, box);
  for (int i = 0; i < 80; ++i) {
    if (f1 <= f2) {
      x1 = m2;
      m2 = m1;
      f2 = f1;
      m1 = x1 - kGolden * (x1 - x0);
      f1 = point_box_distance(a + m1 * d, box);
    } else {
      x0 = m1;
      m1 = m2;
      f1 = f2;
      m2 = x0 + kGolden * (x1 - x0);
      f2 = point_box_distance(a + m2 * d, box);
    }
  }
  return std::min({f1, f2, point_box_distance(a, box), point_box_distance(b, box)});
}

std::vector<Capsule> link_capsules(const RobotModel& model, const ParameterVector& params,
                                   const Vector6d& joints, double radius_mm) {
  const auto frames = link_frames(model, PointMass{}, params.data(), joints.data());
  std::vector<Capsule> capsules;
  const Eigen::Vector3d foot(params[0], params[1], params[2]);
  capsules.push_back({"base", foot, frames[0].p, radius_mm});
  for (size_t i = 0; i + 1 < kJointCount; ++i) {
    const int link = static_cast<int>(i) + 2;
    const Eigen::Vector3d elbow = frames[i].p + params[link_param(link, 1)] * frames[i].R.col(0);
    const std::string name = fmt::format("link {}", i + 1);
    capsules.push_back({name, frames[i].p, elbow, radius_mm});
    capsules.push_back({name, elbow, frames[i + 1].p, radius_mm});
  }
  return capsules;
}

Feasibility check_configuration(const Cell& cell, const RobotModel& model, const Tool& tool,
                                const Vector6d& joints, int target) {
  Feasibility result;
  if (!model.within_limits(joints)) {
    result.reason = Rejection::JointLimits;
    for (int j = 0; j < kJointCount; ++j)
      if (joints[j] < model.limits[j].lower || joints[j] > model.limits[j].upper) {
        result.detail = fmt::format("joint {} at {:.2f}° is outside [{:.1f}, {:.1f}]°", j + 1,
                                    rad2deg(joints[j]), rad2deg(model.limits[j].lower),
                                    rad2deg(model.limits[j].upper));
        break;
      }
    return result;
  }
  const ParameterVector params = cell.robot_params(model);
  const std::vector<Capsule> capsules = link_capsules(model, params, joints, cell.link_radius_mm);
  const Pose<double> flange = flange_pose(model, PointMass{}, params, joints);
  std::vector<int> targets;
  for (size_t t = 0; t < tool.targets.size(); ++t)
    if (tool.targets[t].known) targets.push_back(static_cast<int>(t));

  for (size_t c = 1; c < capsules.size(); ++c)  // the base column stands on the floor
    if (std::min(capsules[c].a.z(), capsules[c].b.z()) - capsules[c].radius_mm < cell.floor_z_mm)
      return {
          Rejection::BelowFloor, fmt::format("{} reaches below the floor", capsules[c].name), {}};
  for (int t : targets)
    if ((flange * tool.targets[static_cast<size_t>(t)].position_mm).z() < cell.floor_z_mm)
      return {
          Rejection::BelowFloor,
          fmt::format("target {} is below the floor", tool.targets[static_cast<size_t>(t)].name),
          {}};
  for (const KeepOutBox& box : cell.keep_out) {
    for (const Capsule& c : capsules)
      if (segment_box_distance(c.a, c.b, box) < c.radius_mm)
        return {
            Rejection::Collision, fmt::format("{} enters keep-out box '{}'", c.name, box.name), {}};
    for (int t : targets)
      if (box.contains(flange * tool.targets[static_cast<size_t>(t)].position_mm))
        return {Rejection::Collision,
                fmt::format("target {} is inside keep-out box '{}'",
                            tool.targets[static_cast<size_t>(t)].name, box.name),
                {}};
  }

  std::vector<int> asked = targets;  // only targets with known coordinates can be checked
  if (target >= 0)
    asked.assign(static_cast<size_t>(std::count(targets.begin(), targets.end(), target)), target);
  Sight furthest{-1, Rejection::None, ""};
  for (int t : asked) {
    const Sight s = sight_of(cell, capsules, tool, flange, t);
    if (s.stage == 4)
      result.visible_targets.push_back(t);
    else if (s.stage > furthest.stage)
      furthest = s;
  }
  const bool cmm_tool = cell.instrument.kind == InstrumentKind::OpticalCmm && target < 0;
  const size_t needed = cmm_tool ? static_cast<size_t>(cell.instrument.min_visible_targets) : 1;
  if (result.visible_targets.size() >= needed) return result;
  if (!result.visible_targets.empty()) {
    result.reason = Rejection::TooFewTargets;
    result.detail = fmt::format("{} of the tool's targets visible, {} needed ({})",
                                result.visible_targets.size(), needed, furthest.detail);
    return result;
  }
  result.reason = furthest.stage < 0 ? Rejection::OutOfRange : furthest.reason;
  result.detail = furthest.stage < 0 ? "no target with known coordinates" : furthest.detail;
  return result;
}

RejectionCounts count_rejections(const Cell& cell, const RobotModel& model, const Tool& tool,
                                 const std::vector<Vector6d>& joints,
                                 const std::vector<int>& targets) {
  RejectionCounts counts;
  for (size_t i = 0; i < joints.size(); ++i)
    ++counts.count[static_cast<size_t>(
        check_configuration(cell, model, tool, joints[i], i < targets.size() ? targets[i] : -1)
            .reason)];
  return counts;
}

std::string describe(const RejectionCounts& counts) {
  std::string out;
  for (int r = 0; r < kRejectionCount; ++r)
    if (counts.count[static_cast<size_t>(r)] > 0)
      out +=
          fmt::format("{}{} {}", out.empty() ? "" : ", ", rejection_name(static_cast<Rejection>(r)),
                      counts.count[static_cast<size_t>(r)]);
  return out;
}

CellCandidates feasible_candidates(const Cell& cell, const RobotModel& model, const Tool& tool,
                                   const CellCandidateOptions& options, std::mt19937_64& rng) {
  CellCandidates out;
  const bool cmm = cell.instrument.kind == InstrumentKind::OpticalCmm;
  const long budget = static_cast<long>(options.count) * options.draws_per_candidate;
  while (static_cast<int>(out.joints.size()) < options.count && out.draws < budget) {
    Vector6d q;
    for (int j = 0; j < kJointCount; ++j)
      q[j] = std::uniform_real_distribution<double>(options.box[static_cast<size_t>(j)].lower,
                                                    options.box[static_cast<size_t>(j)].upper)(rng);
    ++out.draws;
    const Feasibility f = check_configuration(cell, model, tool, q, -1);
    ++out.rejected.count[static_cast<size_t>(f.reason)];
    if (f.reason != Rejection::None) continue;
    out.joints.push_back(q);
    out.targets.push_back(cmm ? -1
                              : f.visible_targets[std::uniform_int_distribution<size_t>(
                                    0, f.visible_targets.size() - 1)(rng)]);
  }
  if (out.joints.empty())
    throw InputError(
        {cell.file, 0, 0, "instrument"},
        fmt::format("no measurable configuration in {} random draws in this cell ({}): "
                    "check the instrument's position and range, the target axes, the "
                    "keep-out boxes and the floor",
                    out.draws, describe(out.rejected)));
  return out;
}

}  // namespace robcal::campaign
