#pragma once
/// \file
/// The published simulation experiments (docs/method/11-published-results.md §2), reproduced: (a)
/// random errors scaled to a 5 mm nominal peak, no noise; (b) the same with 0.070 mm noise and 10 %
/// mass error; (c) the published IRB 120 with the tracker's noise, kinematic (25) against full (30)
/// parameters. The workflow behind `robcal experiments`; its JSON and markdown table are written
/// here too.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace robcal {

/// Position errors of one model over the validation configurations, mm.
struct ErrorFigures {
  double mean_mm = 0, std_mm = 0, max_mm = 0;
};

struct NoNoiseExperiment {  ///< (a)
  ErrorFigures nominal_vs_truth, full_vs_truth;
  int identified = 0;
  double truth_error_factor = 0;  ///< scale of the drawn errors that makes the 5 mm peak
  int calibration_rows = 0;
};

struct NoisyExperiment {  ///< (b)
  ErrorFigures nominal_vs_truth, full_vs_truth, full_vs_measurements;
};

struct ModelLevelExperiment {  ///< (c)
  ErrorFigures nominal_vs_measurements, kinematic_vs_measurements, full_vs_measurements;
  ErrorFigures kinematic_vs_truth, full_vs_truth;
  int identified_kinematic = 0, identified_full = 0;
};

struct PublishedExperiments {
  uint64_t seed = 1;
  int calibration_configurations = 0, validation_configurations = 0;
  NoNoiseExperiment a;
  NoisyExperiment b;
  ModelLevelExperiment c;
};

/// Runs the three experiments; every random draw comes from `seed`. `progress`, when given, is
/// told which experiment starts ("(a) no noise…").
PublishedExperiments run_published_experiments(
    uint64_t seed, const std::function<void(const std::string&)>& progress = {});

/// {seed, calibration_configurations, validation_configurations, experiments: {a, b, c:
/// {description, published, result}}}.
nlohmann::json published_experiments_json(const PublishedExperiments& experiments);
/// The markdown table beside the published figures.
std::string published_experiments_markdown(const PublishedExperiments& experiments);

/// The experiments as `robcal experiments` runs them: timed, written to `out`/results.json
/// (published_experiments_run_json) and `out`/results.md (the markdown table).
struct PublishedExperimentsRun {
  PublishedExperiments experiments;
  double seconds = 0;  ///< wall-clock time of the three experiments
};
PublishedExperimentsRun run_published_experiments_files(
    uint64_t seed, const std::filesystem::path& out,
    const std::function<void(const std::string&)>& progress = {});
/// published_experiments_json with the run's seconds.
nlohmann::json published_experiments_run_json(const PublishedExperimentsRun& run);

}  // namespace robcal
