#pragma once
/// \file
/// Candidate calibration configurations (docs/method/05-observability.md §2): random controller
/// joint values inside the robot's limits and the user's joint constraints, every target and the
/// wrist above a floor/table plane, and a target the instrument can see.

#include <array>
#include <functional>
#include <optional>
#include <random>
#include <string_view>
#include <vector>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/model/robot_model.hpp"
#include "robcal/model/tool.hpp"

namespace robcal {

/// Extra joint ranges (controller values, rad) intersected with the robot's limits.
/// Unbounded sides are ±infinity.
struct JointConstraints {
  std::array<JointLimit, kJointCount> range;
};

/// No constraint beyond the robot's limits.
JointConstraints unconstrained_joints();

/// The published test constraints (docs/method/05-observability.md §2): θ2 ≥ 0°, θ3 ≥ −80°
/// (one-signed gearbox torques, so the linear spring model holds), |θ1| ≤ 90°, |θ4| ≤ 150°, |θ5| ≤
/// 90°, |θ6| ≤ 180°.
JointConstraints published_joint_constraints();

/// The robot's limits intersected with `constraints` (controller values, rad). Throws
/// InputError (key `--constraints`) naming the joint when a range is empty.
std::array<JointLimit, kJointCount> constrained_joint_box(const RobotModel& model,
                                                          const JointConstraints& constraints);

/// A preset by name: "published" or "none". Throws InputError (key `flag`) for other names.
JointConstraints joint_constraints_preset(std::string_view name,
                                          std::string_view flag = "--constraints");

/// Whether an instrument can measure target `target` (index into Tool::targets; -1 means the
/// tool as a whole, for pose instruments) with the flange at `world_T_flange`. The instrument
/// models (measure/instrument.hpp) provide these.
using VisibilityPredicate = std::function<bool(const Pose<double>& world_T_flange, int target)>;

struct CandidateOptions {
  JointConstraints constraints = published_joint_constraints();
  /// Every target, the flange and the wrist centre must be above z = floor_z_mm (world frame).
  double floor_z_mm = 0;
  int count = 5000;
  /// Random draws allowed per wanted candidate before giving up.
  int draws_per_candidate = 200;
  /// Points and Distances: one target per configuration, drawn among the visible ones;
  /// Poses: the whole tool (target -1).
  MeasurementKind kind = MeasurementKind::Points;
  /// Empty: the instrument sees everything.
  VisibilityPredicate visible;
  /// The robot's parameters in the instrument's frame (its base placement), used for the
  /// flange pose given to `visible`; empty: the nominal robot at the origin. The floor is
  /// always tested in the robot's base frame.
  std::optional<ParameterVector> instrument_frame_params;
};

/// One candidate measurement: a configuration and the target it measures (-1: the tool pose),
/// with the side each joint is approached from and the payload carried (the backlash and
/// several-payload groups' conditions, docs/method/03-error-model.md §6–§7).
struct Candidate {
  Vector6d joints = Vector6d::Zero();  ///< controller values, rad
  int target = 0;
  Vector6d approach = Vector6d::Ones();  ///< per joint +1 from below, −1 from above
  int payload = -1;                      ///< index into Tool::payloads, −1 the tool's own
};

/// The candidates and why draws were rejected (for messages and reports).
struct CandidateSet {
  std::vector<Candidate> candidates;
  long draws = 0;
  long below_floor = 0;  ///< draws with a target, the flange or the wrist below the floor
  long not_visible = 0;  ///< draws above the floor where the instrument saw no target
};

/// Draws feasible candidates uniformly in the constrained joint box, seeded by `rng`.
/// Throws InputError when the constraints leave an empty joint range, or when no draw is
/// feasible (saying whether the floor or the instrument rejected them). Returns fewer than
/// `options.count` candidates when the draw budget runs out first.
CandidateSet generate_candidates(const RobotModel& model, const Tool& tool,
                                 const CandidateOptions& options, std::mt19937_64& rng);

}  // namespace robcal
