#pragma once
/// \file
/// The `calibrate` workflow: identification, the checks that keep a misleading model from being
/// written (a solver that did not converge, residuals no robot of this kind leaves, parameters
/// no real arm has) and the cross-validated prediction, asked for (`--kfold`) or run because the
/// residuals exceed what the instrument's stated σ explains (model misfit: the covariance would
/// present it as noise).

#include <optional>
#include <string>
#include <vector>

#include "robcal/identify/cross_validation.hpp"
#include "robcal/identify/identification.hpp"

namespace robcal {

struct CalibrationRequest {
  IdentifyOptions options;
  int kfold = 0;  ///< K-fold cross-validation (0: only when the noise test fails)
  /// The user's folds (config → fold 1..K, read_folds_csv); when given, used instead of seeded
  /// ones, and `kfold`, if set, must equal their K.
  std::map<std::string, int> folds;
};

/// Folds used when the noise test fails and no --kfold was given.
inline constexpr int kMisfitFolds = 5;

/// Residual RMS (mm, per-row position error) past which a fit is implausible whatever the
/// instrument: calibrated industrial arms leave 0.02–0.5 mm; 2 mm means another robot's model,
/// wrong units, or wrong tool targets.
inline constexpr double kImplausibleResidualMm = 2.0;
/// A-posteriori σ past this multiple of the stated instrument σ is implausible too.
inline constexpr double kImplausibleNoiseRatio = 20.0;

struct CalibrationRun {
  IdentifyOptions options;  ///< as run (the seed, orientation weight… the summaries report)
  MeasurementKind kind = MeasurementKind::Points;
  size_t rows = 0;   ///< measurement rows
  std::string file;  ///< the measurements' file (MeasurementSet::file)
  IdentificationResult result;
  std::optional<CrossValidation> cross_validation;
  bool cross_validation_for_misfit = false;  ///< run because the noise test failed
  /// Why the model must not be trusted (each says what to check); empty when plausible.
  std::vector<std::string> problems;
  /// For the user: the measurement file's (calibrate_files), then the fit's (result.warnings).
  std::vector<std::string> warnings;
};

/// Compliance magnitude (rad/N·mm) no joint has: 1e-4 turns a joint by 1 rad under 10 N·m,
/// a hundred times the softest arms (published IRB 120: ≤ 7e-7; harmonic-drive joints 1e-8 to
/// 1e-6). Values past it are rounding noise of an unloaded joint (−2e7, −6e5) and make the
/// compensation's inverse singular.
inline constexpr double kImplausibleComplianceRadPerNmm = 1e-4;

/// Identified parameters no real arm has: MDH lengths more than 20 mm or link angles more than
/// 5° from nominal, a joint scale more than 1 % from 1, a compliance beyond
/// kImplausibleComplianceRadPerNmm in magnitude or below zero by more than 3σ.
std::vector<std::string> implausible_parameters(const IdentificationResult& result);

/// Calibrates, tests the residuals against the stated instrument σ, cross-validates when asked
/// or when the test fails (kMisfitFolds folds, the options' seed; skipped with a note in
/// fewer than 2·kMisfitFolds configurations skip it), and lists the problems.
CalibrationRun run_calibration(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const CalibrationRequest& request);

/// Measured configurations a new tool point (per target) or TCP frame needs at level tool:
/// the 3 (6) unknowns and enough redundancy that their σ means something (≥ 9 degrees of
/// freedom for a point; the 4-point TCP method of robot controllers).
inline constexpr int kMinToolConfigurations = 4;

/// `calibrate --model`: starts from a calibrated robot and identifies only what
/// `request.options` asks — level Tool (every target of `tool`, or its TCP frame from poses),
/// Base (a moved robot base), Patterns (the `identify` patterns), or a calibration level —
/// with everything else held at the calibrated values. `tool`: the new tool at level tool;
/// at the other levels the model's own tool is used and a `tool` given must be it
/// (check_tool_against_model, errors naming "--tool"). The result's robot is the calibrated one
/// with the re-identified values, their covariance rows (conditional on the rest, held) and a
/// Reidentification record; statuses, reasons, statistics and provenance of the rest are kept.
/// InputError when the request cannot be met: level tool without a tool or without enough
/// measured configurations (naming the target and its count), Patterns without a pattern, or
/// what run_calibration refuses.
CalibrationRun reidentify(const CalibratedRobot& start, const std::optional<Tool>& tool,
                          const MeasurementSet& data, const CalibrationRequest& request);

}  // namespace robcal
