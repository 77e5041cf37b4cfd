#pragma once
/// \file
/// The calibrated robot as it is used now (docs/method/10-compensation.md §1): the calibrated
/// model, the tool mounted on it and the payload it carries, checked and turned into the
/// compensator every compensation workflow (targets, programs) starts from.

#include <array>
#include <map>
#include <optional>
#include <string>
#include <tuple>

#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal {

struct CompensationSetup {
  CalibratedRobot robot;
  std::string model_file = "<model>";  ///< names the model in errors
  /// When given, the model must be a calibrated robot of this name (`--robot`).
  std::string expected_robot;
  /// When given, its TCP and payload replace the model's (`--tool`).
  std::optional<Tool> tool;
  /// The payload carried now, when not the tool's: the compliance re-compensates for it.
  std::optional<PointMass> payload;
  /// The payload carried now by name, one of the tool's `payloads` (`--payload NAME`, several
  /// payloads, docs/method/03-error-model.md §7); empty: none named.
  std::string payload_name;
  /// Yaskawa: encoder pulses per degree of each joint (io/robot_pulses.hpp); all zero: unknown.
  std::array<double, kJointCount> pulses_per_degree{};
  /// The side each joint reaches the targets from (+1 below, −1 above, 0 unknown): the backlash
  /// group's sign (docs/method/03-error-model.md §6); the programs approach from below.
  Vector6d approach = Vector6d::Ones();
  /// The arm's temperature (°C) when it reaches the targets, for the thermal group
  /// (docs/method/03-error-model.md §8, `--temperature-c`); none: the robot's reference.
  std::optional<double> temperature_c;
  /// How long the arm has worked when it reaches the targets (s), for the warm-up group
  /// (docs/method/03-error-model.md §10, `--warmup-time-s`); `warm` (`--warm`): fully warm;
  /// neither: cold.
  std::optional<double> warmup_time_s;
  bool warm = false;
};

/// The calibrated robot with the tool and payload applied, and its compensator for the run's
/// reach condition (approach, temperature and payload of the setup). The compensator and the
/// program correctors made from it refer to `robot`: keep the object where it was made.
struct Compensation {
  CalibratedRobot robot;
  Compensator comp;
  std::array<double, kJointCount> pulses_per_degree{};  ///< the setup's
};

/// The compensators of a run for targets reached under conditions of their own
/// (docs/method/10-compensation.md §6): each distinct condition's made once, on first use (a
/// closed-form analysis and a chain, not to be repeated per target); the run's own is
/// `run.comp`. `run` must outlive the object, and the references it hands out live as
/// long as it does.
class CompensatorsByCondition {
 public:
  explicit CompensatorsByCondition(const Compensation& run);
  const Compensator& at(const ReachCondition& condition);
  /// Compensators made beyond the run's.
  [[nodiscard]] size_t made() const { return made_.size(); }

 private:
  /// A condition's exact values, ordered: one lookup in log time, as many rows as a target file
  /// has (a temperature column can make every row a condition of its own).
  using Key = std::tuple<std::array<double, 6>, double, double, double, double,
                         std::array<double, 3>, std::string>;
  static Key key_of(const ReachCondition& condition);

  const Compensation& run_;
  std::map<Key, Compensator> made_;  // map nodes keep the references handed out valid
};

/// Applies the tool and payload and builds the compensator. InputError: the model is not the
/// expected robot (key "--robot"), the payload mass is outside [0, 10000) kg or not finite
/// (key "--payload-mass-kg"), its centre of gravity not finite (key "--payload-cog-mm"), a
/// payload name the tool does not list or given with a mass (key "--payload"), a temperature
/// outside [−50, 150] °C (key "--temperature-c"), a negative or not finite warm-up time or one
/// given with `warm` (key "--warmup-time-s").
Compensation prepare_compensation(const CompensationSetup& setup);

/// "newton" or "pose-shift"; InputError (key `key`) otherwise.
IkMethod ik_method_from_name(const std::string& name, const std::string& key = "--method");

/// The name ik_method_from_name reads.
const char* ik_method_name(IkMethod method);

}  // namespace robcal
