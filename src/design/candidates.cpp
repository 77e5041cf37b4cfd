#include "robcal/design/candidates.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "robcal/core/error.hpp"
#include "robcal/core/progress.hpp"
#include "robcal/core/units.hpp"

namespace robcal {
namespace {

// The most candidates one selection takes: its design matrix holds about 1 kB per candidate, so
// this bounds it to a few hundred MB whatever the flag says.
constexpr int kMaxCandidates = 200000;

}  // namespace

JointConstraints unconstrained_joints() {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  JointConstraints c;
  c.range.fill(JointLimit{-kInf, kInf});
  return c;
}

JointConstraints published_joint_constraints() {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  JointConstraints c;
  c.range[0] = {deg2rad(-90), deg2rad(90)};
  c.range[1] = {0, kInf};
  c.range[2] = {deg2rad(-80), kInf};
  c.range[3] = {deg2rad(-150), deg2rad(150)};
  c.range[4] = {deg2rad(-90), deg2rad(90)};
  c.range[5] = {deg2rad(-180), deg2rad(180)};
  return c;
}

std::array<JointLimit, kJointCount> constrained_joint_box(const RobotModel& model,
                                                          const JointConstraints& constraints) {
  std::array<JointLimit, kJointCount> box{};
  for (int i = 0; i < kJointCount; ++i) {
    const double lo = std::max(model.limits[i].lower, constraints.range[i].lower);
    const double hi = std::min(model.limits[i].upper, constraints.range[i].upper);
    if (!(lo <= hi))
      throw InputError(
          {"", 0, 0, "--constraints"},
          fmt::format("joint {} has no feasible range: robot limits [{:.1f}, {:.1f}] "
                      "deg, constraint [{:.1f}, {:.1f}] deg",
                      i + 1, rad2deg(model.limits[i].lower), rad2deg(model.limits[i].upper),
                      rad2deg(constraints.range[i].lower), rad2deg(constraints.range[i].upper)));
    box[static_cast<size_t>(i)] = {lo, hi};
  }
  return box;
}

JointConstraints joint_constraints_preset(std::string_view name, std::string_view flag) {
  if (name == "published") return published_joint_constraints();
  if (name == "none") return unconstrained_joints();
  throw InputError(
      {"", 0, 0, std::string(flag)},
      fmt::format("unknown constraint preset '{}', expected 'published' or 'none'", name));
}

namespace {

bool above_floor(const std::array<Pose<double>, kJointCount>& frames, const Tool& tool,
                 double floor_z_mm) {
  // Elbow, wrist centre and flange (link frames 3..6) and every target.
  for (int i = 2; i < kJointCount; ++i)
    if (frames[i].p.z() < floor_z_mm) return false;
  for (const Target& t : tool.targets)
    if ((frames[kJointCount - 1] * t.position_mm).z() < floor_z_mm) return false;
  return true;
}

}  // namespace

CandidateSet generate_candidates(const RobotModel& model, const Tool& tool,
                                 const CandidateOptions& options, std::mt19937_64& rng) {
  if (options.count <= 0 || options.count > kMaxCandidates)
    throw InputError({"", 0, 0, "--candidates"},
                     fmt::format("expected 1 to {} candidates (the selection keeps a design-matrix "
                                 "row block of each in memory), got {}",
                                 kMaxCandidates, options.count));
  if (options.kind != MeasurementKind::Poses && tool.targets.empty())
    throw InputError({"", 0, 0, "--tool"}, "the tool has no targets to measure");
  const std::array<JointLimit, kJointCount> box = constrained_joint_box(model, options.constraints);
  std::array<std::uniform_real_distribution<double>, kJointCount> joint;
  for (size_t i = 0; i < kJointCount; ++i)
    joint[i] = std::uniform_real_distribution<double>(box[i].lower, box[i].upper);

  const ParameterVector nominal = model.nominal();
  const ParameterVector placed = options.instrument_frame_params.value_or(nominal);
  // The placement moves the whole rigid arm: world_T_flange = P · frames[5] with P the placed
  // base times the nominal base's inverse (forward_kinematics.hpp base_transform), one FK per
  // draw instead of two. Only when nothing but the base differs and no compliance bends the arm
  // (gravity would then act through the placement's tilt).
  bool rigid_placement = true;
  for (int i = kBaseParamCount; i < kParameterCount; ++i)
    rigid_placement = rigid_placement && placed[i] == nominal[i];
  for (int link = 2; link <= kJointCount; ++link)
    rigid_placement = rigid_placement && nominal[compliance_param(link)] == 0;
  const double d1 = model.mdh[0].d;
  const Pose<double> placement = detail::base_transform(placed.data(), d1, 0.0) *
                                 detail::base_transform(nominal.data(), d1, 0.0).inverse();
  const int target_count = static_cast<int>(tool.targets.size());
  CandidateSet out;
  out.candidates.reserve(static_cast<size_t>(options.count));
  const long budget = static_cast<long>(options.count) * options.draws_per_candidate;
  std::vector<int> visible_targets;
  Progress progress("drawing feasible candidate configurations", options.count);
  while (static_cast<int>(out.candidates.size()) < options.count && out.draws < budget) {
    ++out.draws;
    Candidate c;
    for (int i = 0; i < kJointCount; ++i) c.joints[i] = joint[i](rng);
    const auto frames = link_frames(model, tool.payload, nominal.data(), c.joints.data());
    if (!above_floor(frames, tool, options.floor_z_mm)) {
      ++out.below_floor;
      continue;
    }
    const Pose<double> world_T_flange = !options.instrument_frame_params ? frames[kJointCount - 1]
                                        : rigid_placement
                                            ? placement * frames[kJointCount - 1]
                                            : flange_pose(model, tool.payload, placed, c.joints);
    if (options.kind == MeasurementKind::Poses) {
      if (options.visible && !options.visible(world_T_flange, -1)) {
        ++out.not_visible;
        continue;
      }
      c.target = -1;
    } else {
      visible_targets.clear();
      for (int t = 0; t < target_count; ++t)
        if (!options.visible || options.visible(world_T_flange, t)) visible_targets.push_back(t);
      if (visible_targets.empty()) {
        ++out.not_visible;
        continue;
      }
      // One target per configuration (docs/method/05-observability.md §2: one SMR seen at a time),
      // drawn among the visible ones so every target gets used.
      c.target = visible_targets[std::uniform_int_distribution<size_t>(
          0, visible_targets.size() - 1)(rng)];
    }
    out.candidates.push_back(c);
    progress.advance();
  }
  if (out.candidates.empty())
    throw InputError(
        {"", 0, 0, out.not_visible > 0 ? "--instrument" : "--floor-mm"},
        fmt::format("no feasible candidate configuration in {} random draws: {} had a target or "
                    "the wrist below the floor (z < {:.1f} mm), {} had no target the "
                    "instrument can see",
                    out.draws, out.below_floor, options.floor_z_mm, out.not_visible));
  return out;
}

}  // namespace robcal
