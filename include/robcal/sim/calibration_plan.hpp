#pragma once
/// \file
/// Planning a calibration for one instrument of a simulated cell (docs/method/05-observability.md
/// §2–§3): feasible candidates the instrument will see, their design matrix and the D-optimal
/// choice. Shared by `robcal plan`, the simulated campaigns (`robcal demo`, `robcal experiments`,
/// Monte Carlo) and the plan study, so every planned configuration passes the simulator's own
/// visibility test (measure/instrument.hpp) on the real robot.

#include <random>
#include <vector>

#include "robcal/design/candidates.hpp"
#include "robcal/design/design_matrix.hpp"
#include "robcal/design/selection.hpp"
#include "robcal/identify/unknowns.hpp"
#include "robcal/sim/simulator.hpp"

namespace robcal {

struct PlanSettings {
  CalibrationLevel level = CalibrationLevel::Full;
  int count = 40;
  int candidates = 5000;
  JointConstraints constraints = published_joint_constraints();
  /// Targets, flange and wrist above this height over the robot's base plane.
  double floor_mm = 50;
  /// The plan is made on the nominal robot and measured on the real one, whose flange
  /// orientation differs (geometry errors and joint compliance under the payload): a candidate
  /// must stay visible with the SMR cone and the CMM facing limit narrowed by this much (and
  /// the range limits by `visibility_margin_mm`), so no planned target falls out of sight on
  /// the real robot. 4° covers the published IRB 120 (0.6° at most over 500 random
  /// configurations of the published joint box) and the random truths of the default
  /// ErrorBounds (up to 2.8° over 500 configurations each of 8 seeds, more at the extremes).
  double visibility_margin_deg = 4.0;
  double visibility_margin_mm = 10.0;
};

/// The nominal robot placed at `base` (the 6 base parameters, mm and rad): what the planner
/// knows of the cell, never the real robot's errors.
TrueRobot planning_cell(const RobotModel& model, const Tool& tool,
                        const Eigen::Matrix<double, 6, 1>& base);

/// The cell's instrument with its visibility limits narrowed by the settings' margins.
VirtualInstrument planning_instrument(const VirtualInstrument& instrument,
                                      const PlanSettings& settings);

/// What an instrument measures: points (tracker), poses (CMM) or distances (ballbar).
MeasurementKind measurement_kind(InstrumentKind kind);

/// The instrument's σ per scalar reading (mm): the tracker's largest per-axis σ, the CMM's
/// position σ, the ballbar's.
double instrument_sigma(const VirtualInstrument& instrument);

/// `settings.candidates` feasible candidates in `cell`: inside the constrained joint box,
/// above the floor, and seen by planning_instrument() through the simulator's visibility
/// functions (tracker: visible_targets, CMM: cmm_sees_tool; ballbar: the simulator's random
/// configurations moved onto the bar's sphere). InputError (key `--instrument`, `--floor-mm`
/// or `--constraints`) when nothing is feasible.
CandidateSet instrument_candidates(const TrueRobot& cell, const VirtualInstrument& instrument,
                                   const PlanSettings& settings, std::mt19937_64& rng);

/// Design settings of the instrument's measurements, linearised at the cell's parameters.
DesignSettings plan_design_settings(const TrueRobot& cell, const VirtualInstrument& instrument,
                                    CalibrationLevel level);

/// The chosen candidates as configurations named C1, C2, … in selection order, grouped by
/// payload (the operator mounts each once), with their approach sides and payloads.
std::vector<PlannedConfiguration> planned_configurations(const std::vector<Candidate>& candidates,
                                                         const std::vector<int>& chosen);

struct CalibrationPlan {
  CandidateSet candidates;
  DesignMatrix design;
  Selection selection;
  std::vector<PlannedConfiguration> configurations;
};

/// Candidates, design matrix and the fast D-optimal choice of `settings.count` of them.
CalibrationPlan plan_calibration(const TrueRobot& cell, const VirtualInstrument& instrument,
                                 const PlanSettings& settings, std::mt19937_64& rng);

}  // namespace robcal
