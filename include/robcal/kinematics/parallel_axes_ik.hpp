#pragma once
/// \file
/// Closed-form nominal inverse kinematics of the UR family: three parallel axes (2, 3, 4) and an
/// offset wrist (axes 5 and 6 meet, axis 4 passes beside them), all 8 branches, computed
/// directly from the robot's Modified-DH table.
///
/// Which robots: `analyze_parallel_axes` accepts an MDH table (links 1..6, θ offsets free) with
///   link 1: α = a = 0 (d1 free);           link 2: α = ±90° (a, d free);
///   link 3: α = 0, a ≠ 0 (d free);          link 4: α = 0, a ≠ 0 (d free);
///   link 5: α = ±90° (a, d free);           link 6: α = ±90°, a = 0 (d free),
/// and a joint map with an integer inverse (closed_form_joints.hpp). UR3e/5e/10e/16e and the CB3
/// UR5/UR10 are of this shape (their DH d4, d5, d6 are the MDH d of links 4, 5, 6).
///
/// Derivation (θ_i = q_i + θoffset_i the MDH link angles; nominal robot, base at the origin;
/// R = (X, Y, Z), p the flange pose):
///   n = z2 = z3 = z4 = −s_α2·y1 is the direction of the parallel axes. From frame 1 to frame 5
///   every displacement is perpendicular to n except d2 + d3 + d4 =: δ along it, so the point
///   where axes 5 and 6 meet, P = p − d6·Z, has P·n = δ, i.e. P·y1 = e := −s_α2·δ. With
///   h = ±√(P_x² + P_y² − e²) the coordinate of P along x1:
///     θ1 = atan2(P_y, P_x) − atan2(e, h)                        (front h > 0, back h < 0).
///   n seen from the flange, Rᵀn = s_α5·(sin θ5·cos θ6, −sin θ5·sin θ6, −s_α6·cos θ5), gives
///     θ5 = atan2(±|(Rᵀn)_xy|, −s_α5·s_α6·(Rᵀn)_z)               (flip: sin θ5 < 0),
///     θ6 = atan2(−s_α5·(Rᵀn)_y, s_α5·(Rᵀn)_x), both arguments times sign(sin θ5).
///   Frame 4 = flange·(A5·A6)⁻¹: x4 = cos θ5·(cos θ6·X − sin θ6·Y) + s_α6·sin θ5·Z and origin
///   O4 = P − d5·z5 − a5·x4, z5 = s_α6·(sin θ6·X + cos θ6·Y). In frame 2's plane
///   (Tz(d1)·Rz(θ1)·Tx(a2)·Rx(α2))⁻¹·frame 4 = Tz(δ)·Rz(θ2)·Tx(a3)·Rz(θ3)·Tx(a4)·Rz(θ4), a planar
///   3R arm: cos θ3 = (u² + v² − a3² − a4²)/(2·a3·a4) with (u, v) = ((O4 − d1·ẑ)·x1 − a2,
///   s_α2·(O4_z − d1)) (up/down: the two signs of sin θ3), θ2 = atan2(v, u) − atan2(a4·sin θ3,
///   a3 + a4·cos θ3), θ4 = θ234 − θ2 − θ3 with θ234 = atan2(s_α2·x4_z, x4·x1).
///
/// Labels: ArmConfig (inverse_kinematics.hpp) as arm_config computes them: front/back the side
/// of axis 1 where P lies (the two θ1 roots), up/down from the elbow of the planar arm (the sign
/// of s_α2·a3·a4·sin θ3, mirrored at the back), flip when sin θ5 < 0.
///
/// Singularities: |sin θ5| < kWristSingularSin (axis 6 parallel to axes 2–4): θ6 is kept at the
/// seed's value (only θ2 + θ3 + θ4 + θ6 is determined) and the solution flagged
/// `wrist_singular`; P on axis 1 (δ = 0): θ1 from the seed, flagged `shoulder_singular`. Where two
/// branches coincide (wrist singular, stretched elbow, P at distance |δ| from axis 1) the one
/// solution is returned, with the label its angles give, when either branch is in the mask.
/// Joint limits and turns as for nominal_ik of inverse_kinematics.hpp.

#include <optional>
#include <string>

#include "robcal/kinematics/closed_form_joints.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"

namespace robcal {

/// Constants of a UR-family robot from its MDH table. Immutable once built.
struct ParallelAxesGeometry : ClosedFormJoints {
  double d1 = 0, a2 = 0, a3 = 0, a4 = 0, a5 = 0, d5 = 0, d6 = 0;
  double delta = 0;  ///< d2 + d3 + d4, the offset along the parallel axes
  double s_alpha2 = 1, s_alpha5 = 1, s_alpha6 = 1;  ///< signs of the ±90° twists
};

/// The geometry when the model has the UR family's shape, else std::nullopt with `why_not`
/// (if given) naming the MDH entry or joint-map property that fails.
std::optional<ParallelAxesGeometry> analyze_parallel_axes(const RobotModel& model,
                                                          std::string* why_not = nullptr);

/// All solutions of the branches in `branch_mask` (bit 1 << ArmConfig::index()); `seed`
/// supplies θ6 at the wrist singularity and θ1 at the shoulder singularity.
IkResult nominal_ik(const ParallelAxesGeometry& geometry, const Pose<double>& world_T_flange,
                    const Vector6d& seed = Vector6d::Zero(), unsigned branch_mask = kAllBranches);

/// The branch `config`, of its equivalent turns the one nearest `seed` (as the ortho-parallel
/// nominal_ik_branch).
IkBranchResult nominal_ik_branch(const ParallelAxesGeometry& geometry,
                                 const Pose<double>& world_T_flange, const ArmConfig& config,
                                 const Vector6d& seed);

}  // namespace robcal
