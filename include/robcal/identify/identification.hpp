#pragma once
/// \file
/// Identification (docs/method/04-identification.md §2): fit the robot's parameters to data.
///
/// 1. Unknowns: the level's parameters refined by `--identify`/`--fix` patterns, plus target
///    coordinates given without values and the ballbar centre (unknowns.hpp).
/// 2. Start: the nominal robot placed in the world by a rigid best fit (initial_guess.hpp).
/// 3. Identifiability: a rank-revealing QR of the column-scaled Jacobian (identifiability.hpp),
///    first on a rich synthetic design of the same measurement kind — dependencies found there
///    are the model's own (`link3.d` with `link2.d`) and are dropped, named — then on the data:
///    a further dependency is a design the measurements cannot support (InputError).
/// 4. Fit: Ceres trust region (Levenberg–Marquardt) on column-scaled unknowns with the analytic
///    Jacobian (residuals.hpp), optionally with a Huber loss after a least-squares pass.
/// 5. Statistics: σ² = RSS/(m − n), covariance σ²(JᵀJ)⁻¹, standard deviations, correlations,
///    residuals per target, suspected outliers, predicted accuracy (accuracy_prediction.hpp).
///
/// \warning The covariance assumes independent residuals of equal variance: for poses the
/// orientation weight must match the instrument's ratio of position to orientation noise.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "robcal/identify/accuracy_prediction.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/identify/identifiability.hpp"
#include "robcal/identify/residuals.hpp"
#include "robcal/identify/unknowns.hpp"
#include "robcal/measure/measurements.hpp"

namespace robcal {

struct IdentifyOptions {
  CalibrationLevel level = CalibrationLevel::Full;
  std::vector<std::string> identify;  ///< glob patterns of unknowns to add
  std::vector<std::string> fix;       ///< glob patterns of unknowns to hold at their start value
  bool huber = false;                 ///< robust fit (after a least-squares pass)
  double huber_scale_mm = 0;          ///< Huber threshold; 0: 3 × the robust σ of the LS pass
  double orientation_weight_mm = kDefaultOrientationWeightMm;
  int max_iterations = 100;
  /// Validation configurations for the predicted accuracy, drawn in the box of the measured
  /// joint values with this seed.
  int prediction_configurations = 1000;
  uint64_t seed = 1;
  /// Near-dependent groups (identifiability.hpp, kNearDependenceCorrelation): true holds the
  /// latest member of each at its start value (warned, status dropped); false fits them all
  /// (warned: their values are then arbitrary within a large σ).
  bool resolve_near_dependencies = true;
  /// The instrument's stated σ per axis (mm); 0 when not stated. With it the residuals are
  /// tested against the noise it explains (χ², IdentificationResult::noise_test).
  double instrument_sigma_mm = 0;
  /// Where the model parameters start and are held when not freed (internal units,
  /// kParameterCount values): a calibrated robot's (reidentify()); empty: the nominal ones.
  Eigen::VectorXd start_parameters;
  /// Time constant τ (s) of the warm-up group's φ(t) = 1 − exp(−t/τ) (docs/method/03-error-model.md
  /// §10; `--warmup-tau-s`); none: the robot's warmup_time_constant_s (default 1800 s).
  std::optional<double> warmup_time_constant_s;
};

/// Gravity torque below which a joint's compliance cannot show in the measurements (N·mm): a
/// compliance ten times the published IRB 120 values (1e-5 rad/N·mm) under 0.1 N·mm deflects
/// the joint by 1e-6 rad, 1 µm at 1 m — below every instrument's resolution.
inline constexpr double kGravityTorqueFloorNmm = 0.1;

/// How the solver ended (an outcome, not an error).
struct SolverStatus {
  bool converged = false;
  int iterations = 0;
  std::string message;        ///< Ceres' termination reason
  double initial_rms_mm = 0;  ///< RMS residual at the start (after the rigid fit)
  double final_rms_mm = 0;
};

/// Everything an identification needs that does not depend on the measured values: built
/// once, it serves many fits of data with the same rows (the simulator's Monte Carlo).
struct IdentificationSetup {
  RobotModel model;
  Tool tool;
  MeasurementKind kind = MeasurementKind::Points;
  UnknownLayout layout;
  IdentifyOptions options;
  std::vector<bool> requested;  ///< unknowns the level and patterns free
  std::vector<int> free;        ///< unknowns fitted (requested minus dropped), layout order
  /// Unknowns not fitted and why: compliances without gravity torque (reason set), the model's
  /// own dependencies found on the synthetic design, near-dependent ones of the data's design.
  std::vector<Dependency> dropped;
  std::vector<std::string> warnings;  ///< found before fitting, for the user
  Eigen::VectorXd start;              ///< start values (nominal; extras zero) before the rigid fit
  Eigen::VectorXd scales;             ///< column scale of each free unknown (1/‖column‖)
  bool fit_base = false;              ///< all six base parameters free: start with the rigid fit
};

/// Checks and prepares an identification for measurements like `data` (its rows: joints,
/// targets; its values are used for the start point and column scales). Throws InputError for
/// a pattern matching nothing, too few rows for the number of unknowns (saying how many are
/// needed), or a design that cannot identify some unknowns (naming them and what they depend
/// on).
IdentificationSetup prepare_identification(const RobotModel& model, const Tool& tool,
                                           const MeasurementSet& data,
                                           const IdentifyOptions& options);

/// "depends on link2.d (+1.000): axes 2 and 3 are parallel": a dropped unknown's null-space
/// vector in words.
std::string describe_dependency(const UnknownLayout& layout, const RobotModel& model,
                                const Dependency& dependency);

/// The fitted unknowns and the solver's outcome.
struct FitResult {
  Eigen::VectorXd start;     ///< where the solver started (nominal robot, rigid fit)
  Eigen::VectorXd unknowns;  ///< layout order, internal units
  SolverStatus status;
  double huber_scale_mm = 0;  ///< the threshold used (0 without --loss huber)
};

/// The fast path: start (rigid fit) and solve for data with the rows `setup` was prepared for.
/// No statistics. Cost for 31 parameters from 50 points: ≈ 4–5 Jacobian evaluations of 50
/// rows (≈ 1 µs each) plus Ceres' dense normal-equation steps (benchmark: bench_identify).
FitResult fit_unknowns(const IdentificationSetup& setup, const MeasurementSet& data);

/// One identified (or fixed, or dropped) unknown in external units (mm, deg, rad/N·mm).
struct UnknownEstimate {
  std::string name;
  std::string unit;
  double nominal = 0;  ///< the start value (nominal parameter; rigid-fit value for the base)
  double value = 0;
  double std_dev = 0;  ///< 0 unless identified
  ParameterStatus status = ParameterStatus::Fixed;
  std::string reason;             ///< why fixed or dropped
  bool opt_in_not_asked = false;  ///< an opt-in group's term (e.g. periodic) left out as asked
};

struct TargetResiduals {
  std::string target;  ///< target name ("tcp" for poses)
  int rows = 0;
  double rms_mm =
      0;  ///< RMS over rows of the position residual norm (|length error| for distances)
  double max_mm = 0;
};

struct Correlation {
  std::string first, second;
  double rho = 0;
};

struct SuspectedOutlier {
  std::string config;
  int line = 0;
  double residual_mm = 0;  ///< position residual norm (|length error| for distances)
};

/// Are the residuals what the instrument's stated noise explains? RSS/σ² against χ²(m − n).
struct NoiseTest {
  bool tested = false;  ///< false without a stated instrument σ
  double instrument_sigma_mm = 0;
  double chi_square = 0;  ///< RSS / σ²
  int dof = 0;            ///< m − n
  double p_value = 1;     ///< P(χ²_dof ≥ chi_square)
  /// False when p < kNoiseTestLevel: the model misses systematic effects (or σ is
  /// understated), and the covariance-based prediction would present that misfit as noise.
  bool consistent = true;
};

/// Significance level of the noise test: a misfit is reported when a fit this bad would happen
/// less than once in a thousand calibrations of a perfect model.
inline constexpr double kNoiseTestLevel = 1e-3;

/// P(χ²_ν ≥ x) by the Wilson–Hilferty cube-root normal approximation (absolute error < 1e-3
/// for ν ≥ 10; the calibration's ν is in the tens to hundreds).
double chi_square_upper_tail(double x, int dof);

struct IdentificationResult {
  CalibratedRobot robot;
  SolverStatus status;
  std::vector<UnknownEstimate> unknowns;  ///< every unknown of the layout
  std::vector<std::string> warnings;      ///< found before fitting (IdentificationSetup)
  int residual_count = 0;
  int identified_count = 0;
  double sigma_mm = 0;  ///< a-posteriori residual standard deviation √(RSS/(m − n))
  /// One definition throughout: per row, the 3D position error (points; the TCP's for poses)
  /// or |length error| (distances); mean, RMS and maximum over the rows, at the solution and at
  /// the start (nominal robot placed by the rigid fit).
  double mean_mm = 0, rms_mm = 0, max_mm = 0;
  double start_mean_mm = 0, start_rms_mm = 0, start_max_mm = 0;
  std::vector<double> row_errors_mm;  ///< that error of each row at the solution, rows' order
  NoiseTest noise_test;
  double huber_scale_mm = 0;
  std::vector<TargetResiduals> by_target;
  std::vector<Correlation> correlations;   ///< strongest (|ρ| ≥ 0.5), at most 10, largest first
  std::vector<SuspectedOutlier> outliers;  ///< rows beyond 4 robust σ per axis (3.3: distances)
  double condition_number = 0;             ///< of the column-scaled Jacobian at the solution
  PredictedAccuracy predicted;
  Eigen::VectorXd values;      ///< all unknowns, internal units
  std::vector<int> free;       ///< the identified unknowns (indices into values)
  Eigen::MatrixXd covariance;  ///< over `free`, internal units
  /// Set by reidentify(): what was re-identified on a calibrated robot (the rest of `robot`
  /// is that robot's, unchanged).
  std::optional<Reidentification> reidentification;
};

/// Full calibration: prepare, fit, statistics and the calibrated robot (tool with the
/// identified target coordinates filled in).
IdentificationResult calibrate(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const IdentifyOptions& options);

}  // namespace robcal
