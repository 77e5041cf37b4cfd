#pragma once
/// \file
/// The `plan` workflow (docs/method/05-observability.md §2–§5): choose the configurations to
/// measure in a cell and predict the accuracy they give before measuring. Candidates are drawn in
/// the cell (the simulator's standard cell, or a cell file), or read from the user's list; they are
/// generated and scored in streaming batches so that memory stays bounded whatever their number;
/// the choice is I-optimal over the task region with a robustness guard when a task region is
/// given, else D-optimal; a random choice of the same count is scored beside it.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "robcal/campaign/cell.hpp"
#include "robcal/design/candidates.hpp"
#include "robcal/design/misfit_allowance.hpp"
#include "robcal/design/observability.hpp"
#include "robcal/design/task_region.hpp"
#include "robcal/design/task_selection.hpp"
#include "robcal/identify/accuracy_prediction.hpp"
#include "robcal/identify/unknowns.hpp"
#include "robcal/sim/calibration_plan.hpp"

namespace robcal {

enum class SelectionCriterion {
  Default,    ///< I-optimal when a task region is given, else D-optimal
  DOptimal,   ///< fast D-optimal (selection.hpp select_d_optimal)
  IOptimal,   ///< task-aware (task_selection.hpp), with the guard
  Published,  ///< the published exchange on O1
};

/// "default", "d", "i" or "published"; InputError naming `flag` otherwise.
SelectionCriterion parse_selection_criterion(const std::string& text,
                                             const std::string& flag = "--criterion");
const char* criterion_name(SelectionCriterion criterion);

/// The joint constraints `plan` applies by default: the published ones for the robot they were
/// published for (the ABB IRB 120, docs/method/05-observability.md §2), the robot file's own joint
/// limits for every other robot.
JointConstraints default_joint_constraints(const RobotModel& model);

/// A preset name: "auto" (default_joint_constraints), "robot" (the robot file's limits only),
/// "published" or "none" (= "robot"). InputError naming `flag` otherwise.
JointConstraints plan_joint_constraints(const RobotModel& model, const std::string& name,
                                        const std::string& flag = "--constraints");

/// Which candidates are near the task region (the guard's task share, task_selection.hpp): their
/// TCP inside the bounding box of the task configurations' TCP positions grown by `margin_mm`
/// (the robot placed by `params`).
std::vector<char> near_task_region(const RobotModel& model, const Tool& tool,
                                   const ParameterVector& params, const std::vector<Vector6d>& task,
                                   const std::vector<Candidate>& candidates, double margin_mm);

/// Whether the plan varies a measurement condition across its candidates (the approach side of
/// each joint, the payload): the design then sees the groups that need the variety (backlash,
/// compliance across payloads, docs/method/03-error-model.md §6–§7) and chooses among it.
enum class ConditionVariety {
  Auto,    ///< varied when a group that needs it is planned for (and, for payloads, listed)
  Fixed,   ///< every configuration from below / with the tool's own payload
  Varied,  ///< each candidate's sides drawn per joint / its payload drawn among the tool's
};

/// "auto", `fixed_name` ("below", "own") or "varied"; InputError naming `flag` otherwise.
ConditionVariety parse_condition_variety(const std::string& text, const std::string& fixed_name,
                                         const std::string& flag);

struct PlanRequest {
  RobotModel model;
  Tool tool;
  InstrumentKind instrument = InstrumentKind::LaserTracker;  ///< ignored with a cell
  CalibrationLevel level = CalibrationLevel::Full;
  /// Opt-in groups or parameter patterns planned for besides the level's, as `calibrate
  /// --identify` takes them ("backlash", "joint6.periodic", "groups").
  std::vector<std::string> identify;
  /// Approach sides and payloads of drawn candidates (listed ones keep their file's).
  ConditionVariety approach = ConditionVariety::Auto;
  ConditionVariety payloads = ConditionVariety::Auto;
  int count = 40;
  int candidates = 5000;  ///< random candidates to draw (not with candidate_configurations)
  uint64_t seed = 1;
  std::optional<JointConstraints> constraints;  ///< empty: default_joint_constraints(model)
  double floor_mm = 50;                         ///< without a cell (the cell has its floor)
  double noise_mm = 0;                          ///< > 0 replaces the instrument's σ
  SelectionCriterion criterion = SelectionCriterion::Default;
  SelectionGuard guard;  ///< its box is set from the constraints
  /// The cell (campaign/cell.hpp); empty: the simulator's standard cell.
  std::optional<campaign::Cell> cell;
  /// The user's candidate configurations (e.g. already measured); empty: random candidates.
  std::vector<PlannedConfiguration> candidate_configurations;
  std::string candidates_file;  ///< where they were read from (messages)
  /// Task region: configurations, else TCP poses (world frame), else a TCP box, else random
  /// configurations in the constrained joint box above the floor.
  std::vector<Vector6d> task_configurations;
  std::string task_configurations_file;
  std::vector<ListedPose> task_poses;
  std::string task_poses_file;
  std::optional<TaskBox> task_box;
  int task_count = 1000;
  /// Candidates kept for the selection: larger draws are scored in batches of this size and
  /// only the most informative this many kept (see plan_calibration).
  int pool = 5000;
  /// The model misfit (misfit_allowance.hpp): a prior calibration of this robot with its
  /// cross-validation (its file for messages), or a value given directly; neither: unknown, and
  /// the prediction is the noise-only one, labelled so.
  std::optional<CalibratedRobot> prior_model;
  std::string prior_model_file;
  std::optional<double> misfit_mm;
};

struct PlanResult {
  std::vector<PlannedConfiguration> configurations;             ///< C1, C2, … in selection order
  SelectionCriterion criterion = SelectionCriterion::DOptimal;  ///< the one used
  int candidates = 0;  ///< feasible candidates found (drawn or listed and usable)
  int pooled = 0;      ///< kept for the selection (≤ request.pool)
  long draws = 0, below_floor = 0, not_visible = 0;
  int outside_limits = 0;                ///< listed candidates outside the joint limits (left out)
  std::vector<int> parameters, dropped;  ///< layout indices
  bool approach_varied = false;          ///< drawn candidates approached from varied sides
  bool payloads_varied = false;          ///< drawn candidates carrying varied payloads
  ObservabilityIndices selected, random;
  double d_efficiency_selected = 0, d_efficiency_random = 0;  ///< against the pool's optimum
  int exchanges = 0, restarts = 0;
  int near_edge = 0, near_edge_random = 0;  ///< chosen configurations near a joint-range edge
  int edge_limit = 0;                       ///< the guard's cap (count when off)
  double sigma_mm = 0;
  std::string region;  ///< the task region, in words
  int task_configurations = 0;
  bool task_region_given = false;
  PredictedAccuracy predicted_selected, predicted_random;  ///< noise only: σ²(JᵀJ)⁻¹
  /// When the misfit is known: its allowance and the RMS TCP error over the task region
  /// expected with it, √(rms² + m²) (rms_with_misfit).
  std::optional<MisfitAllowance> misfit;
  double predicted_rms_with_misfit_selected = 0, predicted_rms_with_misfit_random = 0;
  std::string instrument;  ///< its name
  std::string cell;        ///< the cell's name ("simulator standard cell" without a file)
  /// What the user should know about the choice (e.g. a D-optimal design resting on the
  /// joint-range edges, which the guard would have capped), one sentence each.
  std::vector<std::string> notes;
};

/// Plans a calibration. Random candidates are drawn in batches of `request.pool`; while the
/// pool is full, every new batch's design rows are scored together with the pool's and only
/// the `pool` candidates with the greatest leverage tr(A_i M⁻¹ A_iᵀ) under the information M of
/// everything drawn so far are kept (the D-optimal design is supported on high-leverage
/// candidates, Harman & Pronzato 2007), half of them among candidates away from the joint-range
/// edges when the guard is on; I-optimal choice scores leverage through the task information,
/// tr(A_i M⁻¹ B M⁻¹ A_iᵀ). The random comparison set is a uniform sample of every feasible
/// candidate (reservoir sampling), not of the pool. Throws InputError for bad requests (keys
/// as the CLI's flags).
PlanResult plan_calibration(const PlanRequest& request);

}  // namespace robcal
