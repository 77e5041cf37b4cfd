#pragma once
/// \file
/// The workflow behind `robcal simulate` and Python's `simulate`: measurements of a virtual
/// robot (the published IRB 120 truth, a random one or a truth file, with optional unmodelled
/// effects) by a virtual instrument placed by a cell file (or the simulator's standard cell),
/// optionally written as the files a real campaign gives; with its one JSON serializer.

#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robcal/sim/simulation_files.hpp"
#include "robcal/sim/simulator.hpp"

namespace robcal {

struct SimulateRequest {
  std::string robot = "abb-irb120";
  std::string truth = "published";  ///< published, random, or a truth file
  std::string instrument;  ///< laser-tracker, optical-cmm, ballbar; "": the cell's, else tracker
  std::string cell;        ///< cell file; "": the simulator's standard cell
  std::string tool;        ///< tool file; "": the simulator's default tool
  std::string configs;     ///< configurations file, or…
  int random = 0;          ///< …this many random measurable configurations
  uint64_t seed = 1;       ///< truth seed; configurations seed + 1, noise seed + 2
  double noise_mm = 0;     ///< σ per axis; 0: the instrument's own
  bool exact = false;      ///< noise-free readings
  std::vector<std::string> effects;  ///< unmodelled effects of the true robot (enable_effects)
  /// below (as the program: q − 5°, or the configurations file's planned sides), sequence or
  /// random
  std::string approach = "below";
  /// With thermal drift, the rows record their time (`time_s`) instead of the arm's temperature:
  /// data for the warm-up group (docs/method/03-error-model.md §10).
  bool clock = false;
  double error_length_mm = ErrorBounds{}.length_mm;  ///< random truth's error bounds
  double error_angle_deg = ErrorBounds{}.angle_deg;
  std::string out;  ///< folder to write (measurements.csv, tool, instrument, truth/); "": none
};

struct SimulateResult {
  SimulateRequest request;
  std::string instrument;  ///< the instrument's name
  std::string truth;       ///< where the truth came from
  Tool tool;               ///< the tool the pipeline is given
  size_t configurations = 0;
  SimulationResult simulation;
  std::optional<SimulationFiles> files;  ///< when written
};

/// Runs the simulation. With a cell, random configurations also keep its rules (floor,
/// keep-out boxes, line of sight, occlusion by the links). Throws InputError naming the flag.
SimulateResult run_simulation(const SimulateRequest& request);

/// {seed, instrument, cell?, truth, configurations, measured, skipped, files?}.
nlohmann::json simulation_json(const SimulateResult& result);

}  // namespace robcal
