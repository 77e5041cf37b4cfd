#include "robcal/kinematics/inverse_kinematics.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "fast_atan2.hpp"
#include "robcal/core/units.hpp"

namespace robcal {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kInvTwoPi = 0.5 / std::numbers::pi;
constexpr double kAngleTolerance = kRightAngleTolerance;
constexpr double kLengthTolerance = kZeroLengthTolerance;
constexpr double kLimitTolerance = 1e-9;  // rad, as RobotModel::within_limits
// Below this |sin θ5| θ6 is solved from the full residual rotation, which keeps the pose exact
// when θ4 is ill-conditioned (near the wrist singularity).
constexpr double kWristNearSingularSin = 1e-4;

/// Rotation about x by ±90° applied to a vector: Rx(σ·90°)ᵀ·v = (v0, σ·v2, −σ·v1).
inline Eigen::Vector3d rx90_transpose_times(double sigma, const Eigen::Vector3d& v) {
  return {v[0], sigma * v[2], -sigma * v[1]};
}

/// What the emission and the wrist-singular case need of one arm (shoulder and elbow); its
/// angles live in the solver's lanes.
struct ArmSolution {
  double c23, s23, s5;
  int shoulder;  ///< 0 front, 1 back: which X of the solver
  bool back, down;
  unsigned labels;  ///< mask bits of the branches this arm stands for (both elbows if stretched)
};

/// Where a solve puts its solutions: every turn of every branch into an array, or, per branch,
/// only the turn nearest the seed.
struct SolutionSink {
  IkSolution* solutions;
  int capacity;
  bool nearest_turn_only;
  int count = 0;
  int branches_reached = 0;
  bool truncated = false;
};

/// Up to four arms (shoulder × elbow) are solved side by side in slots 0..3: the atan2
/// arguments of a solve are laid out for vector lanes (2 or 4 doubles), θ1 and the two
/// shoulders' φ first, then each kind of angle with one lane per arm slot.
constexpr int kArms = 4;
constexpr int kColumns = 2 * kArms;           // each arm and its wrist flip
constexpr int kTheta1Lane = 0, kPhiLane = 1;  // φ of the front and back shoulder
constexpr int kTheta2Lanes = 4, kTheta4Lanes = 8, kTheta5Lanes = 12, kTheta6Lanes = 16;
constexpr int kLaneCount = 20;

/// Candidate solutions in link angles before the joint limits, one column each: arm slot a
/// in column a, its wrist flip in column kArms + a.
using Columns = std::array<std::array<double, kColumns>, kJointCount>;

/// Solves in stages, each over all arms at once so that the compiler can use vector lanes:
/// the arms' atan2 arguments → every atan2 → the candidates' columns → the joint turns within
/// the limits → the solutions written out. Only the branches whose bit
/// (1 << ArmConfig::index()) is set in `mask` are solved.
class Solver {
 public:
  Solver(const OrthoParallelGeometry& g, const Pose<double>& pose, const Vector6d& seed,
         unsigned mask, SolutionSink& out)
      : g_(g), R_(pose.R), seed_(seed), mask_(mask), out_(out) {
    // Seed in link angles, for the singular cases.
    const Vector6d q_seed = g.map_identity ? seed : Vector6d(g.map_matrix * seed + g.map_offset);
    seed_theta1_ = q_seed[0] + g.theta_offset[0];
    seed_theta4_ = q_seed[3] + g.theta_offset[3];
    wrist_ = pose.p - g.d6 * pose.R.col(2);
    // Derived here rather than stored in the geometry, so that a caller who edits its public
    // limits (or lengths) gets them applied.
    elbow_sum_sq_ = g.a3 * g.a3 + g.rho * g.rho;
    elbow_inv_product_ = 1.0 / (2.0 * g.a3 * g.rho);
    for (int i = 0; i < kJointCount; ++i) {
      lower_[i] = g.limits[i].lower - kLimitTolerance;
      upper_[i] = g.limits[i].upper + kLimitTolerance;
      const double span = upper_[i] - lower_[i];
      if (span < kTwoPi) continue;
      wide_joints_[wide_count_++] = i;
      wide_max_turns_ = std::max(wide_max_turns_, 1 + static_cast<int>(span / kTwoPi));
    }
  }

  ROBCAL_VECTOR_CLONES void run() {
    // θ1: W lies in the x1–z1 plane.
    const double wx = wrist_.x(), wy = wrist_.y();
    const double rxy = std::sqrt(wx * wx + wy * wy);
    double c1, s1;
    // Unused lanes are atan2(0, 1): (0, 0) takes the 0/0 path of fast_atan2, whose discarded
    // NaN division measured slower.
    alignas(32) std::array<double, kLaneCount> y{}, x;
    x.fill(1.0);
    y[kTheta1Lane] = wy;
    x[kTheta1Lane] = wx;
    if (rxy < kShoulderSingularMm) {
      c1 = std::cos(seed_theta1_);
      s1 = std::sin(seed_theta1_);
      shoulder_singular_ = true;
    } else {
      const double inv = 1.0 / rxy;  // one division: the divider is the IK's bottleneck
      c1 = wx * inv;
      s1 = wy * inv;
    }
    // Planar arm for front (r = +|W_xy|) and back (r = −|W_xy|): W at (r, 0, h) in frame 1,
    // w = W − shoulder in frame 2's plane, w = Rz(θ2)·v (see the header).
    const double h = wrist_.z() - g_.d1;
    std::array<double, 2> w_x, w_y, D, D_inv, kappa, sigma;
    std::array<bool, 2> reach;
    for (int b = 0; b < 2; ++b) {
      const double r = b == 0 ? rxy : -rxy;
      w_x[b] = r - g_.a2;
      w_y[b] = g_.s_alpha2 * h;
      D[b] = w_x[b] * w_x[b] + w_y[b] * w_y[b];
      D_inv[b] = 1.0 / D[b];
      const double k = (D[b] - elbow_sum_sq_) * elbow_inv_product_;
      reach[b] = std::abs(k) <= 1.0 + kStretchedElbowCos && (mask_ & shoulder_mask(b)) != 0;
      kappa[b] = std::clamp(k, -1.0, 1.0);
      sigma[b] = std::sqrt(1.0 - kappa[b] * kappa[b]);
      y[kPhiLane + b] = sigma[b];
      x[kPhiLane + b] = kappa[b];
    }
    // Wrist-side rotations X_b = Rx(α2)ᵀ·Rz(θ1_b)ᵀ·R (rows of R rotated), one per shoulder.
    for (int b = 0; b < 2; ++b) {
      const double c = b == 0 ? c1 : -c1, s = b == 0 ? s1 : -s1;
      X_[b].row(0) = c * R_.row(0) + s * R_.row(1);
      X_[b].row(1) = g_.s_alpha2 * R_.row(2);
      X_[b].row(2) = -g_.s_alpha2 * (-s * R_.row(0) + c * R_.row(1));
    }
    // Elbows: φ = θ3 + ψ = ±φ_b; v = (a3, 0) + ρ(cos φ, sin φ); θ2 turns v onto w (c2, s2 by
    // division, θ2 by atan2 with the others).
    std::array<ArmSolution, kArms> arms;
    alignas(32) std::array<double, kArms> back{}, elbow_sign{};  // per slot, 0 when unused
    int n = 0;
    for (int b = 0; b < 2; ++b) {
      if (!reach[b]) continue;
      const bool stretched = sigma[b] == 0.0;  // both elbows coincide
      for (int elbow = 0; elbow < 2; ++elbow) {
        if (elbow == 1 && stretched) break;
        const double sign = elbow == 0 ? 1.0 : -1.0;
        const double sphi = sign * sigma[b];
        // Elbow up/down from the sign of the (x1, z1) cross product (header definition).
        const bool down = (b == 1 ? -1.0 : 1.0) * (-g_.s_alpha2 * g_.a3 * sphi) <= 0.0;
        // A stretched elbow stands for both labels.
        const unsigned labels = stretched ? shoulder_mask(b) : elbow_mask(b, down);
        if ((mask_ & labels) == 0) continue;
        const double c3 = kappa[b] * g_.cos_psi + sphi * g_.sin_psi;
        const double s3 = sphi * g_.cos_psi - kappa[b] * g_.sin_psi;
        const double vx = g_.a3 + g_.rho * kappa[b], vy = g_.rho * sphi;
        const double dot = vx * w_x[b] + vy * w_y[b];
        const double cross = vx * w_y[b] - vy * w_x[b];
        const double c2 = D[b] > 0 ? dot * D_inv[b] : 1.0;
        const double s2 = D[b] > 0 ? cross * D_inv[b] : 0.0;
        ArmSolution& arm = arms[n];
        arm.c23 = c2 * c3 - s2 * s3;
        arm.s23 = s2 * c3 + c2 * s3;
        arm.shoulder = b;
        arm.back = b == 1;
        arm.down = down;
        arm.labels = labels;
        back[n] = b;
        elbow_sign[n] = sign;
        // Wrist: Y = Rz(θ23)ᵀ·X, M = Rx(α4)ᵀ·Y = Rz(θ4)·Rx(α5)·Rz(θ5)·Rx(α6)·Rz(θ6), whose
        // third column is σ6·s5·(c4, s4, ·) and third row σ5·s5·(c6, −s6, ·),
        // c5 = −σ5σ6·M22.
        const Eigen::Matrix3d& X = X_[b];
        const double m02 = arm.c23 * X(0, 2) + arm.s23 * X(1, 2);
        const double m12 = g_.s_alpha4 * X(2, 2);
        const double m20 = g_.s_alpha4 * (arm.s23 * X(0, 0) - arm.c23 * X(1, 0));
        const double m21 = g_.s_alpha4 * (arm.s23 * X(0, 1) - arm.c23 * X(1, 1));
        const double m22 = g_.s_alpha4 * (arm.s23 * X(0, 2) - arm.c23 * X(1, 2));
        arm.s5 = std::sqrt(m02 * m02 + m12 * m12);
        y[kTheta2Lanes + n] = cross;
        x[kTheta2Lanes + n] = dot;
        y[kTheta4Lanes + n] = g_.s_alpha6 * m12;
        x[kTheta4Lanes + n] = g_.s_alpha6 * m02;
        y[kTheta5Lanes + n] = arm.s5;
        x[kTheta5Lanes + n] = -g_.s_alpha5 * g_.s_alpha6 * m22;
        y[kTheta6Lanes + n] = -g_.s_alpha5 * m21;
        x[kTheta6Lanes + n] = g_.s_alpha5 * m20;
        ++n;
      }
    }
    // Every angle of every arm in one pass over the lanes.
    alignas(32) std::array<double, kLaneCount> angle;
    for (int i = 0; i < kLaneCount; ++i) angle[i] = fast_atan2(y[i], x[i]);
    // Near the wrist singularity θ4 comes from the seed and θ6 from the residual rotation (rare:
    // the only per-arm branch).
    for (int a = 0; a < n; ++a) {
      if (arms[a].s5 >= kWristNearSingularSin) continue;
      double& theta4 = angle[kTheta4Lanes + a];
      if (arms[a].s5 < kWristSingularSin) theta4 = seed_theta4_;
      angle[kTheta6Lanes + a] = residual_theta6(arms[a], theta4, angle[kTheta5Lanes + a]);
    }
    // The candidates: each arm and its wrist flip (θ4 + π, −θ5, θ6 + π), in every slot.
    const double theta1 = shoulder_singular_ ? seed_theta1_ : angle[kTheta1Lane];
    const double phi_front = angle[kPhiLane], phi_back = angle[kPhiLane + 1];
    alignas(32) Columns q;
    for (int a = 0; a < kArms; ++a) {
      const double theta4 = angle[kTheta4Lanes + a], theta6 = angle[kTheta6Lanes + a];
      q[0][a] = q[0][kArms + a] = back[a] != 0 ? theta1 + std::numbers::pi : theta1;
      q[1][a] = q[1][kArms + a] = angle[kTheta2Lanes + a];
      q[2][a] = q[2][kArms + a] = elbow_sign[a] * (back[a] != 0 ? phi_back : phi_front) - g_.psi;
      q[3][a] = theta4;
      q[3][kArms + a] = theta4 - std::copysign(std::numbers::pi, theta4);
      q[4][a] = angle[kTheta5Lanes + a];
      q[4][kArms + a] = -angle[kTheta5Lanes + a];
      q[5][a] = theta6;
      q[5][kArms + a] = theta6 - std::copysign(std::numbers::pi, theta6);
    }
    emit(arms, n, q);
  }

 private:
  /// Mask bits of the branches with shoulder `b` (0 front, 1 back), and also elbow `down`.
  static unsigned shoulder_mask(int b) { return b == 0 ? 0x0Fu : 0xF0u; }
  static unsigned elbow_mask(int b, bool down) { return 3u << (4 * b + (down ? 2 : 0)); }

  /// θ6 from Rz(θ6) = (Rz(θ4)·Rx(α5)·Rz(θ5)·Rx(α6))ᵀ·M, exact for any θ4, θ5.
  double residual_theta6(const ArmSolution& arm, double theta4, double theta5) const {
    const Eigen::Matrix3d& X = X_[arm.shoulder];
    Eigen::Matrix3d Y;
    Y.row(0) = arm.c23 * X.row(0) + arm.s23 * X.row(1);
    Y.row(1) = -arm.s23 * X.row(0) + arm.c23 * X.row(1);
    Y.row(2) = X.row(2);
    Eigen::Matrix3d M;
    for (int c = 0; c < 3; ++c) M.col(c) = rx90_transpose_times(g_.s_alpha4, Y.col(c));
    const Eigen::Matrix3d W =
        (Eigen::AngleAxisd(theta4, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(g_.s_alpha5 * std::numbers::pi / 2, Eigen::Vector3d::UnitX()) *
         Eigen::AngleAxisd(theta5, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(g_.s_alpha6 * std::numbers::pi / 2, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    const Eigen::Matrix3d Rz6 = W.transpose() * M;
    return std::atan2(Rz6(1, 0), Rz6(0, 0));
  }

  /// Converts the candidates to controller joints and emits every turn inside the limits (or
  /// the turn nearest the seed). Joint by joint over all 8 columns (unused ones hold finite
  /// values), without branches, up to the limit test.
  void emit(const std::array<ArmSolution, kArms>& arms, int n, Columns& q) {
    if (!g_.map_identity)
      for (int m = 0; m < kColumns; ++m) {
        Vector6d v;
        for (int i = 0; i < kJointCount; ++i) v[i] = q[i][m] - g_.theta_offset[i];
        v = g_.map_inverse * (v - g_.map_offset);
        for (int i = 0; i < kJointCount; ++i) q[i][m] = v[i] + g_.theta_offset[i];
      }
    // Each joint moved by whole turns to the lowest value at or above its lower limit.
    alignas(32) std::array<double, kColumns> outside{};  // 1 where a joint is above its limit
    for (int i = 0; i < kJointCount; ++i) {
      const double offset = g_.theta_offset[i], lower = lower_[i], upper = upper_[i];
      for (int m = 0; m < kColumns; ++m) {
        const double v = q[i][m] - offset;
        const double w = v - kTwoPi * turns_below(v - lower);
        outside[m] = w <= upper ? outside[m] : 1.0;  // NaN is outside
        q[i][m] = w;
      }
    }
    // One wide joint (the usual case): every candidate written with all the turns the joint can
    // have, and counted with those it has, without branching on the pose.
    const bool one_wide = wide_count_ == 1 && !out_.nearest_turn_only &&
                          out_.count + kColumns * wide_max_turns_ <= out_.capacity;
    alignas(32) std::array<double, kColumns> turns{};  // solutions per candidate, if one_wide
    if (one_wide) {
      const int i = wide_joints_[0];
      for (int m = 0; m < kColumns; ++m)
        turns[m] = outside[m] == 0 ? 1 + turns_below(upper_[i] - q[i][m]) : 0.0;
    }
    // Bit 0 of a branch index is the flip. At the wrist singularity the flip is the same pose
    // with θ4 off the seed: one solution stands for both.
    constexpr unsigned kNoFlipBits = 0x55u, kFlipBits = 0xAAu;
    for (int m = 0; m < 2 * n; ++m) {  // each arm, then its flip
      const int a = m / 2, column = a + (m % 2) * kArms;
      const ArmSolution& arm = arms[a];
      const bool flip = m % 2 == 1, singular = arm.s5 < kWristSingularSin;
      if (!(mask_ & arm.labels & (flip ? kFlipBits : singular ? ~0u : kNoFlipBits))) continue;
      if (flip && singular) continue;
      ++out_.branches_reached;
      if (out_.count == out_.capacity) {
        out_.truncated = true;
        return;
      }
      IkSolution& s = out_.solutions[out_.count];
      Vector6d joints;
      for (int i = 0; i < kJointCount; ++i) joints[i] = q[i][column];
      const ArmConfig config{arm.back, arm.down, flip};
      s = {joints, config, singular && !flip, shoulder_singular_};
      if (one_wide) {
        // Stores only: reading back `s` or a vector just changed in one place would be a wide
        // load of a narrow store, which stalls.
        const int i = wide_joints_[0];
        for (int k = 1; k < wide_max_turns_; ++k) {
          IkSolution& copy = out_.solutions[out_.count + k];
          copy = {joints, config, singular && !flip, shoulder_singular_};
          copy.joints[i] = q[i][column] + kTwoPi * k;
        }
        out_.count += static_cast<int>(turns[column]);
        continue;
      }
      if (outside[column] != 0) continue;
      ++out_.count;
      if (out_.nearest_turn_only)
        nearest_turn(s);
      else if (!add_turns(s))
        return;
    }
  }

  /// Moves each wide joint of `s` to its turn nearest the seed (joints are independent).
  void nearest_turn(IkSolution& s) const {
    for (int w = 0; w < wide_count_; ++w) {
      const int i = wide_joints_[w];
      const double top = turns_below(upper_[i] - s.joints[i]);
      const double k = std::round((seed_[i] - s.joints[i]) * kInvTwoPi);
      s.joints[i] += kTwoPi * std::clamp(k, 0.0, top);
    }
  }

  /// Appends every further turn of the wide joints of `s`, the last solution emitted: the
  /// solutions so far copied once per turn. False when the capacity ran out.
  bool add_turns(const IkSolution& s) {
    const int first = out_.count - 1;
    for (int w = 0; w < wide_count_; ++w) {
      const int i = wide_joints_[w];
      const int turns = 1 + static_cast<int>(turns_below(upper_[i] - s.joints[i]));
      const int block = out_.count - first;
      for (int k = 1; k < turns; ++k)
        for (int m = 0; m < block; ++m) {
          if (out_.count == out_.capacity) {
            out_.truncated = true;
            return false;
          }
          IkSolution& copy = out_.solutions[out_.count++];
          copy = out_.solutions[first + m];
          copy.joints[i] += kTwoPi * k;
        }
    }
    return true;
  }

  /// floor(x / 2π), branch-free and defined for every input: adding and subtracting 1.5·2⁵²
  /// rounds t = x / 2π to the nearest integer r (|t| < 2⁵¹); one less when r > t, i.e. when
  /// t − r < 0 (t = r gives +0). NaN and ±∞ give NaN, which the limit test rejects.
  static double turns_below(double x) {
    constexpr double kRound = 6755399441055744.0;  // 1.5·2⁵²
    const double t = x * kInvTwoPi;
    const double r = (t + kRound) - kRound;
    return r - (0.5 - std::copysign(0.5, t - r));
  }

  const OrthoParallelGeometry& g_;
  const Eigen::Matrix3d& R_;
  const Vector6d& seed_;
  unsigned mask_;
  SolutionSink& out_;
  std::array<Eigen::Matrix3d, 2> X_;
  Eigen::Vector3d wrist_;
  double seed_theta1_ = 0, seed_theta4_ = 0;
  bool shoulder_singular_ = false;
  double elbow_sum_sq_ = 0, elbow_inv_product_ = 0;  ///< a3² + ρ², 1 / (2·a3·ρ)
  /// The limits widened by the tolerance (as within_limits), and the joints whose range
  /// exceeds one turn (they get every equivalent turn), with the most turns any of them has.
  std::array<double, kJointCount> lower_, upper_;
  std::array<int, kJointCount> wide_joints_;
  int wide_count_ = 0, wide_max_turns_ = 1;
};

IkStatus status_of(const SolutionSink& sink) {
  if (sink.truncated) return IkStatus::Truncated;
  if (sink.branches_reached == 0) return IkStatus::Unreachable;
  if (sink.count == 0) return IkStatus::OutsideLimits;
  return IkStatus::Solved;
}

}  // namespace

std::string ArmConfig::label() const {
  return fmt::format("{}-{}-{}", back ? "back" : "front", down ? "down" : "up",
                     flip ? "flip" : "noflip");
}

std::optional<ArmConfig> parse_arm_config(const std::string& label) {
  for (int i = 0; i < 8; ++i) {
    const ArmConfig c{(i & 4) != 0, (i & 2) != 0, (i & 1) != 0};
    if (c.label() == label) return c;
  }
  return std::nullopt;
}

const char* to_string(IkStatus status) {
  switch (status) {
    case IkStatus::Solved:
      return "solved";
    case IkStatus::Unreachable:
      return "unreachable";
    case IkStatus::OutsideLimits:
      return "outside joint limits";
    case IkStatus::Truncated:
      return "truncated";
  }
  return "unknown";
}

std::optional<OrthoParallelGeometry> analyze_ortho_parallel(const RobotModel& model,
                                                            std::string* why_not) {
  auto fail = [&](const std::string& reason) -> std::optional<OrthoParallelGeometry> {
    if (why_not) *why_not = reason;
    return std::nullopt;
  };
  const auto& m = model.mdh;
  auto zero_length = [](double v) { return std::abs(v) < kLengthTolerance; };
  auto zero_angle = [](double v) { return std::abs(v) < kAngleTolerance; };
  if (!zero_angle(m[0].alpha) || !zero_length(m[0].a))
    return fail("link 1 must have alpha = a = 0");
  if (right_angle_sign(m[1].alpha) == 0) return fail("link 2 alpha must be ±90°");
  if (!zero_length(m[1].d)) return fail("link 2 d must be 0 (no shoulder offset)");
  if (!zero_angle(m[2].alpha)) return fail("link 3 alpha must be 0 (axes 2 and 3 parallel)");
  if (!zero_length(m[2].d)) return fail("link 3 d must be 0");
  if (zero_length(m[2].a)) return fail("link 3 a (upper arm) must not be 0");
  if (right_angle_sign(m[3].alpha) == 0) return fail("link 4 alpha must be ±90°");
  if (right_angle_sign(m[4].alpha) == 0) return fail("link 5 alpha must be ±90°");
  if (!zero_length(m[4].a) || !zero_length(m[4].d))
    return fail("link 5 a and d must be 0 (spherical wrist)");
  if (right_angle_sign(m[5].alpha) == 0) return fail("link 6 alpha must be ±90°");
  if (!zero_length(m[5].a)) return fail("link 6 a must be 0 (spherical wrist)");

  OrthoParallelGeometry g;
  g.d1 = m[0].d;
  g.a2 = m[1].a;
  g.a3 = m[2].a;
  g.a4 = m[3].a;
  g.d4 = m[3].d;
  g.d6 = m[5].d;
  g.s_alpha2 = right_angle_sign(m[1].alpha);
  g.s_alpha4 = right_angle_sign(m[3].alpha);
  g.s_alpha5 = right_angle_sign(m[4].alpha);
  g.s_alpha6 = right_angle_sign(m[5].alpha);
  // Forearm vector (a4, −s_α4·d4) in frame 3: the wrist centre seen from axis 3.
  g.rho = std::hypot(g.a4, g.d4);
  if (g.rho < kLengthTolerance) return fail("link 4 a and d are both 0 (no forearm)");
  g.psi = std::atan2(-g.s_alpha4 * g.d4, g.a4);
  g.cos_psi = std::cos(g.psi);
  g.sin_psi = std::sin(g.psi);
  const auto joints = analyze_closed_form_joints(model, why_not);
  if (!joints) return std::nullopt;
  static_cast<ClosedFormJoints&>(g) = *joints;
  return g;
}

IkResult nominal_ik(const OrthoParallelGeometry& geometry, const Pose<double>& world_T_flange,
                    const Vector6d& seed, unsigned branch_mask) {
  IkResult result;
  SolutionSink sink{result.solutions.data(), kMaxIkSolutions, false};
  Solver(geometry, world_T_flange, seed, branch_mask, sink).run();
  result.count = sink.count;
  result.branches_reached = sink.branches_reached;
  result.status = status_of(sink);
  return result;
}

IkBranchResult nominal_ik_branch(const OrthoParallelGeometry& geometry,
                                 const Pose<double>& world_T_flange, const ArmConfig& config,
                                 const Vector6d& seed) {
  IkBranchResult result;
  SolutionSink sink{&result.solution, 1, true};
  Solver(geometry, world_T_flange, seed, 1u << config.index(), sink).run();
  result.status = status_of(sink);
  return result;
}

const IkSolution* nearest_solution(const IkResult& result, const Vector6d& joints) {
  const IkSolution* best = nullptr;
  double best_distance = 0;
  for (const IkSolution& s : result) {
    const double distance = (s.joints - joints).cwiseAbs().maxCoeff();
    if (!best || distance < best_distance) {
      best = &s;
      best_distance = distance;
    }
  }
  return best;
}

ArmConfig arm_config(const RobotModel& model, const Vector6d& joints) {
  const auto frames = link_frames(model, PointMass{}, model.nominal().data(), joints.data());
  const Eigen::Vector3d x1 = frames[0].R.col(0), y1 = frames[0].R.col(1);
  const Eigen::Vector3d S = frames[1].p, E = frames[2].p, W = frames[3].p;
  ArmConfig c{};
  c.back = (frames[4].p - frames[0].p).dot(x1) < 0;
  const double side = (W - S).cross(E - S).dot(-y1);
  c.down = (c.back ? -side : side) <= 0;
  c.flip = std::sin(model.joint_map.to_model(joints)[4] + model.mdh[4].theta_offset) < 0;
  return c;
}

}  // namespace robcal
