#pragma once
/// \file
/// Simulated measurement campaigns: a true robot (sim/true_robot.hpp) moved through planned or
/// random configurations and read by a virtual instrument (measure/instrument.hpp). The result
/// is the same MeasurementSet a real instrument's file gives, so the pipeline cannot tell the
/// difference.

#include <functional>
#include <random>
#include <string>
#include <vector>

#include "robcal/core/error.hpp"
#include "robcal/design/candidates.hpp"
#include "robcal/measure/instrument.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/sim/true_robot.hpp"

namespace robcal {

/// One configuration to measure: controller joints (rad) and the target to read (index into
/// Tool::targets; −1 lets the instrument pick a visible one), the side each joint is approached
/// from and the payload carried (the backlash and several-payload groups,
/// docs/method/03-error-model.md §6–§7; the plan asks for them when those groups are identified).
struct PlannedConfiguration {
  std::string name;
  Vector6d joints = Vector6d::Zero();
  int target = -1;
  /// Per joint +1: approached from below (from q − 5°, the measurement programs' default), −1:
  /// from above.
  Vector6d approach = Vector6d::Ones();
  int payload = -1;  ///< index into Tool::payloads; −1: the tool's own payload
};

/// Reads `config,target,j1..j6` (degrees; what `robcal plan` writes; `target` may be empty or
/// absent) with optional `approach` ("+-++++", as measurement files have it) and `payload` (a
/// name under the tool's `payloads:`, empty: its own) columns. Errors name the file, line and
/// column. Other columns are ignored.
std::vector<PlannedConfiguration> read_configurations_csv(const std::string& path,
                                                          const Tool& tool);

/// A configurations file's row as written, before its names meet a tool: the configuration with
/// its target and payload unresolved (−1), their names (empty: none given) and cells.
struct ConfigurationRow {
  PlannedConfiguration config;
  std::string target, payload;
  SourceLocation target_at, payload_at;
  int line = 0;
};
/// The rows of the text of a configurations file named `file`, with read_configurations_csv's
/// checks but the names unchecked (their user checks them against its tool, or passes them on).
std::vector<ConfigurationRow> parse_configuration_rows(const std::string& text,
                                                       const std::string& file);

/// Writes configurations in the same format (round-trips through read_configurations_csv); the
/// approach and payload columns only when some configuration has one other than the default.
std::string write_configurations_csv(const std::vector<PlannedConfiguration>& configs,
                                     const Tool& tool);

/// One instrument of the cell, placed in the world (measurement) frame.
struct VirtualInstrument {
  InstrumentKind kind = InstrumentKind::LaserTracker;
  LaserTracker tracker;
  OpticalCmm cmm;
  Ballbar ballbar;
};

/// The instrument of `kind` in a standard cell around `truth`: tracker or CMM at the world
/// origin, ballbar centre at (300, 0, 250) mm in the robot's base frame with a 150 mm bar.
/// `noise_mm` > 0 replaces the instrument's σ (per axis; for the CMM the orientation σ scales
/// with it, as σ / 100 mm).
VirtualInstrument standard_instrument(InstrumentKind kind, const TrueRobot& truth,
                                      double noise_mm = 0);

/// A base-frame point (the robot's foot, z up) in the world frame of `truth`.
Eigen::Vector3d world_from_base(const TrueRobot& truth, const Eigen::Vector3d& p_base_mm);

struct SimulationOptions {
  /// true: every configuration approached as the measurement program does, from 5° away on each
  /// joint's planned side (PlannedConfiguration::approach: from below, q − 5°, unless the plan
  /// says otherwise, docs/method/05-observability.md §4); false: the robot moves straight from one
  /// configuration to the next.
  bool approach_from_below = true;
  double seconds_per_measurement = 20;  ///< clock for thermal drift
  /// With thermal drift, the rows record their time (`time_s`, the warm-up group's input,
  /// docs/method/03-error-model.md §10) instead of the arm's temperature (§8).
  bool record_time = false;
  /// Each joint of each configuration approached from below or above at random (from q ∓ 5°),
  /// drawn from `approach_seed` (overrides approach_from_below): data for the backlash group,
  /// docs/method/03-error-model.md §6. The rows record the side of every joint either way.
  bool approach_random = false;
  uint64_t approach_seed = 0;
  /// true: each configuration carries a payload drawn (seeded) from the true tool's payload and
  /// its `payloads`, recorded in the row (several payloads in one calibration, §7).
  bool random_payloads = false;
};

struct SimulationResult {
  MeasurementSet measurements;
  std::vector<std::string> skipped;  ///< one line per configuration not measured, with why
};

/// Measures `configs` in order on the true robot. A configuration whose target the instrument
/// cannot read (not facing the tracker, tool not seen by the CMM, ballbar out of range) is
/// skipped and listed.
SimulationResult simulate_measurements(const TrueRobot& truth, const VirtualInstrument& instrument,
                                       const std::vector<PlannedConfiguration>& configs,
                                       std::mt19937_64& rng, const SimulationOptions& options = {});

/// Joint ranges of the published tests (design/candidates.hpp: published_joint_constraints),
/// intersected with the robot's limits (controller values).
inline std::array<JointLimit, kJointCount> published_joint_box(const RobotModel& model) {
  return constrained_joint_box(model, published_joint_constraints());
}

struct RandomConfigurationOptions {
  std::array<JointLimit, kJointCount> box{};  ///< controller joint ranges, rad
  double min_target_height_mm = 50;           ///< above the robot's base plane
  std::string name_prefix = "R";
  int max_attempts = 2000;  ///< per configuration, before giving up with an InputError
  /// A further rule a draw must keep (e.g. a cell's keep-out boxes and line of sight), asked
  /// once the draw is measurable; empty: none.
  std::function<bool(const PlannedConfiguration&)> accept;
};

/// `count` random configurations the instrument can measure on the true robot, uniform in the
/// box, each with the target to read. For the ballbar, each draw is moved (Gauss-Newton on the
/// joints, nominal geometry at the truth's placement: what the operator's program does) so
/// that its target sits at the bar's nominal length from the centre.
std::vector<PlannedConfiguration> random_configurations(const TrueRobot& truth,
                                                        const VirtualInstrument& instrument,
                                                        int count, std::mt19937_64& rng,
                                                        const RandomConfigurationOptions& options);

}  // namespace robcal
