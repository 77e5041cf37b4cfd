#pragma once
/// \file
/// Whether a configuration can be measured in a cell (issue 16 item 2), and why not: joint
/// limits, the floor, collisions of the robot's links with keep-out boxes, and the line of
/// sight from the instrument to each target (range, tracker SMR cone or CMM field of view and
/// facing angle, occlusion by a link or a keep-out box).
///
/// The robot's links are capsules (a segment and a radius: cell.link_radius_mm) along its
/// nominal MDH geometry at the cell's base: a base column from the base origin to frame 1, then
/// for each link i = 1..5 the segments O_i → O_i + a_{i+1}·x_i → O_{i+1} (both fixed in link i,
/// docs/method/02-frames.md §3). The tool itself is not modelled (the flange link ends at the
/// flange origin).

#include <array>
#include <random>
#include <string>
#include <vector>

#include "robcal/campaign/cell.hpp"
#include "robcal/model/tool.hpp"

namespace robcal::campaign {

/// A link as a capsule: the points within `radius` of the segment a–b (world frame, mm).
struct Capsule {
  std::string name;  ///< "base", "link 1" … "link 5"
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double radius_mm = 0;
};

/// The robot's capsules at controller joints `joints` (rad), in the world frame.
std::vector<Capsule> link_capsules(const RobotModel& model, const ParameterVector& params,
                                   const Vector6d& joints, double radius_mm);

/// Why a configuration cannot be measured, in the order they are checked.
enum class Rejection {
  None,          ///< measurable
  JointLimits,   ///< outside the robot's joint limits
  BelowFloor,    ///< a link capsule or a target below the floor/table
  Collision,     ///< a link capsule or a target inside a keep-out box
  OutOfRange,    ///< every target outside the instrument's range
  NotFacing,     ///< tracker: no SMR within its cone; CMM: target axes beyond the facing limit
  OutsideView,   ///< CMM: targets outside the field of view
  Occluded,      ///< the line of sight crosses a link or a keep-out box
  TooFewTargets  ///< CMM: fewer visible targets than min_visible_targets
};
inline constexpr int kRejectionCount = 9;

/// "measurable", "joint limits", "below floor", "collision", "out of range", "not facing",
/// "outside view", "occluded", "too few targets".
const char* rejection_name(Rejection reason);

struct Feasibility {
  Rejection reason = Rejection::None;
  std::string detail;                ///< which link, box or target, for messages
  std::vector<int> visible_targets;  ///< indices into Tool::targets
};

/// Checks one configuration. `target` ≥ 0: that target must be visible (tracker); −1: any
/// target (tracker) or the tool as a whole (CMM, at least min_visible_targets). When no target
/// is visible the reason is that of the target that passed the most checks (range, then
/// facing, then view, then occlusion). Targets with unknown coordinates are not checked.
Feasibility check_configuration(const Cell& cell, const RobotModel& model, const Tool& tool,
                                const Vector6d& joints, int target = -1);

/// Counts of a candidate set by reason (index: Rejection).
struct RejectionCounts {
  std::array<long, kRejectionCount> count{};
  [[nodiscard]] long of(Rejection r) const { return count[static_cast<size_t>(r)]; }
};

/// Checks every configuration (with its target, −1 for any) and counts the reasons.
RejectionCounts count_rejections(const Cell& cell, const RobotModel& model, const Tool& tool,
                                 const std::vector<Vector6d>& joints,
                                 const std::vector<int>& targets);

/// Summary of counts: "measurable 53, joint limits 113, …" (reasons with a zero count left out).
std::string describe(const RejectionCounts& counts);

struct CellCandidateOptions {
  /// Controller joint ranges (rad) to draw in, e.g. design/candidates.hpp constrained_joint_box.
  std::array<JointLimit, kJointCount> box{};
  int count = 5000;
  int draws_per_candidate = 200;  ///< draw budget per wanted candidate
};

/// Measurable configurations drawn uniformly in the box, each with the target to read (tracker:
/// one of its visible targets, drawn; optical CMM: −1, the tool).
struct CellCandidates {
  std::vector<Vector6d> joints;
  std::vector<int> targets;
  RejectionCounts rejected;  ///< every draw, by reason (None: the accepted ones)
  long draws = 0;
};

/// Draws `options.count` measurable configurations in `cell` (fewer when the budget runs out).
/// \throws InputError naming the cell file when no draw at all is measurable, with the counts
///   per reason and what to change.
CellCandidates feasible_candidates(const Cell& cell, const RobotModel& model, const Tool& tool,
                                   const CellCandidateOptions& options, std::mt19937_64& rng);

/// Distance between segments p0–p1 and q0–q1 (mm).
double segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& q0, const Eigen::Vector3d& q1);

/// Distance from segment a–b to an axis-aligned box (0 when they meet).
double segment_box_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const KeepOutBox& box);

}  // namespace robcal::campaign
