#pragma once
/// \file
/// Forward kinematics of the *nominal* robot (docs/method/02-frames.md §7 with every error
/// parameter zero and the base at the world origin) with the constant factors precomputed: the
/// cosines and sines of the twists α_i. Double only; the error model and derivatives stay in
/// forward_kinematics.hpp. Used where the nominal pose is needed many times (IK checks,
/// compensation loops, benchmarks); tests check it against flange_pose to 1e-12.

#include <array>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

/// The nominal MDH chain with cos α, sin α precomputed. Immutable once built.
struct NominalChain {
  std::array<double, kJointCount> cos_alpha{}, sin_alpha{}, a{}, d{}, theta_offset{};
  JointMap joint_map;
  bool map_identity = true;
};

NominalChain make_nominal_chain(const RobotModel& model);

/// World pose of the flange for controller joints (rad):
/// Trans(0, 0, d1)·Rz(θ1)·A_2⋯A_6, A_i = Rot_x(α_i)·Trans_x(a_i)·Rot_z(θ_i)·Trans_z(d_i).
Pose<double> nominal_flange_pose(const NominalChain& chain, const Vector6d& joints);

}  // namespace robcal
