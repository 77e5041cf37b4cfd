#pragma once
/// \file
/// The Monte Carlo study behind `robcal montecarlo` (docs/method/04-identification.md §5): repeated
/// simulated calibrations of the published IRB 120 with a laser tracker, their accuracy spread
/// against the Cramér–Rao prediction. Its JSON is written here.

#include <nlohmann/json_fwd.hpp>

#include "robcal/sim/monte_carlo.hpp"

namespace robcal {

struct MonteCarloStudyRequest {
  MonteCarloOptions options;
  double noise_mm = 0.022;  ///< tracker σ per axis
};

struct MonteCarloStudy {
  MonteCarloStudyRequest request;
  int poses = 0;       ///< calibration rows
  int identified = 0;  ///< identified parameters
  PredictedAccuracy predicted;
  MonteCarloResult result;
  /// Spread of the converged runs: 5th and 95th percentiles of the per-run mean, 95th of the
  /// per-run maximum (linear interpolation between order statistics).
  double run_mean_p05_mm = 0, run_mean_p95_mm = 0, run_max_p95_mm = 0;
};

/// Runs the study. Throws InputError (key "--noise-mm") unless the noise is positive.
MonteCarloStudy run_monte_carlo_study(const MonteCarloStudyRequest& request);

/// The request from the names `robcal montecarlo` and Python take: level (base, joints,
/// kinematic, full), plan (optimal: D-optimal of 5000 candidates, or random) and validation model
/// (first-order or exact). \throws InputError naming --level, --plan or --validation-model.
MonteCarloStudyRequest monte_carlo_study_request(MonteCarloOptions options, double noise_mm,
                                                 const std::string& level, const std::string& plan,
                                                 const std::string& validation_model);

/// The p-quantile (0..1) of `values` by linear interpolation between order statistics; 0 when
/// empty.
double percentile(std::vector<double> values, double p);

/// {seed, runs, failed, poses, validation, validation_model, identified_parameters, noise_mm,
/// threads, observed, predicted, ratio}.
nlohmann::json monte_carlo_study_json(const MonteCarloStudy& study);

}  // namespace robcal
