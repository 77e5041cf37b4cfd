#pragma once
/// \file
/// Closing the loop on configuration design (docs/method/05-observability.md §5, issue 5 items
/// 5–6): for several random true robots, plan → simulate → calibrate → compare with the truth over
/// a task region, for D-optimal configurations and for the same number of random feasible ones, at
/// several counts (the accuracy-against-count curve), beside the accuracy predicted before
/// measuring from the design's parameter covariance.

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "robcal/campaign/cell.hpp"
#include "robcal/design/calibration_planning.hpp"
#include "robcal/design/task_region.hpp"
#include "robcal/sim/calibration_plan.hpp"
#include "robcal/sim/true_robot.hpp"

namespace robcal {

struct PlanStudyOptions {
  std::vector<int> counts{15, 20, 30, 40, 60};
  int seeds = 4;  ///< true robots; robot k draws from seeds seed + 10k + 0…4
  uint64_t seed = 1;
  PlanSettings plan;  ///< level, candidates, constraints, floor (count comes from `counts`)
  InstrumentKind instrument = InstrumentKind::LaserTracker;
  double noise_mm = 0;  ///< > 0 replaces the instrument's σ
  ErrorBounds bounds;   ///< of the random true robots
  /// Task region: TCP poses (world frame, solved for each true robot's placement; read from
  /// `task_poses_file`), else a box of TCP positions (world frame), else random
  /// configurations in the constrained joint box above the floor.
  std::vector<ListedPose> task_poses;
  std::string task_poses_file;
  std::optional<TaskBox> task_box;
  int task_count = 200;
  /// The planned design: Default is `plan`'s default (I-optimal with the guard when a task box
  /// or poses are given, else D-optimal); Published is not offered here.
  SelectionCriterion criterion = SelectionCriterion::Default;
  SelectionGuard guard;  ///< its box is set from the constraints
  /// Effects the model does not contain, switched on in every true robot (sim/true_robot.hpp
  /// enable_effects names: backlash, j6-periodic, mass-error, thermal).
  std::vector<std::string> effects;
  /// The cell (robot base, instrument, floor, keep-out boxes); empty: the simulator's cell.
  std::optional<campaign::Cell> cell;
  /// A prior calibration of each true robot, as a user would have run before planning: this
  /// many random candidates measured and cross-validated (prior_folds folds); its misfit
  /// allowance (design/misfit_allowance.hpp) gives the misfit-aware prediction. 0: none.
  int prior_count = 60;
  int prior_folds = 5;
};

/// The criterion the study's planned design uses for `options` (Default resolved).
SelectionCriterion study_criterion(const PlanStudyOptions& options);

/// Position error of the TCP over the task region, mm.
struct RegionError {
  double mean_mm = 0, rms_mm = 0, max_mm = 0;
};

/// One design (optimal or random) at one count for one true robot.
struct StudyOutcome {
  RegionError achieved;   ///< calibrated model against the truth
  RegionError predicted;  ///< before measuring: √tr(J_v C J_vᵀ) with C from the design
  /// √(predicted rms² + m²), m the prior calibration's misfit allowance (0 without a prior).
  double predicted_rms_with_misfit_mm = 0;
  double O1 = 0;
  int measured = 0;  ///< configurations the simulator measured (every planned one)
  bool converged = false;
};

struct StudyRow {
  int count = 0;
  std::vector<StudyOutcome> optimal, random;  ///< one per seed
};

struct PlanStudyResult {
  std::vector<uint64_t> seeds;          ///< s of each true robot
  std::vector<RegionError> nominal;     ///< nominal robot (placed like the truth), per seed
  std::vector<MisfitAllowance> misfit;  ///< from each robot's prior calibration (if any)
  double sigma_mm = 0;
  int candidates = 0;  ///< feasible candidates per seed (the smallest)
  int task_configurations = 0;
  std::vector<StudyRow> rows;
};

/// Runs the study on `model` with `tool`. True robot k uses s = seed + 10k: the truth from
/// seed s, candidates s + 1, random subsets s + 2, task region s + 3, measurement noise
/// s + 4 (one stream per robot, drawn in row order), the prior calibration s + 5 (its
/// configurations, then its noise; its folds seed s). `progress`, when set, is called after
/// each true robot.
PlanStudyResult run_plan_study(const RobotModel& model, const Tool& tool,
                               const PlanStudyOptions& options,
                               const std::function<void(int done, int total)>& progress = {});

/// One design's outcomes at one count, over the true robots: means of the mean and max TCP
/// errors, quadratic means of the RMS ones (the covariance predicts E[RMS²], and a plain mean
/// of RMS over few robots is biased low).
struct StudySummary {
  double achieved_mean_mm = 0, achieved_rms_mm = 0, achieved_max_mm = 0;
  double predicted_mean_mm = 0, predicted_rms_mm = 0;
  double predicted_rms_with_misfit_mm = 0;  ///< quadratic mean, like the RMS
  double O1 = 0;
};

StudySummary summarize(const std::vector<StudyOutcome>& outcomes);

}  // namespace robcal
