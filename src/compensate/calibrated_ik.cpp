#include "robcal/compensate/calibrated_ik.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <variant>

#include <Eigen/LU>

#include "../kinematics/fast_atan2.hpp"
#include "robcal/core/error.hpp"

namespace robcal {
namespace {

/// World pose error e = (p* − p, log(R*·Rᵀ)), with the squared distance and the sine and
/// cosine of the rotation angle for the tolerance check; the angle itself only for the result.
struct PoseError {
  Vector6d e;
  double position_sq;
  double sin_angle, cos_angle;
  [[nodiscard]] double position_mm() const { return std::sqrt(position_sq); }
  [[nodiscard]] double orientation_rad() const { return fast_atan2(sin_angle, cos_angle); }
};

PoseError pose_error(const Pose<double>& wanted, const Pose<double>& reached) {
  PoseError out;
  out.e.head<3>() = wanted.p - reached.p;
  out.position_sq = out.e.head<3>().squaredNorm();
  // E = R*·Rᵀ = Σ_k a_k·b_kᵀ over the columns a_k of R*, b_k of R: the vector of its skew part
  // E − Eᵀ is w = Σ_k b_k × a_k (2·sin·axis) and its trace Σ_k a_k · b_k (1 + 2·cos).
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  double trace = 0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = wanted.R.col(k), b = reached.R.col(k);  // copies, not Blocks: faster
    w += b.cross(a);
    trace += a.dot(b);
  }
  const double sin_sq = 0.25 * w.squaredNorm();
  out.sin_angle = std::sqrt(sin_sq);
  out.cos_angle = 0.5 * (trace - 1.0);
  // log map: ½w·angle/sin. Within 0.01 rad (all but the first errors of a solve) angle/sin =
  // asin(s)/s by its series to s⁴, the next term 5s⁶/112 < 5e-14; beyond, by atan2. The ratio
  // tends to 1 as the rotation vanishes.
  double ratio = 1;
  if (sin_sq < 1e-4 && out.cos_angle > 0)
    ratio = 1 + sin_sq * (1.0 / 6 + sin_sq * (3.0 / 40));
  else if (out.sin_angle > 1e-12)
    ratio = out.orientation_rad() / out.sin_angle;
  out.e.tail<3>() = (0.5 * ratio) * w;
  return out;
}

/// Joint moves beyond which the branch is checked, and beyond which a step is shortened
/// (near a singularity a full Newton step can leap across the workspace).
constexpr double kBranchCheckRad = 0.05;
constexpr double kMaxStepRad = 0.25;

/// A Newton step gets the chain's second-order correction when its largest joint move lies
/// between kCurvatureMinStepRad (below, the curvature leaves < 3e-8 mm: nothing to correct)
/// and kCurvatureMaxStepRad, and the correction changes it by less than the step itself: near a
/// singularity (elbow close to stretch) the expansion no longer describes the chain and the
/// corrected step could turn back towards the other branch.
constexpr double kCurvatureMinStepRad = 1e-5;
constexpr double kCurvatureMaxStepRad = 0.1;

/// |det| of a 3×3 block below this fraction of its largest column norm cubed (about the
/// smallest LU pivot relative to the largest) counts as lost rank.
constexpr double kRankRatio = 1e-10;

using Columns3 = std::array<Eigen::Vector3d, 3>;

/// Rows of the inverse of the 3×3 matrix with columns a, b, c (b×c, c×a, a×b over the
/// determinant), false when it has (nearly) lost rank.
bool invert_block(const Columns3& m, Columns3& inverse_rows) {
  const Eigen::Vector3d bc = m[1].cross(m[2]), ca = m[2].cross(m[0]), ab = m[0].cross(m[1]);
  const double det = m[0].dot(bc);
  const double largest_sq = std::max({m[0].squaredNorm(), m[1].squaredNorm(), m[2].squaredNorm()});
  if (!(det * det > kRankRatio * kRankRatio * largest_sq * largest_sq * largest_sq))
    return false;  // NaN included
  const double inv_det = 1.0 / det;
  inverse_rows = {inv_det * bc, inv_det * ca, inv_det * ab};
  return true;
}

/// Solves J·x = e through the spherical wrist's decoupling (Pieper): with the linear rows taken
/// at the wrist centre (`r` = TCP − wrist centre, rows J_v + r × J_ω and e_v + r × e_ω, the
/// same system), J = [[A, B], [C, D]] has A the arm's position block and D the wrist's
/// orientation block (B vanishes on the nominal robot), and the Schur complement
/// S = D − C·A⁻¹·B gives x_w = S⁻¹·(e_ω − C·A⁻¹·e_v), x_a = A⁻¹·(e_v − B·x_w): exact, with
/// 3×3 inverses only, factored once per Jacobian for the two right-hand sides of a step. In
/// columns, rows, cross and dot products of 3-vectors, which the compiler keeps inline.
class WristPartitionedSolver {
 public:
  /// False at (or near) an arm or wrist singularity, where A or S loses rank.
  bool factor(const Matrix6d& J, const Eigen::Vector3d& r) {
    Columns3 A, S;
    for (int k = 0; k < 3; ++k) {
      C_[k] = J.block<3, 1>(3, k);
      A[k] = J.block<3, 1>(0, k) + r.cross(C_[k]);
    }
    r_ = r;
    if (!invert_block(A, A_inv_rows_)) return false;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d D_k = J.block<3, 1>(3, k + 3);
      const Eigen::Vector3d B_k = J.block<3, 1>(0, k + 3) + r.cross(D_k);
      A_inv_B_[k] = apply_rows(A_inv_rows_, B_k);
      S[k] = D_k - combine(C_, A_inv_B_[k]);
    }
    return invert_block(S, S_inv_rows_);
  }
  [[nodiscard]] Vector6d solve(const Vector6d& e) const {
    const Eigen::Vector3d e_w = e.tail<3>();
    const Eigen::Vector3d e_v = e.head<3>();
    const Eigen::Vector3d A_inv_e = apply_rows(A_inv_rows_, e_v + r_.cross(e_w));
    const Eigen::Vector3d x_w = apply_rows(S_inv_rows_, e_w - combine(C_, A_inv_e));
    Vector6d x;
    x.head<3>() = A_inv_e - combine(A_inv_B_, x_w);
    x.tail<3>() = x_w;
    return x;
  }

 private:
  static Eigen::Vector3d apply_rows(const Columns3& rows, const Eigen::Vector3d& v) {
    return {rows[0].dot(v), rows[1].dot(v), rows[2].dot(v)};
  }
  static Eigen::Vector3d combine(const Columns3& columns, const Eigen::Vector3d& v) {
    return v[0] * columns[0] + v[1] * columns[1] + v[2] * columns[2];
  }
  Columns3 A_inv_rows_, A_inv_B_, C_, S_inv_rows_;
  Eigen::Vector3d r_;
};

/// Solves J·x = e for a wrist that is not spherical, by LU with partial pivoting of J with its
/// angular rows scaled by kRotationRowScaleMm (so that all rows are in mm and the pivots
/// compare); singular when the smallest pivot falls below kRankRatio of the largest.
class FullJacobianSolver {
 public:
  bool factor(const Matrix6d& J, const Eigen::Vector3d& /*r*/) {
    Matrix6d scaled = J;
    scaled.bottomRows<3>() *= kRotationRowScaleMm;
    lu_.compute(scaled);
    const auto pivots = lu_.matrixLU().diagonal().cwiseAbs();
    return pivots.minCoeff() > kRankRatio * pivots.maxCoeff();  // NaN: false
  }
  [[nodiscard]] Vector6d solve(const Vector6d& e) const {
    Vector6d scaled = e;
    scaled.tail<3>() *= kRotationRowScaleMm;
    return lu_.solve(scaled);
  }

 private:
  static constexpr double kRotationRowScaleMm = 1000.0;
  Eigen::PartialPivLU<Matrix6d> lu_;
};

/// The angle is within tolerance when sin ≤ cos·tolerance (atan x ≤ x: never looser).
bool within(const PoseError& err, const CalibratedIkOptions& options) {
  return err.position_sq <= options.position_tolerance_mm * options.position_tolerance_mm &&
         err.cos_angle > 0 && err.sin_angle <= err.cos_angle * options.orientation_tolerance_rad;
}

/// Final verdict of a converged iterate: still in the seed's configuration, then the limits.
/// `expected` is the configuration asked for, or null for the seed's.
CalibratedIkResult finish(const Compensator& comp, const Vector6d& seed, const ArmConfig* expected,
                          const Vector6d& joints, const PoseError& err, int iterations) {
  CalibratedIkResult r;
  r.joints = joints;
  r.iterations = iterations;
  r.position_error_mm = err.position_mm();
  r.orientation_error_rad = err.orientation_rad();
  // On a spherical wrist the labels depend on model joints 1–3 and 5 only: the large moves of 4
  // and 6 near the wrist singularity need no check (on the UR family 4 moves the point P).
  const Vector6d moved = comp.chain.map_identity ? Vector6d(joints - seed)
                                                 : Vector6d(comp.chain.joint_map * (joints - seed));
  const double moved4 = comp.spherical_wrist ? 0.0 : std::abs(moved[3]);
  if (std::max({std::abs(moved[0]), std::abs(moved[1]), std::abs(moved[2]), moved4,
                std::abs(moved[4])}) > kBranchCheckRad &&
      !(arm_config(comp.model, joints) == (expected ? *expected : arm_config(comp.model, seed))))
    r.status = CalibratedIkStatus::LeftConfiguration;
  else
    r.status = comp.model.within_limits(joints) ? CalibratedIkStatus::Converged
                                                : CalibratedIkStatus::OutsideLimits;
  return r;
}

CalibratedIkResult failed(CalibratedIkStatus status, const Vector6d& joints, const PoseError& err,
                          int iterations) {
  CalibratedIkResult r;
  r.status = status;
  r.joints = joints;
  r.iterations = iterations;
  r.position_error_mm = err.position_mm();
  r.orientation_error_rad = err.orientation_rad();
  return r;
}

/// The nominal branch `config` of `base_T_tcp` for the flange, of the turn nearest `near`, on
/// `geometry`. Solved, or the status the calibrated inverse reports.
struct Seed {
  CalibratedIkStatus status;
  Vector6d joints;
};
Seed seed_of(const ClosedFormIk& geometry, const Pose<double>& base_T_flange,
             const ArmConfig& config, const Vector6d& near) {
  const IkBranchResult r = nominal_ik_branch(geometry, base_T_flange, config, near);
  switch (r.status) {
    case IkStatus::Solved:
      return {CalibratedIkStatus::Converged, r.solution.joints};
    case IkStatus::OutsideLimits:
      return {CalibratedIkStatus::OutsideLimits, Vector6d::Zero()};
    default:
      return {CalibratedIkStatus::NoNominalSolution, Vector6d::Zero()};
  }
}

}  // namespace

const char* to_string(CalibratedIkStatus status) {
  switch (status) {
    case CalibratedIkStatus::Converged:
      return "converged";
    case CalibratedIkStatus::NoNominalSolution:
      return "no nominal solution in this configuration";
    case CalibratedIkStatus::Singular:
      return "singular (at or near a singularity)";
    case CalibratedIkStatus::LeftConfiguration:
      return "left the configuration";
    case CalibratedIkStatus::NotConverged:
      return "not converged";
    case CalibratedIkStatus::OutsideLimits:
      return "outside the joint limits";
  }
  return "unknown";
}

Compensator make_compensator(const CalibratedRobot& robot, const std::optional<PointMass>& payload,
                             const RowConditions& row) {
  ReachCondition condition;
  condition.payload = payload.value_or(robot.tool.payload);
  if (row.approach) condition.approach = *row.approach;
  condition.temperature_rise_k = row.temperature_rise_k;
  condition.warmup_fraction = row.warmup_fraction;
  return make_compensator(robot, condition);
}

Compensator make_compensator(const CalibratedRobot& robot, const ReachCondition& condition) {
  Compensator comp;
  comp.model = robot.model;
  std::string why_not;
  const auto geometry = analyze_closed_form(robot.model, &why_not);
  if (!geometry)
    throw InputError(SourceLocation{"", 0, 0, "robot"},
                     "compensation needs the nominal closed-form inverse: " + why_not);
  comp.geometry = *geometry;
  comp.spherical_wrist = std::holds_alternative<OrthoParallelGeometry>(*geometry);
  RobotModel widened = robot.model;
  for (JointLimit& limit : widened.limits) {
    limit.lower -= kSeedLimitMarginRad;
    limit.upper += kSeedLimitMarginRad;
  }
  comp.seed_geometry = *analyze_closed_form(widened);
  for (int i = 0; i < kParameterCount; ++i)
    if (!std::isfinite(robot.params[i]))
      throw InputError(SourceLocation{"", 0, 0, parameter_table()[i].name},
                       "parameter is not a finite number");
  comp.flange_T_tcp.R = robot.tool.flange_T_tcp.linear();
  comp.flange_T_tcp.p = robot.tool.flange_T_tcp.translation();
  comp.condition = condition;
  comp.chain = make_calibrated_chain(
      robot.model, robot.params, condition.payload, comp.flange_T_tcp,
      {&comp.condition.approach, condition.temperature_rise_k, condition.warmup_fraction});
  // world_T_base = world_A_1(q1 = 0) · (nominal base_A_1(q1 = 0))⁻¹ = (R_xy·Rz(γ), p_b − d1·R_xy·ẑ)
  const CalibratedChain& c = comp.chain;
  const double cg = std::cos(c.base_gamma), sg = std::sin(c.base_gamma);
  Eigen::Matrix3d Rz;
  Rz << cg, -sg, 0, sg, cg, 0, 0, 0, 1;
  comp.world_T_base.R = c.base_R_xy * Rz;
  comp.world_T_base.p = c.base_p - robot.model.mdh[0].d * c.base_R_xy.col(2);
  comp.base_T_world = comp.world_T_base.inverse();
  comp.tcp_T_flange = comp.flange_T_tcp.inverse();
  return comp;
}

std::optional<Vector6d> nominal_solution(const Compensator& comp, const Pose<double>& base_T_tcp,
                                         const ArmConfig& config, const Vector6d& near) {
  const IkBranchResult r =
      nominal_ik_branch(comp.geometry, base_T_tcp * comp.flange_T_tcp.inverse(), config, near);
  if (r.status != IkStatus::Solved) return std::nullopt;
  return r.solution.joints;
}

Pose<double> nominal_tcp_pose(const Compensator& comp, const Vector6d& joints) {
  return flange_pose(comp.model, PointMass{}, comp.model.nominal(), joints) * comp.flange_T_tcp;
}

namespace {

template <typename Solver>
CalibratedIkResult newton(const Compensator& comp, const Pose<double>& world_T_tcp,
                          const Vector6d& seed, const ArmConfig* expected,
                          const CalibratedIkOptions& options) {
  Vector6d joints = seed;
  ChainState state;
  Matrix6d J;
  Solver solver;
  for (int it = 0;; ++it) {
    const PoseError err = pose_error(world_T_tcp, calibrated_tcp_pose(comp.chain, joints, state));
    if (within(err, options)) return finish(comp, seed, expected, joints, err, it);
    if (it == options.max_iterations)
      return failed(CalibratedIkStatus::NotConverged, joints, err, it);
    calibrated_jacobian(comp.chain, state, J);
    if (!solver.factor(J, state.tcp_p - state.frames[4].p))
      return failed(CalibratedIkStatus::Singular, joints, err, it);
    Vector6d step = solver.solve(err.e);
    double largest_step = step.cwiseAbs().maxCoeff();
    // The chain's curvature along the step, ½·(p̈, ω̇), is what a plain Newton step leaves as
    // the next error (~1e-2 mm from a seed ~2 mm off: in a third of the cases too much for one
    // more step to reach the tolerance); taken out of the right-hand side, the step is exact to
    // second order and the next error ~1e-4 mm, after which a plain step suffices.
    if (largest_step > kCurvatureMinStepRad && largest_step < kCurvatureMaxStepRad) {
      const Vector6d corrected =
          solver.solve(err.e - 0.5 * calibrated_jacobian_derivative(comp.chain, state, step, step));
      if ((corrected - step).cwiseAbs().maxCoeff() < largest_step) {
        step = corrected;
        largest_step = step.cwiseAbs().maxCoeff();
      }
    }
    if (!std::isfinite(largest_step)) return failed(CalibratedIkStatus::Singular, seed, err, it);
    if (largest_step > kMaxStepRad) step *= kMaxStepRad / largest_step;
    joints += step;
    if ((joints - seed).cwiseAbs().maxCoeff() > options.max_joint_change_rad)
      return failed(CalibratedIkStatus::LeftConfiguration, joints, err, it + 1);
  }
}

CalibratedIkResult newton(const Compensator& comp, const Pose<double>& world_T_tcp,
                          const Vector6d& seed, const ArmConfig* expected,
                          const CalibratedIkOptions& options) {
  return comp.spherical_wrist
             ? newton<WristPartitionedSolver>(comp, world_T_tcp, seed, expected, options)
             : newton<FullJacobianSolver>(comp, world_T_tcp, seed, expected, options);
}

CalibratedIkResult pose_shift(const Compensator& comp, const Pose<double>& world_T_tcp,
                              const ArmConfig& config, const Vector6d& seed,
                              const CalibratedIkOptions& options) {
  Vector6d joints = seed;
  // The command starts as the nominal pose of the seed (the base-frame image of the wanted).
  Pose<double> command = nominal_tcp_pose(comp, seed);
  ChainState state;
  for (int it = 0;; ++it) {
    const Pose<double> reached = calibrated_tcp_pose(comp.chain, joints, state);
    const PoseError err = pose_error(world_T_tcp, reached);
    if (within(err, options)) return finish(comp, seed, &config, joints, err, it);
    if (it == options.max_iterations)
      return failed(CalibratedIkStatus::NotConverged, joints, err, it);
    command = command * (reached.inverse() * world_T_tcp);
    const Seed next = seed_of(comp.seed_geometry, command * comp.tcp_T_flange, config, joints);
    if (next.status != CalibratedIkStatus::Converged)
      return failed(next.status, joints, err, it + 1);
    joints = next.joints;
    if ((joints - seed).cwiseAbs().maxCoeff() > options.max_joint_change_rad)
      return failed(CalibratedIkStatus::LeftConfiguration, joints, err, it + 1);
  }
}

}  // namespace

CalibratedIkResult calibrated_ik_newton(const Compensator& comp, const Pose<double>& world_T_tcp,
                                        const Vector6d& seed, const CalibratedIkOptions& options) {
  return newton(comp, world_T_tcp, seed, nullptr, options);
}

CalibratedIkResult calibrated_ik_pose_shift(const Compensator& comp,
                                            const Pose<double>& world_T_tcp,
                                            const ArmConfig& config, const Vector6d& seed,
                                            const CalibratedIkOptions& options) {
  CalibratedIkResult r = pose_shift(comp, world_T_tcp, config, seed, options);
  r.method = IkMethod::PoseShift;
  return r;
}

namespace {

/// calibrated_ik from the nominal solution `seed` of `config`; `near` picks the turn of the
/// last resort (a wide-range joint beyond its limit).
CalibratedIkResult iterate_from_seed(const Compensator& comp, const Pose<double>& world_T_tcp,
                                     const ArmConfig& config, const Vector6d& seed,
                                     const Vector6d& near, IkMethod method,
                                     const CalibratedIkOptions& options) {
  auto iterate = [&](const Vector6d& start) {
    if (method == IkMethod::Newton) {
      CalibratedIkResult r = newton(comp, world_T_tcp, start, &config, options);
      // Near a branch boundary (elbow close to stretch, the nominal seed midway between the
      // calibrated up and down answers) Newton may converge on the other branch; pose shift
      // solves each step on the branch asked for.
      if (r.status != CalibratedIkStatus::LeftConfiguration) return r;
    }
    return calibrated_ik_pose_shift(comp, world_T_tcp, config, start, options);
  };
  CalibratedIkResult r = iterate(seed);
  if (r.status != CalibratedIkStatus::OutsideLimits) return r;
  // A joint just beyond a limit may be inside one turn back (every joint of a UR spans ±360°):
  // the nominal seed was inside, but its calibrated answer crossed the limit. Iterated again
  // from there: with joint scales ≠ 1 a calibrated turn is not exactly 2π.
  Vector6d turned = r.joints;
  bool moved = false;
  for (int i = 0; i < kJointCount; ++i) {
    const JointLimit& limit = comp.model.limits[i];
    const double k = turned[i] > limit.upper ? -1.0 : turned[i] < limit.lower ? 1.0 : 0.0;
    const double candidate = turned[i] + k * 2.0 * std::numbers::pi;
    if (k != 0 && candidate >= limit.lower && candidate <= limit.upper) {
      turned[i] = candidate;
      moved = true;
    }
  }
  if (moved) {
    CalibratedIkResult other = iterate(turned);
    if (other.ok()) return other;
  }
  // Beyond a limit: another turn of a wide-range joint may be inside.
  const Pose<double> base_T_flange = comp.base_T_world * world_T_tcp * comp.tcp_T_flange;
  const Seed inside = seed_of(comp.geometry, base_T_flange, config, near);
  if (inside.status != CalibratedIkStatus::Converged || inside.joints == seed) return r;
  const CalibratedIkResult other = iterate(inside.joints);
  return other.ok() ? other : r;
}

}  // namespace

CalibratedIkResult calibrated_ik(const Compensator& comp, const Pose<double>& world_T_tcp,
                                 const ArmConfig& config, const Vector6d& near, IkMethod method,
                                 const CalibratedIkOptions& options) {
  const Pose<double> base_T_flange = comp.base_T_world * world_T_tcp * comp.tcp_T_flange;
  // The turn nearest `near` on the widened limits first: near a limit the calibrated answer
  // may lie inside while the nominal seed does not.
  Seed seed = seed_of(comp.seed_geometry, base_T_flange, config, near);
  // Near full stretch (or fold) of the elbow the calibrated arm may reach a little further
  // (or closer) than the nominal one: seed from the pose pulled in towards the shoulder (or
  // pushed out), by as little as will do (the joints move fast there); the iteration takes it
  // back.
  for (const double pull_mm : {1.0, 3.0, 10.0, -1.0, -3.0, -10.0}) {
    if (seed.status != CalibratedIkStatus::NoNominalSolution) break;
    Pose<double> moved = base_T_flange;
    const Eigen::Vector3d out = moved.p - Eigen::Vector3d(0, 0, comp.model.mdh[0].d);
    moved.p -= pull_mm * out.normalized();
    seed = seed_of(comp.seed_geometry, moved, config, near);
  }
  if (seed.status != CalibratedIkStatus::Converged) {
    CalibratedIkResult r;
    r.status = seed.status;
    return r;
  }
  return iterate_from_seed(comp, world_T_tcp, config, seed.joints, near, method, options);
}

CalibratedIkResult calibrated_ik_from_seed(const Compensator& comp, const Pose<double>& world_T_tcp,
                                           const ArmConfig& config, const Vector6d& seed,
                                           IkMethod method, const CalibratedIkOptions& options) {
  return iterate_from_seed(comp, world_T_tcp, config, seed, seed, method, options);
}

}  // namespace robcal
