#pragma once
/// \file
/// A whole simulated calibration campaign (docs/method/01-overview.md §2): plan the calibration
/// configurations, measure them on the true robot, calibrate at each level, and validate every
/// model on other configurations, both against new (noisy) measurements, as the published tables
/// do, and against the truth itself. Shared by `robcal demo` and `robcal experiments`.

#include <cstdint>
#include <vector>

#include "robcal/identify/identification.hpp"
#include "robcal/report/report.hpp"
#include "robcal/sim/calibration_plan.hpp"
#include "robcal/sim/simulator.hpp"

namespace robcal {

/// `count` calibration configurations chosen D-optimally (sim/calibration_plan.hpp) among
/// `candidates` feasible ones (published joint box, above the floor, visible to the
/// instrument with the planning margins), for the parameters of `level`, planned on the
/// nominal robot placed like the truth (where the instrument stands relative to the robot is
/// known roughly, its errors are not). Names "C1", "C2", …
std::vector<PlannedConfiguration> plan_calibration(const TrueRobot& truth,
                                                   const VirtualInstrument& instrument,
                                                   const RobotModel& model, const Tool& tool,
                                                   CalibrationLevel level, int count,
                                                   int candidates, std::mt19937_64& rng);

struct CampaignOptions {
  int calibration_count = 50;
  bool optimal_plan = true;  ///< false: random measurable configurations
  int candidates = 5000;
  int validation_count = 1000;
  std::vector<CalibrationLevel> levels{CalibrationLevel::Base, CalibrationLevel::Kinematic,
                                       CalibrationLevel::Full};
  uint64_t seed = 1;
  SimulationOptions simulation;
};

struct LevelOutcome {
  CalibrationLevel level = CalibrationLevel::Full;
  IdentificationResult fit;
  ModelErrors vs_measurements;  ///< against the noisy validation readings
  ModelErrors vs_truth;         ///< against the true positions (noise-free readings)
};

struct CampaignResult {
  std::vector<PlannedConfiguration> plan;
  SimulationResult calibration;
  std::vector<PlannedConfiguration> validation_configs;
  SimulationResult validation;        ///< noisy readings
  SimulationResult validation_truth;  ///< the same rows without noise
  /// The nominal robot rigidly fitted to the calibration readings (the published tables'
  /// "before": the base found from the calibration data, scored on the validation data).
  CalibratedRobot nominal;
  ModelErrors nominal_vs_measurements, nominal_vs_truth;
  std::vector<LevelOutcome> levels;
};

/// Runs the campaign. Seeds: plan `seed`, calibration noise `seed + 1`, validation
/// configurations `seed + 2`, validation noise `seed + 3`.
CampaignResult run_campaign(const TrueRobot& truth, const VirtualInstrument& instrument,
                            const RobotModel& model, const Tool& tool,
                            const CampaignOptions& options);

}  // namespace robcal
