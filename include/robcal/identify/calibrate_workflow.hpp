#pragma once
/// \file
/// The workflow behind `robcal calibrate` and Python's `calibrate`
/// (docs/method/04-identification.md §2–§6): the files of a calibration read as the CLI names them,
/// run_calibration or reidentify with every check (warnings, noise test, cross-validation,
/// problems), and the model file written only when the fit is trustworthy or the user forces it.
/// The CLI and Python call only these, so neither can skip a guard.

#include <optional>
#include <string>

#include "robcal/identify/calibration_run.hpp"
#include "robcal/report/provenance.hpp"

namespace robcal {

/// The files and options of one calibration, as the CLI names them (errors name the flag).
struct CalibrateFilesRequest {
  std::string robot;         ///< built-in robot name or robot file (empty with `model`)
  std::string model;         ///< calibrated model file to re-identify a part of (`--model`)
  std::string tool;          ///< tool file; with `model` optional (its tool is used)
  std::string measurements;  ///< points, poses or distances CSV
  std::string units;  ///< "m, rad"… when the file does not declare them (`--units`); empty: none
  std::string euler;  ///< rx,ry,rz rotation order (`--euler`); empty: the file's or none
  std::string level;  ///< empty: full, or with `model` the `identify` patterns only
  std::string loss = "none";  ///< none or huber
  std::string folds;          ///< folds CSV (config,fold); empty: seeded folds
  /// identify/fix patterns, Huber scale, orientation weight, seed, instrument σ, near-dependence
  /// resolution (level is set from `level`) and the K of K-fold cross-validation.
  CalibrationRequest request;
};

/// `options` with `loss` (none or huber) applied, after the checks of what a user can give
/// (InputError naming the flag): a finite instrument σ >= 0, a valid orientation weight.
IdentifyOptions checked_options(IdentifyOptions options, const std::string& loss);

/// Reads the files, checks the options (checked_options; an unknown level, robot and model
/// both or neither given: InputError naming the flag) and calibrates
/// (run_calibration, or reidentify with `model`). The run's warnings start with the measurement
/// file's.
CalibrationRun calibrate_files(const CalibrateFilesRequest& request);

/// Writes the calibrated model file (calibrated_model_file, whole or not at all) unless the run
/// lists problems and `force` is false. Returns why it was not written ("model.yaml not
/// written: …, or write it anyway with --force"), or nothing when written.
std::optional<std::string> write_calibration(const CalibrationRun& run, const std::string& path,
                                             bool force, const Provenance* provenance);

}  // namespace robcal
