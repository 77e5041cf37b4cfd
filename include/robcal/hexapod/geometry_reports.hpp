#pragma once
/// \file
/// The workflows of the hexapod's geometry commands (`robcal hexapod dkp | poses | uncertainty |
/// world-frame`) and their JSON: the direct kinematics' solutions, the pruned poses with the
/// closest pair in orientation, and the tool-cup uncertainty per assembly mode with its Monte
/// Carlo check (docs/method/07-hexapod.md §2–§4).

#include <cstdint>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robcal/hexapod/direct_kinematics.hpp"
#include "robcal/hexapod/four_cup_kinematics.hpp"
#include "robcal/hexapod/poses.hpp"
#include "robcal/hexapod/uncertainty.hpp"
#include "robcal/hexapod/world_frame.hpp"

namespace robcal::hexapod {

/// {solutions: [{mode, signs, tool_cups_mm, base_T_tool}]}.
nlohmann::json dkp_json(const DkpResult& dkp);

/// Fixtures with a fourth cup: {distances (names), solutions: [{mode, rms_residual_mm,
/// tool_cups_mm, uncertainty_sigma_multiple (per tool cup, in multiples of a distance's σ)}]}.
nlohmann::json four_cup_dkp_json(const FourCupDkpResult& dkp);

/// {robot_T_world, corrected_cups_mm, planar {x_mm, y_mm, phi_deg}, rms_mm, iterations,
/// converged}.
nlohmann::json world_frame_json(const WorldFrameFit& fit);

/// The poses of a geometry and those kept after pruning.
struct PoseSelection {
  std::vector<HexapodPose> enumerated, kept;
  double angle_deg = 0, distance_mm = 0;  ///< the pruning thresholds
  /// The closest two enumerated poses in orientation, and their tool-fixture centres' distance:
  /// what the angle threshold must exceed for any pruning.
  double closest_orientation_deg = 180, closest_centres_mm = 0;
};

/// Enumerates and prunes. Throws InputError unless both thresholds are non-negative.
PoseSelection select_poses(const HexapodGeometry& geometry, double angle_deg, double distance_mm);
nlohmann::json pose_selection_json(const PoseSelection& selection);

/// The tool-cup uncertainty per assembly mode, analytic (Guide 98-3) and by Monte Carlo.
struct UncertaintyStudy {
  double sigma_um = 0;  ///< standard uncertainty of one ballbar distance
  uint64_t seed = 1;
  int samples = 0;
  std::vector<ModeUncertainty> analytic, monte_carlo;
  double worst_norm_sigma = 0;                     ///< largest |σ|/σ of a cup over the modes
  double monte_carlo_max_relative_difference = 0;  ///< of |σ| against the analytic one
};

/// Throws InputError unless σ > 0 and samples ≥ 100.
UncertaintyStudy uncertainty_study(const HexapodGeometry& geometry, double sigma_um, uint64_t seed,
                                   int samples);
nlohmann::json uncertainty_study_json(const UncertaintyStudy& study);

}  // namespace robcal::hexapod
