#pragma once
/// \file
/// Closed-form nominal inverse kinematics of ortho-parallel robots with a spherical wrist
/// (docs/method/02-frames.md §7), computed directly from the robot's Modified-DH table, all
/// branches.
///
/// Which robots: `analyze_ortho_parallel` accepts an MDH table (links 1..6, θ offsets free) with
///   link 1: α = a = 0 (d1 free);           link 2: α = ±90°, d = 0 (a free);
///   link 3: α = 0, d = 0, a > 0;           link 4: α = ±90° (a, d free);
///   link 5: α = ±90°, a = d = 0;           link 6: α = ±90°, a = 0 (d free),
/// and a joint map whose matrix and inverse are integer (signs and couplings), so that a full
/// turn of any controller joint leaves the pose unchanged. Anything else: use numeric_ik.hpp.
///
/// Geometry used (angles θ_i are the MDH link angles, θ_i = q_i + θoffset_i):
///   wrist centre W = flange origin − d6·z_flange (axes 4, 5, 6 meet there);
///   W lies in the x1–z1 plane of frame 1, so θ1 = atan2(W_y, W_x) or that + π;
///   the planar 2R arm (a3 and the forearm vector (a4, d4)) gives θ3 (two elbows), then θ2;
///   R_34'ᵀ·R = Rz(θ4)·Rx(α5)·Rz(θ5)·Rx(α6)·Rz(θ6) gives (θ4, θ5, θ6) and its flip
///   (θ4 + π, −θ5, θ6 + π).
///
/// Configuration labels (precise definitions, independent of the maker's names):
///   front / back: the wrist centre W lies on the +x1 (front) or −x1 (back) side of axis 1, x1
///       being the direction of the shoulder offset link2.a (the arm's forward direction).
///   up / down:    in the arm plane (x1, z1), the elbow (axis 3) lies above (up) or below
///       (down) the line from the shoulder (axis 2) to W, "above" meaning the side of +z1 when
///       the arm is viewed with W on the right: sign(x1_W)·((W − S) × (E − S))·(−y1) > 0.
///   flip / no-flip: sin θ5 < 0 (flip) or ≥ 0 (no-flip), θ5 the MDH link-5 angle.
/// Label strings are "front-up-noflip", "back-down-flip", etc.
///
/// Singularities: when |sin θ5| < kWristSingularSin (axes 4 and 6 aligned) only θ4 ± θ6 is
/// determined: θ4 is kept at the seed's value and the solution is flagged `wrist_singular`;
/// when W lies on axis 1 (within kShoulderSingularMm), θ1 is kept at the seed's value.
/// Unreachable poses and poses whose solutions all violate the joint limits are reported in
/// `IkResult::status`, never thrown.
///
/// Joint limits: every solution is returned in controller joint values (rad) inside the
/// robot's limits; a joint whose range spans more than one turn yields every equivalent turn.
/// The hot path allocates nothing: results live in a fixed-size array.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "robcal/kinematics/closed_form_joints.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

/// |sin θ5| below which the wrist counts as singular (θ4 then comes from the seed).
inline constexpr double kWristSingularSin = 1e-8;
/// Distance (mm) of the wrist centre from axis 1 below which θ1 comes from the seed.
inline constexpr double kShoulderSingularMm = 1e-9;
/// |cos θ3| beyond 1 by less than this is still taken as a stretched elbow (rounding).
inline constexpr double kStretchedElbowCos = 1e-10;
/// Capacity of an IkResult: 8 branches × the equivalent turns of wide-range joints (2⁶ when
/// every joint spans ±360°, as on the UR family).
inline constexpr int kMaxIkSolutions = 512;

/// The arm configuration of one solution (see the file comment for the definitions). Plain
/// fields without initialisers keep IkResult's fixed array free to construct.
struct ArmConfig {
  bool back;
  bool down;
  bool flip;
  /// "front-up-noflip" style label.
  [[nodiscard]] std::string label() const;
  /// Index 0..7: back·4 + down·2 + flip.
  [[nodiscard]] int index() const { return (back ? 4 : 0) + (down ? 2 : 0) + (flip ? 1 : 0); }
  friend bool operator==(const ArmConfig&, const ArmConfig&) = default;
};

/// Parses a label made by ArmConfig::label(); std::nullopt when it is not one.
std::optional<ArmConfig> parse_arm_config(const std::string& label);

/// One solution; every field is set by the solver.
struct IkSolution {
  Vector6d joints;  ///< controller joint values, rad
  ArmConfig config;
  bool wrist_singular;     ///< θ4 was taken from the seed
  bool shoulder_singular;  ///< θ1 was taken from the seed
};

enum class IkStatus : std::uint8_t {
  Solved,         ///< at least one solution within the joint limits
  Unreachable,    ///< no arm configuration reaches the wrist centre
  OutsideLimits,  ///< reachable, but every solution violates a joint limit
  Truncated,      ///< more solutions than kMaxIkSolutions; the first ones are returned
};

/// Human-readable status name ("solved", "unreachable", ...).
const char* to_string(IkStatus status);

struct IkResult {
  IkStatus status = IkStatus::Unreachable;
  int count = 0;             ///< valid entries of `solutions`
  int branches_reached = 0;  ///< arm branches (of 8) that reach the pose, before joint limits
  std::array<IkSolution, kMaxIkSolutions> solutions;

  [[nodiscard]] const IkSolution* begin() const { return solutions.data(); }
  [[nodiscard]] const IkSolution* end() const { return solutions.data() + count; }
};

/// Constants of an ortho-parallel robot precomputed from its MDH table and joint map, so a
/// solve does no set-up work. Immutable once built; safe to share between threads.
struct OrthoParallelGeometry : ClosedFormJoints {
  double d1 = 0, a2 = 0, a3 = 0, a4 = 0, d4 = 0, d6 = 0;
  double s_alpha2 = 1, s_alpha4 = 1, s_alpha5 = 1, s_alpha6 = 1;  ///< signs of the ±90° twists
  double rho = 0;                   ///< |(a4, s_α4·d4)|, forearm length to the wrist centre
  double cos_psi = 1, sin_psi = 0;  ///< direction ψ of the forearm vector in frame 3
  double psi = 0;
};

/// The geometry when the model is ortho-parallel with a spherical wrist, else std::nullopt
/// with `why_not` (if given) saying which MDH entry or joint-map property fails.
std::optional<OrthoParallelGeometry> analyze_ortho_parallel(const RobotModel& model,
                                                            std::string* why_not = nullptr);

/// Mask of every configuration branch for nominal_ik; branch i is bit 1 << ArmConfig::index().
inline constexpr unsigned kAllBranches = 0xFFu;

/// All solutions for the flange pose `world_T_flange` (nominal robot, base at the world
/// origin), of the branches in `branch_mask`. `seed` (controller joints, rad) supplies θ4 at a
/// wrist singularity and θ1 at a shoulder singularity. Where two branches coincide (wrist
/// singular: flip and no-flip; stretched elbow: up and down) the one solution is returned, with
/// the label its angles give, when either branch is in the mask.
IkResult nominal_ik(const OrthoParallelGeometry& geometry, const Pose<double>& world_T_flange,
                    const Vector6d& seed = Vector6d::Zero(), unsigned branch_mask = kAllBranches);

/// The solution of one configuration branch, computed without the others.
struct IkBranchResult {
  /// Solved; Unreachable when this branch does not reach the pose; OutsideLimits when its
  /// solution violates a joint limit.
  IkStatus status = IkStatus::Unreachable;
  IkSolution solution;  ///< valid when status == Solved
};

/// The branch `config` of nominal_ik: of its equivalent turns (joints whose range exceeds one
/// turn), the one nearest `seed` (each joint independently, so nearest in every norm). `seed`
/// also plays its singular-case role as in nominal_ik; at a wrist singularity or stretched
/// elbow the coinciding solution is returned with the label its angles give (see nominal_ik).
IkBranchResult nominal_ik_branch(const OrthoParallelGeometry& geometry,
                                 const Pose<double>& world_T_flange, const ArmConfig& config,
                                 const Vector6d& seed);

/// The solution nearest to `joints` (max-norm over joints), or nullptr when there is none.
const IkSolution* nearest_solution(const IkResult& result, const Vector6d& joints);

/// The configuration of controller joints from the link frames, by the definitions above with
/// S, E the origins of frames 2, 3 and W the origin of frame 4 for up/down, of frame 5 for
/// front/back (the same point, the wrist centre, on a spherical wrist; on the UR family,
/// parallel_axes_ik.hpp, the point of axis 4 in the arm plane and the meeting point of axes 5
/// and 6). Meaningful for any six-revolute arm of these shapes.
ArmConfig arm_config(const RobotModel& model, const Vector6d& joints);

/// For tools (CLI, Python): every closed-form solution when the robot has one (closed_form_ik.hpp,
/// where it is defined), else the damped-least-squares solution from `seed` (numeric_ik.hpp)
/// labelled by arm_config. Allocates; the hot path is nominal_ik.
struct AnyIkResult {
  IkStatus status = IkStatus::Unreachable;
  std::vector<IkSolution> solutions;
  std::string method;  ///< which solver ran, and why
};
AnyIkResult solve_ik(const RobotModel& model, const Pose<double>& world_T_flange,
                     const Vector6d& seed = Vector6d::Zero());

}  // namespace robcal
