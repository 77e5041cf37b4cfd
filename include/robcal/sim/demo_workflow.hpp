#pragma once
/// \file
/// The workflow behind `robcal demo` and Python's `demo`: the whole method on a virtual ABB
/// IRB 120 (the published identified robot as the truth) measured by a simulated laser tracker —
/// plan, measure, calibrate at each level, validate on other configurations — and the files a
/// real campaign would leave; with its one JSON serializer.

#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "robcal/sim/campaign.hpp"

namespace robcal {

struct DemoRequest {
  std::string out;  ///< folder to write (calibration/, validation/, plan.csv, models/, report.*);
                    ///< empty: none
  uint64_t seed = 1;
  int count = 50;         ///< calibration configurations
  int validation = 1000;  ///< validation configurations
};

struct DemoResult {
  DemoRequest request;
  int candidates = 0;  ///< feasible candidates the plan chose from
  CampaignResult campaign;
};

/// Runs the campaign and writes the folder when asked (each file whole or not at all).
/// Throws InputError before any work when the report's Chart.js is missing and files are asked.
DemoResult run_demo(const DemoRequest& request);

/// {seed, calibration_rows, validation_rows, vs_measurements: {nominal, base, kinematic, full},
/// vs_truth: {…}, identified: {level: count}, out}; each summary as the report's
/// (count, mean_mm, std_mm, mean_plus_3std_mm, max_mm, …).
nlohmann::json demo_json(const DemoResult& result);

}  // namespace robcal
