#pragma once
/// \file
/// Identification (METHOD §5): fit the robot's parameters to measurements.
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
};

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
  std::vector<bool> requested;      ///< unknowns the level and patterns free
  std::vector<int> free;            ///< unknowns fitted (requested minus dropped), layout order
  std::vector<Dependency> dropped;  ///< model dependencies found on the synthetic design
  Eigen::VectorXd start;            ///< start values (nominal; extras zero) before the rigid fit
  Eigen::VectorXd scales;           ///< column scale of each free unknown (1/‖column‖)
  bool fit_base = false;            ///< all six base parameters free: start with the rigid fit
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
  std::string reason;  ///< why fixed or dropped
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

struct IdentificationResult {
  CalibratedRobot robot;
  SolverStatus status;
  std::vector<UnknownEstimate> unknowns;  ///< every unknown of the layout
  int residual_count = 0;
  int identified_count = 0;
  double sigma_mm = 0;            ///< a-posteriori residual standard deviation √(RSS/(m − n))
  double rms_mm = 0, max_mm = 0;  ///< over rows, position residual norm
  double huber_scale_mm = 0;
  std::vector<TargetResiduals> by_target;
  std::vector<Correlation> correlations;   ///< strongest (|ρ| ≥ 0.5), at most 10, largest first
  std::vector<SuspectedOutlier> outliers;  ///< rows above 3 robust σ (per axis)
  double condition_number = 0;             ///< of the column-scaled Jacobian at the solution
  PredictedAccuracy predicted;
  Eigen::VectorXd values;      ///< all unknowns, internal units
  std::vector<int> free;       ///< the identified unknowns (indices into values)
  Eigen::MatrixXd covariance;  ///< over `free`, internal units
};

/// Full calibration: prepare, fit, statistics and the calibrated robot (tool with the
/// identified target coordinates filled in).
IdentificationResult calibrate(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const IdentifyOptions& options);

/// The fit statistics as a YAML map (for calibrated_robot_to_yaml).
std::string statistics_yaml(const IdentificationResult& result);

}  // namespace robcal
