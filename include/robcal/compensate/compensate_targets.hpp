#pragma once
/// \file
/// The `robcal compensate` workflow (docs/method/10-compensation.md §1–§5): wanted world poses in,
/// corrected targets for the controller out (corrected_targets.hpp), with the summary the user
/// checks (worst residual on the model, iterations, confidence radius) and, in simulation, the
/// closed-loop check on the true robot (closed_loop.hpp). Its JSON is written here.

#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robcal/compensate/closed_loop.hpp"
#include "robcal/compensate/compensation_setup.hpp"
#include "robcal/compensate/corrected_targets.hpp"

namespace robcal {

struct CompensateTargetsRequest {
  CompensationSetup setup;
  std::vector<WantedTarget> targets;
  std::string targets_file = "<targets>";  ///< names the targets in errors
  IkMethod method = IkMethod::Newton;
  /// A simulation's true robot: command the corrected joints on it (closed-loop check).
  std::optional<TrueRobot> truth;
  /// When given, the corrected-targets CSV is written there (whole or not at all).
  std::string out;
};

struct CompensateTargetsResult {
  std::string robot;  ///< the model's robot name
  IkMethod method = IkMethod::Newton;
  double payload_kg = 0;  ///< the run's
  /// Distinct conditions the targets are reached under (approach, temperature, warm-up time,
  /// payload; 1: all alike), one compensator each.
  int conditions = 1;
  std::vector<CorrectedTarget> rows;  ///< each with the condition it was corrected for
  std::string csv;                    ///< corrected_targets_csv of the rows
  std::string out;                    ///< where it was written ("" = not written)
  int max_iterations = 0;
  double max_residual_mm = 0;                 ///< on the calibrated model
  std::optional<double> max_confidence95_mm;  ///< none when the model has no covariance
  std::optional<ClosedLoopReport> closed_loop;
};

/// Corrects every target under its own condition (docs/method/10-compensation.md §6): the
/// approach, temperature, warm-up time and payload its row gives, the setup's otherwise. The CSV
/// records each row's condition when some target gives one. InputError (file and line of the
/// target) when one cannot be corrected, or (file, line, column, key "payload") names a payload the
/// tool does not list: nothing is written then.
CompensateTargetsResult compensate_targets(const CompensateTargetsRequest& request);

/// {robot, targets, out, method, payload_kg, conditions, max_iterations, max_residual_mm,
/// max_confidence95_mm, closed_loop: {compensated, uncompensated}} (the last only with a truth).
void to_json(nlohmann::json& j, const CompensateTargetsResult& result);

}  // namespace robcal
