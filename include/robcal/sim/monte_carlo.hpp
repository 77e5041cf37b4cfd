#pragma once
/// \file
/// Monte Carlo of the calibration's accuracy against its Cramér–Rao prediction (METHOD §5):
/// the same calibration configurations are measured again and again with new noise, each set
/// is calibrated with identify's fast path, and each calibrated model is compared with the
/// truth at the validation configurations. An efficient estimator's RMS error equals the
/// prediction √(mean_v tr(J_v C J_vᵀ)), C = σ²(JᵀJ)⁻¹: the ratio is 1.00 up to sampling error.
///
/// Validation error of run r at configuration v: e_v = p_model(q_v; x̂_r) − p_true(q_v), evaluated
/// to first order about the truth, J_v·(x̂_r − x_true), with J_v the exact (autodiff) position
/// Jacobian at the truth. The second-order remainder is of order |x̂ − x_true|² (about 1e-8 mm
/// for 0.02 mm noise); the tests check the expansion against the exact forward kinematics.
///
/// Runs are independent: run r draws its noise from a generator seeded with (seed, r), so the
/// results are identical whatever the number of threads.

#include <cstdint>
#include <string>
#include <vector>

#include "robcal/identify/identification.hpp"
#include "robcal/sim/simulator.hpp"

namespace robcal {

struct MonteCarloOptions {
  int runs = 1000;
  int poses = 50;         ///< calibration configurations (one target each)
  int validation = 1000;  ///< validation configurations
  int threads = 2;
  uint64_t seed = 1;
  CalibrationLevel level = CalibrationLevel::Full;
  bool optimal_plan = true;  ///< D-optimal among `candidates`; false: random measurable ones
  int candidates = 5000;
};

/// Everything that does not change from run to run, built once.
struct MonteCarloSetup {
  TrueRobot truth;
  VirtualInstrument instrument;
  std::vector<PlannedConfiguration> plan;
  MeasurementSet template_set;                  ///< calibration rows (values: true positions)
  std::vector<Eigen::Vector3d> true_positions;  ///< of the calibration rows
  IdentificationSetup identification;
  Eigen::MatrixXd validation_jacobian;  ///< 3·validation × kParameterCount, at the truth
  double sigma_mm = 0;                  ///< noise per axis of the instrument
  PredictedAccuracy predicted;          ///< Cramér–Rao over the validation configurations
};

/// Plans and prepares. The instrument must be a laser tracker (points) with equal σ per axis.
MonteCarloSetup prepare_monte_carlo(const TrueRobot& truth, const VirtualInstrument& instrument,
                                    const RobotModel& model, const Tool& tool,
                                    const MonteCarloOptions& options);

struct MonteCarloRun {
  double rms_mm = 0;  ///< RMS over validation configurations of |e_v|
  double mean_mm = 0;
  double max_mm = 0;
  bool converged = false;
};

struct MonteCarloResult {
  std::vector<MonteCarloRun> runs;
  double observed_rms_mm = 0;   ///< √(mean over runs and configurations of |e_v|²)
  double observed_mean_mm = 0;  ///< mean over runs and configurations of |e_v|
  double ratio = 0;             ///< observed_rms / predicted rms
  int failed = 0;               ///< runs whose solver did not converge
};

/// Runs `options.runs` calibrations on `options.threads` threads.
MonteCarloResult run_monte_carlo(const MonteCarloSetup& setup, const MonteCarloOptions& options);

/// One run's calibrated parameters (for tests: the exact-FK check of the expansion).
ParameterVector monte_carlo_fit(const MonteCarloSetup& setup, uint64_t seed, int run);

}  // namespace robcal
