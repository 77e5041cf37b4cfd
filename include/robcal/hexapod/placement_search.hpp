#pragma once
/// \file
/// Where to put the base fixture (issue 20 items 1–2, docs/method/07-hexapod.md §7): every
/// placement of a grid (centroid x, y, z, yaw, tilt of the pivoting platform) is planned as
/// `robcal hexapod plan` would (enumeration, cup screening, pruning, IK, table/fixture/cell
/// clearance), and its measurable configurations are scored by the accuracy they predict over the
/// whole workspace: C = σ²·(JᵀJ)⁻¹ of the pose rows (design/predicted_accuracy.hpp) propagated to
/// random configurations in the joint limits (identify/accuracy_prediction.hpp). Pairs of the best
/// placements are scored the same way on the union of their configurations, each placement beyond
/// the first with its own six world-frame unknowns (docs/method/08-world-frame.md §4) — and at the
/// same number of configurations as one placement (every other configuration of each), the fair
/// comparison. Given the placements already measured, every grid placement is ranked as the next
/// one by what it adds to them (PlacementSearchResult::next).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robcal/design/task_region.hpp"
#include "robcal/hexapod/plan_file.hpp"
#include "robcal/identify/unknowns.hpp"

namespace robcal::hexapod {

/// A placement already measured: its plan's configurations.
struct MeasuredPlacement {
  std::string source;                 ///< the plan file, for messages
  std::array<double, 4> placement{};  ///< x, y, z (mm), yaw (deg)
  double tilt_deg = 0;
  /// Where the robot put the base cups B1..B3 (and B4), robot frame.
  std::vector<Eigen::Vector3d> setting_points;
  std::vector<Vector6d> joints;  ///< the configurations (controller, rad)
};

/// The measured placement of a plan written by `robcal hexapod plan`; InputError naming `source`
/// and the key when the plan has no cell or a configuration no joints.
MeasuredPlacement measured_placement(const HexapodPlan& plan, const std::string& source);

struct PlacementSearchRequest {
  /// Robot, fixtures, offsets, pruning, gauge, cup screening and workcell of every placement;
  /// its placement and tilt are replaced by each grid point.
  HexapodPlanRequest plan;
  std::vector<double> x_mm{450}, y_mm{0}, z_mm{300}, yaw_deg{0}, tilt_deg{0};
  CalibrationLevel level = CalibrationLevel::Kinematic;  ///< the parameters to identify
  /// Opt-in groups or parameter patterns identified beyond the level (as `calibrate --identify`),
  /// e.g. "periodic": joint-dependent errors need the joint ranges several placements visit.
  std::vector<std::string> identify;
  /// σ of one pose row (mm; rotation rows × the lever arm): the gauge σ times the DKP's worst-case
  /// amplification (≈ 3.2, docs/method/07-hexapod.md §4). With a fourth tool cup in the plan's
  /// geometry it is scaled by worst_tool_cup_uncertainty's all_legs / design_legs over the poses
  /// planned with it (§7).
  double pose_sigma_multiple = 3.2;
  int validation_configurations = 2000;  ///< random configurations in the joint limits …
  /// … or, given, configurations putting the tool fixture's frame in this box of the robot frame
  /// (tool axis down, task_region.hpp): the task region the predictions are over.
  std::optional<TaskBox> task_box;
  uint64_t seed = 1;
  /// How many placements, pairs and next placements to report (≥ 1); pairs are searched among
  /// the max(best, 2) best single placements.
  int best = 5;
  /// Placements already measured (none: no `next` ranking). Each once, apart from each other.
  std::vector<MeasuredPlacement> measured;
};

/// What the predictions are over, as the CLI prints it: "random configurations in the joint
/// limits" or the task box.
std::string task_region_text(const std::optional<TaskBox>& task_box);

struct PlacementScore {
  std::array<double, 4> placement{};  ///< x, y, z (mm), yaw (deg)
  double tilt_deg = 0;
  std::string refused;  ///< why the placement cannot be used (fixture in a keep-out box …)
  int poses_measurable = 0, configurations = 0;
  /// Of the parameters the whole grid determines (identified_parameters), those these
  /// configurations leave undetermined (0: all).
  int undetermined = 0;
  double observability_o1 = 0;   ///< O1 of the scaled pose Jacobian (design/observability.hpp)
  double predicted_mean_mm = 0;  ///< predicted mean position error over the workspace
  double predicted_max_mm = 0;
  [[nodiscard]] bool usable() const { return refused.empty() && configurations > 0; }
};

struct PlacementPair {
  int first = -1, second = -1;  ///< indices into PlacementSearchResult::ranked
  int configurations = 0, undetermined = 0;
  double observability_o1 = 0;
  double predicted_mean_mm = 0, predicted_max_mm = 0;  ///< every configuration of both
  /// Every other configuration of each: (n₁ + n₂)/2 configurations, as many as one placement
  /// measures on average; its prediction (0 when it leaves parameters undetermined).
  int equal_count_configurations = 0, equal_count_undetermined = 0;
  double equal_count_mean_mm = 0;
};

/// A grid placement as the next one after the measured placements: the prediction of all their
/// configurations and its own, each placement but the first with its own world frame.
struct NextPlacement {
  int rank = -1;  ///< index into PlacementSearchResult::ranked
  int configurations = 0, undetermined = 0;
  double predicted_mean_mm = 0, predicted_max_mm = 0;
};

struct PlacementSearchResult {
  /// Every grid placement, best first: usable ones with every parameter determined by predicted
  /// mean error, then those leaving parameters undetermined, then unusable ones.
  std::vector<PlacementScore> ranked;
  std::vector<PlacementPair> pairs;  ///< best first (predicted mean error of the union)
  CalibrationLevel level = CalibrationLevel::Kinematic;  ///< the request's
  std::vector<std::string> identify;                     ///< the request's opt-in groups
  std::optional<TaskBox> task_box;                       ///< the request's task region
  int parameters = 0;                                    ///< asked for at the level and by identify
  /// The design's parameters (layout indices): the level's less those no placement determines.
  std::vector<int> identified_parameters;
  double pose_sigma_mm = 0;
  /// With measured placements: their prediction alone, and the grid placements as the next one,
  /// best first (those overlapping a measured placement, unusable or with nothing to measure
  /// left out).
  int measured_configurations = 0, measured_undetermined = 0;
  double measured_mean_mm = 0, measured_max_mm = 0;
  std::vector<NextPlacement> next;
  int best = 0;  ///< the request's: how many of each to report
};

/// Throws InputError on bad fixtures, gauge or grid (an empty axis, more than 2000 placements),
/// a robot without closed-form IK, no grid placement with a configuration to measure, or measured
/// placements given twice or overlapping (a cup within a cup diameter of another placement's).
PlacementSearchResult search_placements(const RobotModel& model,
                                        const PlacementSearchRequest& request);

/// The I-optimal choice of `count` configurations among those of `plans` (one per placement,
/// written by `robcal hexapod plan`): design/task_selection.hpp's select_i_optimal on the pose
/// Jacobian with each placement's world-frame columns (placements × poses × configurations), the
/// task region being the validation configurations in the joint limits; and what it predicts.
/// Level, σ multiple, gauge σ, validation and seed come from `request`.
struct PlacementsDesign {
  std::vector<std::vector<int>> chosen;  ///< per plan, indices into its configurations
  /// The level's parameters, and those the candidates can determine (the design's columns;
  /// the prediction is of these only).
  int parameters = 0, identifiable = 0;
  int undetermined = 0;
  double predicted_mean_mm = 0, predicted_max_mm = 0;
};
PlacementsDesign design_placements(const RobotModel& model, const std::vector<HexapodPlan>& plans,
                                   int count, const PlacementSearchRequest& request);

/// `plan` reduced to its configurations `chosen` (indices, ascending), numbered again from 1:
/// what the operator measures at that placement. The planning outcome (what the placement
/// offered) is kept.
HexapodPlan plan_with_configurations(const HexapodPlan& plan, const std::vector<int>& chosen);

/// `robcal hexapod design`: which configurations to measure at each of several planned
/// placements (design_placements), each plan written again with only those.
struct PlacementsDesignRequest {
  std::vector<std::string> plan_files;  ///< written by `robcal hexapod plan --out`, ≥ 1
  /// Configurations in all; 0: as many as the first plan offers (the fair comparison with
  /// measuring that placement alone).
  int count = 0;
  CalibrationLevel level = CalibrationLevel::Kinematic;
  std::vector<std::string> identify;  ///< as PlacementSearchRequest::identify
  int validation_configurations = 2000;
  std::optional<TaskBox> task_box;  ///< as PlacementSearchRequest::task_box
  uint64_t seed = 1;
  /// Where to write each reduced plan (none, or one per plan file, in order; all written or none,
  /// write_files_atomically). A placement with nothing chosen is not worth setting up: no plan
  /// for it.
  std::vector<std::string> out_files;
};
struct PlacementsDesignResult {
  std::string robot;
  int count = 0;
  PlacementsDesign design;
  std::vector<HexapodPlan> plans;  ///< per plan file, reduced to its chosen configurations
  std::vector<int> offered;        ///< per plan file, the configurations it offered
  /// The first plan alone with the same count (its I-optimal choice): what measuring one
  /// placement predicts, for comparison.
  PlacementsDesign first_alone;
  std::vector<bool> written;  ///< per out file
};
/// Throws InputError naming the plan file: a plan without its cell, plans of different robots or
/// tool fixtures, overlapping placements, a count beyond the configurations offered, out files
/// not one per plan.
PlacementsDesignResult design_placements(const PlacementsDesignRequest& request);
/// The result as `robcal hexapod design --json` prints it (without the plans themselves).
nlohmann::json placements_design_json(const PlacementsDesignRequest& request,
                                      const PlacementsDesignResult& result);

/// The result as `robcal hexapod place --json` prints it (the `best` first placements and pairs).
nlohmann::json placement_search_json(const PlacementSearchResult& result);

}  // namespace robcal::hexapod
