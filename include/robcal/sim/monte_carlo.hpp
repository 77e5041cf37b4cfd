#pragma once
/// \file
/// Monte Carlo of the calibration's accuracy against its Cramér–Rao prediction
/// (docs/method/04-identification.md §5): the same calibration configurations are measured again
/// and again with new noise, each set is calibrated with identify's fast path, and each calibrated
/// model is compared with the truth at the validation configurations. An efficient estimator's RMS
/// error equals the prediction √(mean_v tr(J_v C J_vᵀ)), C = σ²(JᵀJ)⁻¹: the ratio is 1.00 up to
/// sampling error.
///
/// Validation error of run r at configuration v: e_v = p_model(q_v; x̂_r) − p_true(q_v), either
/// - first order (the default): J_v·(x̂_r − x_true) + b_v, with J_v the exact analytic position
///   Jacobian at the truth and b_v the model-error bias (zero for a model-complete truth): one
///   matrix–vector product per run. The remainder is of order |x̂ − x_true|² (a few 1e-6 mm
///   against errors of 0.01 mm for 0.02 mm noise); the tests compare it run by run with the
///   exact mode;
/// - exact: the calibrated model's forward kinematics at every validation configuration (the
///   configurations prepared once at the truth, so no trigonometric call per run) against the
///   true positions computed once.
///
/// Runs are independent: run r draws its noise from a generator seeded with (seed, r), so the
/// results are identical whatever the number of threads.

#include <cstdint>
#include <string>
#include <vector>

#include "robcal/identify/identification.hpp"
#include "robcal/kinematics/parameter_jacobian.hpp"
#include "robcal/sim/simulator.hpp"

namespace robcal {

/// How each run's calibrated model is compared with the truth (see the file comment).
enum class ValidationModel { FirstOrder, Exact };

/// "first-order" / "exact" and back (InputError with key "--validation-model").
const char* validation_model_name(ValidationModel model);
ValidationModel parse_validation_model(const std::string& text);

struct MonteCarloOptions {
  int runs = 1000;
  int poses = 50;         ///< calibration configurations (one target each)
  int validation = 1000;  ///< validation configurations
  int threads = 2;
  uint64_t seed = 1;
  CalibrationLevel level = CalibrationLevel::Full;
  bool optimal_plan = true;  ///< D-optimal among `candidates`; false: random measurable ones
  int candidates = 5000;
  ValidationModel validation_model = ValidationModel::FirstOrder;
};

/// Everything that does not change from run to run, built once.
struct MonteCarloSetup {
  TrueRobot truth;
  VirtualInstrument instrument;
  std::vector<PlannedConfiguration> plan;
  MeasurementSet template_set;                  ///< calibration rows (values: true positions)
  std::vector<Eigen::Vector3d> true_positions;  ///< of the calibration rows
  IdentificationSetup identification;
  /// 3·validation × (kParameterCount + 1): the position Jacobian at the truth and, in the last
  /// column, the model-error bias b_v.
  Eigen::MatrixXd validation_jacobian;
  /// Exact validation: configurations prepared at the truth, targets (flange frame), true
  /// positions (world).
  std::vector<PreparedConfiguration> validation_configurations;
  std::vector<Eigen::Vector3d> validation_targets, validation_true_positions;
  double sigma_mm = 0;          ///< noise per axis of the instrument
  PredictedAccuracy predicted;  ///< Cramér–Rao over the validation configurations
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

/// Validation of one run's calibrated parameters (the whole run's figures).
MonteCarloRun validate_monte_carlo_run(const MonteCarloSetup& setup, const ParameterVector& fitted,
                                       ValidationModel model);

/// Runs `options.runs` calibrations on `options.threads` threads.
MonteCarloResult run_monte_carlo(const MonteCarloSetup& setup, const MonteCarloOptions& options);

/// One run's calibrated parameters (for tests: the exact-FK check of the expansion).
ParameterVector monte_carlo_fit(const MonteCarloSetup& setup, uint64_t seed, int run);

}  // namespace robcal
