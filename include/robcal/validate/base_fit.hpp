#pragma once
/// \file
/// Placing a robot in the measurement (world) frame by a rigid best fit: the world frame of a
/// tracker is arbitrary, so a model whose base was never fitted has no world frame. The rigid
/// transform minimising Σ|m_i − (R p_i + t)|² (Horn / Kabsch, through Eigen::umeyama) is folded
/// into the six base parameters of docs/method/02-frames.md §4.

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/measure/measurements.hpp"

namespace robcal {

/// The robot with base parameters (x, y, z, α, β, γ) such that world_A_1 = T_fit · world_A_1:
/// its predicted positions (targets or TCP) move rigidly onto the measured ones in the
/// least-squares sense, and `base_fitted` becomes true. Exact for a robot without compliance;
/// with compliance, gravity keeps its direction in the world, so the fit is the first step of
/// a calibration rather than its result.
/// \throws InputError when the measured positions do not fix a frame (fewer than 3 rows, or
///   all on one line)
CalibratedRobot fit_base(const CalibratedRobot& robot, const MeasurementSet& set);

}  // namespace robcal
