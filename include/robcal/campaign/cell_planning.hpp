#pragma once
/// \file
/// A cell file in the form the planner and the simulator take (for `plan --cell`,
/// `simulate --cell`): the base parameters for sim/calibration_plan.hpp planning_cell, the
/// instrument as the simulator's VirtualInstrument, and cell candidates as design's
/// CandidateSet.

#include <Eigen/Core>

#include "robcal/campaign/feasibility.hpp"
#include "robcal/design/candidates.hpp"
#include "robcal/sim/simulator.hpp"

namespace robcal::campaign {

/// The cell's robot base as the six base parameters (x, y, z mm; α, β, γ rad).
Eigen::Matrix<double, 6, 1> base_parameters(const Cell& cell);

/// The cell's instrument for the simulator. Tracker: position, range, SMR cone, σ (when the
/// cell gives one) and the SMR axes of `tool`'s targets (the cell's, else the default axis).
/// Optical CMM: position, range, facing limit, σ, and the target axes as the artifact's face
/// normals (the simulator has no field of view: check_configuration applies it).
VirtualInstrument virtual_instrument(const Cell& cell, const Tool& tool);

/// Cell candidates as the planner's candidate set: below_floor counts the draws below the
/// floor or in a keep-out box, not_visible those the instrument could not read (range,
/// facing, view, occlusion, too few targets); draws outside the joint limits are not counted
/// (the planner draws inside them).
CandidateSet candidate_set(const CellCandidates& cell_candidates);

}  // namespace robcal::campaign
