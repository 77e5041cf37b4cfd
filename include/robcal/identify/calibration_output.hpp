#pragma once
/// \file
/// What `calibrate` writes and prints, one serializer per result: the calibrated model file of
/// a CalibrationRun (the robot, the fit's statistics with the cross-validation, the problems
/// found and where it came from) and its JSON summary. The CLI and Python both use them.

#include <nlohmann/json.hpp>
#include <string>

#include "robcal/identify/calibrated_robot_file.hpp"
#include "robcal/identify/calibration_run.hpp"
#include "robcal/report/provenance.hpp"

namespace robcal {

/// Writes the fit statistics' entries into the map `out` has open (kStatisticsDigits), so that
/// a caller can add its own entries to the same map.
void emit_statistics_entries(YAML::Emitter& out, const IdentificationResult& result);

/// The fit statistics as a map (calibrated_robot_to_yaml's `statistics`); `result` must
/// outlive the writer.
YamlWriter statistics_writer(const IdentificationResult& result);

/// The model file. A fresh calibration writes its statistics (+ cross-validation, problems and
/// `provenance` when given) under `statistics`; a re-identification (reidentify()) keeps the
/// calibrated model's statistics and adds a `reidentified` record: what was asked, each value
/// before and after with its σ, and this fit's statistics.
std::string calibrated_model_file(const CalibrationRun& run, const Provenance* provenance);

/// The same for a bare identification (no cross-validation, no problems listed).
std::string calibrated_model_file(const IdentificationResult& result, const Provenance* provenance);

/// The files a calibration read; an empty path was not given.
struct CalibrationInputs {
  std::string model;         ///< the calibrated model it started from (calibrate --model)
  std::string tool;          ///< the tool file
  std::string measurements;  ///< the measurement file
};

/// Where a calibrated model came from, as `calibrate` records it under statistics.provenance:
/// this process's command line, the robot, the level and seed of `run`, and every input file
/// with its SHA-256 (InputError naming a file that cannot be read).
Provenance calibration_provenance(const CalibrationRun& run, const CalibrationInputs& inputs);

/// The summary `calibrate --json` prints; `written_to`: the model file written, empty when
/// it was not (the problems say why).
nlohmann::json calibration_run_json(const CalibrationRun& run, const std::string& written_to);

}  // namespace robcal
