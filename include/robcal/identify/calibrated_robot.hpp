#pragma once
/// \file
/// A robot with identified parameters: what `calibrate` writes and every later command reads
/// (`--model FILE`), and what the simulator's truth file holds (without covariance).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "robcal/model/parameters.hpp"
#include "robcal/model/robot_model.hpp"
#include "robcal/model/tool.hpp"

namespace robcal {

/// Why a parameter was not identified.
enum class ParameterStatus { Identified, Fixed, Dropped };

/// "identified", "fixed" or "dropped", as written in model files and reports.
const char* status_name(ParameterStatus status);

/// One value of a re-identification (calibrate --model), external units (mm, deg).
struct ReidentifiedValue {
  std::string name, unit;
  double before = 0;  ///< the calibrated value it started from (targets: the tool file's, or 0)
  double value = 0;
  double std_dev = 0;
};

/// What a re-identification changed in a calibrated model, and the fit's statistics.
struct Reidentification {
  std::string what;  ///< "tool", "base", or the --identify patterns
  std::vector<ReidentifiedValue> values;
};

struct CalibratedRobot {
  RobotModel model;
  ParameterVector params = ParameterVector::Zero();  ///< values in use (internal units)
  std::array<ParameterStatus, kParameterCount> status{};
  std::array<std::string, kParameterCount>
      reason{};  ///< for Dropped: which parameters it depends on
  /// Covariance of all parameters (internal units), zero rows/columns for the non-identified;
  /// empty when unknown (a truth file, a nominal robot).
  Eigen::MatrixXd covariance;
  Tool tool;                 ///< the tool, with identified target coordinates filled in
  bool base_fitted = false;  ///< false: no world frame (nominal robot at the origin)
  std::string level;         ///< "nominal", "base", "joints", "kinematic", "full"
  /// The `statistics` map of the file it was read from (YAML text, provenance included): kept
  /// verbatim, not interpreted, when only a part of the model is re-identified.
  std::string statistics;
  /// The file's `reidentified` records (YAML maps, oldest first), kept verbatim likewise.
  std::vector<std::string> reidentified;

  /// The nominal robot at the world origin (no world frame).
  static CalibratedRobot nominal(const RobotModel& model, const Tool& tool);
};

/// Significance of an opt-in parameter group (docs/method/03-error-model.md §5): the Wald
/// statistic W = dᵀ·C⁻¹·d of the group's identified parameters d (deviations from nominal, C
/// their covariance) against χ² with as many degrees of freedom. A group whose effect the data
/// do not show gives W ≈ dof; `significant` when P(χ²_dof ≥ W) < kGroupSignificanceLevel.
struct GroupSignificance {
  std::string group;     ///< e.g. "joint6.periodic"
  bool enabled = false;  ///< some parameter of the group identified, or non-zero
  int identified = 0;    ///< parameters of the group identified (the test's degrees of freedom)
  double wald = 0;
  double p_value = 1;
  bool significant = false;
};

/// Level of the group test: as strict as the noise test (kNoiseTestLevel), so that a group the
/// data do not need is almost never called significant.
inline constexpr double kGroupSignificanceLevel = 1e-3;

/// Every opt-in group of `robot` (model/parameters.hpp: opt_in_groups), enabled or not.
std::vector<GroupSignificance> group_significance(const CalibratedRobot& robot);

/// Writes the calibrated model as YAML (robot fields + a parameter table with nominal,
/// identified value, standard deviation, unit, status and reason, + the robot's own fit
/// `statistics`) and its `reidentified` records.
std::string calibrated_robot_to_yaml(const CalibratedRobot& robot);

/// A tool file given beside a calibrated model (`validate --tool`) is used or refused, never
/// silently ignored: its targets must be the model's, within 5 mm (the model's refined ones are
/// used), and its payload the model's; InputError naming `tool_path` otherwise (another tool).
/// (`validate` notes each target whose refined coordinates replace the tool file's.)
void check_tool_against_model(const CalibratedRobot& robot, const Tool& tool,
                              const std::string& tool_path);

/// Loads a calibrated model file (errors name the file, line and key).
CalibratedRobot load_calibrated_robot(const std::string& path);

}  // namespace robcal
