#pragma once
/// \file
/// A simulated calibration from several base-fixture placements (issue 20 item 1,
/// docs/method/08-world-frame.md §4): one true robot and one tool fixture; at each placement the
/// robot places the base cups by its nominal model, the ballbar measures their sides and the legs
/// of the chosen configurations of that placement's plan; the leg fit (leg_fit.hpp) identifies the
/// model with every placement's base cups; the result is validated against the true robot (no
/// instrument noise) on random configurations within the joint limits — the whole workspace —
/// in the first placement's base fixture frame.

#include <cstdint>
#include <random>
#include <vector>

#include "robcal/hexapod/plan_file.hpp"
#include "robcal/hexapod/simulation.hpp"
#include "robcal/identify/unknowns.hpp"
#include "robcal/sim/true_robot.hpp"
#include "robcal/validate/error_statistics.hpp"

namespace robcal::hexapod {

/// A placement's plan (written by `robcal hexapod plan`: its cell gives the placement) and the
/// configurations measured there (indices into its configurations; none: the placement is set up
/// but left out of the fit).
struct SimulatedPlacement {
  HexapodPlan plan;
  std::vector<int> chosen;
};

struct PlacementsSimulationOptions {
  double sigma_mm = 0.00051;                        ///< ballbar σ
  double fixture_tolerance_mm = 0.05;               ///< true fixture sides about the design
  CalibrationLevel level = CalibrationLevel::Full;  ///< identified (base held: leg fit)
  std::vector<std::string> identify;                ///< opt-in groups identified beyond the level
  int validation_configurations = 2000;
  uint64_t validation_seed = 1;  ///< of the validation configurations (the same for every design)
};

struct PlacementsSimulation {
  int configurations = 0;  ///< measured (all six legs in range)
  int out_of_range = 0;    ///< chosen configurations a leg of which the gauge could not read
  int legs = 0;            ///< legs read: six per configuration, and those to a fourth cup
  double fit_rms_mm = 0;
  bool converged = false;
  ErrorStatistics nominal;     ///< the nominal model (world frame of the cups) vs the truth, mm
  ErrorStatistics calibrated;  ///< the calibrated model vs the truth, mm
  /// The same after a rigid best fit of the model's points to the truth's (Umeyama): the accuracy
  /// of the model itself, without the error of the first placement's fitted frame.
  ErrorStatistics registered;
};

/// Simulates the placements' sessions with `truth` (payload `payload`) and calibrates. Throws
/// InputError for a plan without its cell, a placement whose cups the robot cannot place or a
/// first placement with nothing measured.
PlacementsSimulation simulate_placements(const RobotModel& model, const TrueRobot& truth,
                                         const PointMass& payload,
                                         const std::vector<SimulatedPlacement>& placements,
                                         const PlacementsSimulationOptions& options,
                                         std::mt19937_64& rng);

}  // namespace robcal::hexapod
