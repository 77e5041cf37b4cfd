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
  IdentificationResult result;
  std::optional<CrossValidation> cross_validation;
  bool cross_validation_for_misfit = false;  ///< run because the noise test failed
  /// Why the model must not be trusted (each says what to check); empty when plausible.
  std::vector<std::string> problems;
};

/// Identified parameters no real arm has: MDH lengths more than 20 mm or link angles more than
/// 5° from nominal, a joint scale more than 1 % from 1, a compliance below zero by more than 3σ.
std::vector<std::string> implausible_parameters(const IdentificationResult& result);

/// Calibrates, tests the residuals against the stated instrument σ, cross-validates when asked
/// or when the test fails (kMisfitFolds folds, the options' seed; skipped with a note in
/// fewer than 2·kMisfitFolds configurations skip it), and lists the problems.
CalibrationRun run_calibration(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const CalibrationRequest& request);

}  // namespace robcal
