#pragma once
/// \file
/// Nominal inverse kinematics of any six-revolute arm written in Modified DH, every real
/// solution (up to 16): Raghavan and Roth's elimination solved as an eigenvalue problem (Manocha
/// and Canny), for the robots neither closed form (inverse_kinematics.hpp, parallel_axes_ik.hpp)
/// accepts — the Fanuc CRX, Kinova/Doosan-like wrists, random 6R geometries.
///
/// Chain (θ_i the MDH link angles, nominal robot, base at the origin):
///   T = B·Rz(θ1)·K1·Rz(θ2)·K2·Rz(θ3)·K3·Rz(θ4)·K4·Rz(θ5)·K5·Rz(θ6),
///   B = Trans_z(d1), K_i = Rot_x(α_{i+1})·Trans_x(a_{i+1})·Trans_z(d_{i+1}).
/// With T' = B⁻¹·T, Rz(θ3)·K3·Rz(θ4)·K4·Rz(θ5)·K5·Rz(θ6) = K2⁻¹·Rz(−θ2)·K1⁻¹·Rz(−θ1)·T'.
/// The origin p and z axis l of both sides do not depend on θ6. From them, 14 scalar
/// equations: l, p, p·p, p·l, p×l, l·(p·p) − 2·p·(p·l); each is a trigonometric polynomial of
/// degree one in every angle, so the left sides are 27 coefficients over
/// {1, cos θ3, sin θ3}⊗{1, cos θ4, sin θ4}⊗{1, cos θ5, sin θ5} (fixed per robot) and the right
/// sides 9 over {1, cos θ1, sin θ1}⊗{1, cos θ2, sin θ2} (per pose). Both are found exactly by
/// interpolation at three equally spaced angles per variable — no symbolic expansion.
/// The 8 non-constant θ1θ2 monomials are eliminated by the left null space of their 14×8
/// coefficient matrix: 6 equations in θ3, θ4, θ5. Half-angle tangents x_i = tan((θ_i − φ_i)/2)
/// (fixed shifts φ_i keep the roots away from x = ∞), times (1 + x4²)(1 + x5²)(1 + x3²), and
/// the 6 equations again multiplied by x4 give M(x3)·v = 0, M = M0 + M1·x3 + M2·x3² (12×12),
/// v = (x4^i·x5^j), i ≤ 3, j ≤ 2. Its 24×24 companion matrix has 8 spurious eigenvalues x3 = ±i
/// whose eigenvectors depend on the geometry alone; restricted to their orthogonal complement
/// (computed once per geometry) it is 16×16 (docs/method/02-frames.md §7). Its real eigenvalues
/// are the θ3 of the solutions (eigenvalues only: Hessenberg and Francis QR on the active
/// window), v (null vector of M(x3)) gives θ4 and θ5; θ2 from the 3×5 linear system of the
/// two-rotation subproblem, θ1 and θ6 from the pose. Every candidate is polished by Newton on the
/// exact forward kinematics (unless it starts within 1e-8 rad of a solution already found: it is
/// that one) and kept only when it reproduces the pose within 1e-9 mm and 1e-11 rad; duplicates
/// (within 1e-6 rad) are merged.
///
/// Limits of the method: on special shapes (many zero lengths and twists) the elimination
/// started at joint 1 degenerates; `analyze_general_6r` takes the first cyclic start of the loop
/// (cyclic_shift) on which three arbitrary configurations are found again, and refuses the
/// robot when none is. Multiple roots: on the CRX the solutions come in pairs sharing (nearly)
/// the eliminated angle, a double eigenvalue whose computed eigenvectors are any mix of the
/// pair's vectors (split by rounding into two close reals or a conjugate pair). Roots within
/// 1e-4 of each other are taken as one cluster, and beside each root's own eigenvector the
/// null space of M(x3) (dimension: the cluster's size, or more when a pivoted QR shows it) is
/// searched for its monomial vectors (a small shift eigenproblem); every candidate is polished,
/// so the extra ones cost time, never a wrong answer. On spherical-wrist-like robots (TX2-60,
/// M1013) the double root is defective and rounding spreads it as ε^(1/4), beyond the cluster:
/// a multiple or crowded cluster that reaches fewer solutions at its own x3 than roots also
/// searches the near-null space (three wide) at each reached solution's exact x3 for its twin. A
/// real Schur that does not converge is retried with the next θ3 shift. Near a singularity (a
/// continuum of solutions) the solutions returned are the ones Newton reaches; they are exact,
/// the continuum is not enumerated.
///
/// Labels: arm_config's definitions (inverse_kinematics.hpp); on a general arm up to two
/// solutions share a label, and nominal_ik_branch picks the one nearest its seed (why no twin
/// index: docs/method/02-frames.md §7). Joint limits and turns as for the closed forms.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>

#include "robcal/kinematics/closed_form_joints.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"

namespace robcal {

/// The most real solutions a 6R arm has.
inline constexpr int kMaxGeneral6rSolutions = 16;

struct General6rElimination;

/// Constants of a 6R arm for the eigenvalue method. Immutable once built.
struct General6rGeometry : ClosedFormJoints {
  Pose<double> base;                 ///< B, mm
  std::array<Pose<double>, 5> link;  ///< K1..K5, mm
  double length_scale = 1;           ///< mm; lengths are divided by it inside the elimination
  /// Which joint plays θ1 in the elimination: the loop Rz(θ1)·K1⋯Rz(θ6)·(B⁻¹·T)⁻¹ = I is
  /// started at joint 1 + cyclic_shift, the first start on which the elimination is regular.
  int cyclic_shift = 0;
  /// The part of the elimination that does not depend on the pose (the left sides and the
  /// spurious eigenvalues' deflation, general_6r_ik.cpp), computed once by analyze_general_6r;
  /// null when the pose enters it (cyclic_shift 1 to 3), then computed per pose.
  std::shared_ptr<const General6rElimination> elimination;
};

/// The geometry of any model with an integer joint map, else std::nullopt with `why_not`
/// (if given) saying what fails.
std::optional<General6rGeometry> analyze_general_6r(const RobotModel& model,
                                                    std::string* why_not = nullptr);

/// Which paths one call of general_6r_link_angles took (docs/method/02-frames.md §7): what the
/// benchmarks report per pose and the tests hold the method to.
struct General6rCounts {
  int real_roots = 0;             ///< eigenvalues x3 taken as real (near-real pairs included)
  int eigenvector_solutions = 0;  ///< new solutions from a lone root's companion eigenvector
  int null_spaces = 0;            ///< pivoted-QR null spaces of M(x3) (clusters, fallbacks, twins)
  int twin_searches = 0;          ///< of those, searches for a twin at a solution's own x3
  int polishes = 0;               ///< candidates polished by Newton

  General6rCounts& operator+=(const General6rCounts& other) {
    real_roots += other.real_roots;
    eigenvector_solutions += other.eigenvector_solutions;
    null_spaces += other.null_spaces;
    twin_searches += other.twin_searches;
    polishes += other.polishes;
    return *this;
  }
};

/// MDH link angles θ1..θ6 (rad) of every real solution for `world_T_flange`, before joint
/// limits and turns; returns how many (≤ kMaxGeneral6rSolutions) were written to `out`, and
/// (if given) which paths it took in `counts`.
int general_6r_link_angles(const General6rGeometry& geometry, const Pose<double>& world_T_flange,
                           std::array<std::array<double, kJointCount>, kMaxGeneral6rSolutions>& out,
                           General6rCounts* counts = nullptr);

/// Every solution of the branches in `branch_mask` with every turn inside the limits.
IkResult nominal_ik(const General6rGeometry& geometry, const Pose<double>& world_T_flange,
                    const Vector6d& seed = Vector6d::Zero(), unsigned branch_mask = kAllBranches);

/// Of the solutions labelled `config`, the one nearest `seed` (max-norm over joints).
IkBranchResult nominal_ik_branch(const General6rGeometry& geometry,
                                 const Pose<double>& world_T_flange, const ArmConfig& config,
                                 const Vector6d& seed);

}  // namespace robcal
