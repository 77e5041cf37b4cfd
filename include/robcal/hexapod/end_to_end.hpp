#pragma once
/// \file
/// The simulated end-to-end hexapod calibration (docs/method/08-world-frame.md §3,
/// 11-published-results.md (LR Mate 200iC) experiment): a true robot with random errors, a
/// base-fixture placement, planning, ballbar readings with σ and ±range, a preliminary calibration
/// on what was measurable, re-planning of the rest with the preliminary model, the final
/// calibration, and validation with a simulated laser tracker on random configurations — absolute
/// errors and all-pairs distance errors — before and after. The pose-based fit (through
/// `calibrate`, relative model + world frame from the base cups) is compared with the fit straight
/// from the raw readings (leg_fit.hpp).

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "robcal/hexapod/cup_collision.hpp"
#include "robcal/hexapod/plan_file.hpp"
#include "robcal/hexapod/simulation.hpp"
#include "robcal/sim/true_robot.hpp"
#include "robcal/validate/error_statistics.hpp"

namespace robcal::hexapod {

struct EndToEndOptions {
  HexapodCellOptions cell;
  /// Errors of the true robot (its base levelled: see the .cpp). Compliance up to 0.05e-6 rad per
  /// N·mm: ≈ 0.2° at joint 2 of an LR Mate 200iC under its ≈ 70 N·m, the published order.
  ErrorBounds errors{0.3, 0.1, 0.05e-6, 1.0, 0.1};
  double angle_deg = 30;  ///< pose pruning
  double distance_mm = 50;
  CupClearance cups;  ///< poses whose cups or legs collide are refused before pruning
  int validation_configurations = 10000;
  double tracker_sigma_mm = 0.022;  ///< docs/method/06-instruments.md §1, laser tracker
  int threads = 2;                  ///< all-pairs statistics
  bool leg_fit = true;              ///< also fit from the raw readings
  /// Hold the base in the pose fits (the published relative model): the fit then keeps the error
  /// of the world frame the uncalibrated robot gave the base cups.
  bool relative_pose_fit = false;
};

/// `settings` (validation, threads, fits, errors) in the cell `plan` describes: its fixtures,
/// placement (tilt included), offsets, table, pruning, gauge and cup clearance.
EndToEndOptions end_to_end_options(const HexapodPlanRequest& plan, EndToEndOptions settings = {});

/// Accuracy of one model on the validation configurations.
struct ValidationFigures {
  ErrorStatistics absolute;  ///< |measured − predicted| of the validation target, mm
  ErrorStatistics pairs;     ///< all-pairs distance errors, mm
};

struct CalibrationStage {
  int configurations = 0;  ///< used in the fit
  double rms_mm = 0;       ///< residual RMS (position part for poses)
  int iterations = 0;
  bool converged = false;
  ValidationFigures validation;
};

struct EndToEndReport {
  std::string robot;
  int poses_enumerated = 0, poses_refused = 0, poses_kept = 0, poses_measurable = 0,
      configurations_planned = 0;
  int measured_first = 0;  ///< configurations whose six legs were all in range
  int retried = 0;         ///< out of range at first, re-planned with the preliminary model
  int measured_after_replan = 0;
  /// Legs read in the configurations measured (first pass and after re-planning), and of those
  /// the legs to a fourth tool cup and from a fourth base cup (a B4–T4 leg counts in both).
  int legs_read = 0, legs_read_fourth_cup = 0, legs_read_base_cup4 = 0;
  double world_frame_rms_mm = 0;
  /// The fitted world frame against the true base fixture frame (translation, rotation): the
  /// uncalibrated robot's error where it placed the cups.
  double world_frame_error_mm = 0, world_frame_error_deg = 0;
  ValidationFigures nominal;
  CalibrationStage preliminary, final_pose_fit, leg_fit;
  double leg_fit_offset_mm = 0;
  /// With a fourth base cup: |fitted B4 − true B4| in the frame of B1..B3 (each fit's own
  /// B1..B3 against the true ones), and the worst error of its fitted distances to B1..B3, mm.
  std::optional<double> leg_fit_base_cup4_error_mm, leg_fit_base_cup4_distance_error_mm;
  int validation_configurations = 0;
};

EndToEndReport run_end_to_end(const RobotModel& model, const EndToEndOptions& options,
                              std::mt19937_64& rng);

}  // namespace robcal::hexapod
