#pragma once
/// \file
/// Where to put the base fixture (issue 20 items 1–2, docs/method/07-hexapod.md §7): every
/// placement of a grid (centroid x, y, z, yaw, tilt of the pivoting platform) is planned as
/// `robcal hexapod plan` would (enumeration, cup screening, pruning, IK, table/fixture/cell
/// clearance), and its measurable configurations are scored by the accuracy they predict over the
/// whole workspace: C = σ²·(JᵀJ)⁻¹ of the pose rows (design/predicted_accuracy.hpp) propagated to
/// random configurations in the joint limits (identify/accuracy_prediction.hpp). Pairs of the best
/// placements are scored the same way on the union of their configurations, assuming one world
/// frame shared by the placements (the second fixture's cups measured from the first's, issue 20
/// item 1) — and at the same number of configurations as one placement (every other configuration
/// of each), the fair comparison.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robcal/hexapod/plan_file.hpp"
#include "robcal/identify/unknowns.hpp"

namespace robcal::hexapod {

struct PlacementSearchRequest {
  /// Robot, fixtures, offsets, pruning, gauge, cup screening and workcell of every placement;
  /// its placement and tilt are replaced by each grid point.
  HexapodPlanRequest plan;
  std::vector<double> x_mm{450}, y_mm{0}, z_mm{300}, yaw_deg{0}, tilt_deg{0};
  CalibrationLevel level = CalibrationLevel::Kinematic;  ///< the parameters to identify
  /// σ of one pose row (mm; rotation rows × the lever arm): the gauge σ times the DKP's worst-case
  /// amplification (≈ 3.2, docs/method/07-hexapod.md §4).
  double pose_sigma_multiple = 3.2;
  int validation_configurations = 2000;  ///< random configurations in the joint limits
  uint64_t seed = 1;
  int pair_candidates = 6;  ///< pairs are searched among this many best single placements
};

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

struct PlacementSearchResult {
  /// Every grid placement, best first: usable ones with every parameter determined by predicted
  /// mean error, then those leaving parameters undetermined, then unusable ones.
  std::vector<PlacementScore> ranked;
  std::vector<PlacementPair> pairs;  ///< best first (predicted mean error of the union)
  int parameters = 0;                ///< asked for at the level
  /// The design's parameters (layout indices): the level's less those no placement determines.
  std::vector<int> identified_parameters;
  double pose_sigma_mm = 0;
};

/// Throws InputError on bad fixtures, gauge or grid (an empty axis, more than 2000 placements),
/// or a robot without closed-form IK.
PlacementSearchResult search_placements(const RobotModel& model,
                                        const PlacementSearchRequest& request);

/// The result as `robcal hexapod place --json` prints it (the `best` first placements and pairs).
nlohmann::json placement_search_json(const PlacementSearchResult& result, int best);

}  // namespace robcal::hexapod
