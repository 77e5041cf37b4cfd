#pragma once
/// \file
/// Where the fit starts: the world frame of an instrument may be anywhere (a laser tracker's
/// frame is arbitrary), so the nominal robot is first placed by a rigid best fit (Horn/Kabsch,
/// Eigen::umeyama) of its modelled points to the measured ones; unknown target coordinates and
/// the ballbar centre get closed-form least-squares guesses.

#include <Eigen/Geometry>

#include "robcal/identify/residuals.hpp"

namespace robcal {

/// Base parameters (x, y, z mm; alpha, beta, gamma rad; docs/method/02-frames.md §4 convention
/// world_A_1 = Trans(x, y, d1 + z)·Rot_x(α)·Rot_y(β)·Rot_z(γ + θ1)) that place a robot whose
/// base frame (the nominal base at the origin) sits at `world_T_base` in the world.
Vector6d base_parameters_from_transform(const Eigen::Isometry3d& world_T_base, double d1_mm);

/// Fills the start values in `unknowns` (model parameters already set, extras zero):
/// - `fit_base`: the six base parameters from the rigid best fit of modelled to measured
///   positions (points, poses), alternating with the least-squares target coordinates of the
///   unknown targets (a few rounds: a target without coordinates starts at the flange centre);
/// - unknown targets alone (`fit_base` false): their least-squares coordinates;
/// - distances: the ballbar centre from the linear sphere fit |p_k − c|² = L_k².
/// Needs at least three rows at distinct positions for the rigid fit (InputError otherwise).
void initial_guess(const ResidualContext& context, bool fit_base, Eigen::VectorXd& unknowns);

}  // namespace robcal
