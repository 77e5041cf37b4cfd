#include "robcal/kinematics/parallel_axes_ik.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fast_atan2.hpp"
#include "ik_sink.hpp"

namespace robcal {
namespace {

// P closer to axis 1 than |δ| by less than this (mm², on r² − δ²) still counts as reached.
constexpr double kShoulderReachMm2 = 1e-9;

/// Mask bits of every branch with the given shoulder, elbow and flip choices (bit 0: the
/// value false is allowed, bit 1: true), so that a solution standing for coinciding branches
/// answers to any of them.
unsigned branch_bits(unsigned backs, unsigned downs, unsigned flips) {
  unsigned bits = 0;
  for (int i = 0; i < 8; ++i)
    if ((backs >> ((i >> 2) & 1) & 1) && (downs >> ((i >> 1) & 1) & 1) && (flips >> (i & 1) & 1))
      bits |= 1u << i;
  return bits;
}

/// Lanes of the atan2 arguments of one solve (fast_atan2 over all of them in one vectorisable
/// pass): θ1, θ5, θ6 per shoulder b; θ3, atan2(v, u), the elbow's correction and θ2+θ3+θ4 per
/// slot 2·b + flip.
constexpr int kTheta1 = 0, kTheta5 = 2, kTheta6 = 4, kTheta3 = 6, kUv = 10, kElbow = 14,
              kTheta234 = 18, kLanes = 24;

/// The derivation of the header with its transcendental calls reduced to one fast_atan2 per
/// angle (cos θ1, sin θ1 by rotating P; cos θ6, sin θ6 from Rᵀn / |sin θ5|; the wrist flip
/// negates sin θ5, cos θ6, sin θ6, hence x4, z5, θ5 and turns θ6 and θ234 by π; the elbows are
/// the two signs of sin θ3), then the branches in the order shoulder, flip, elbow. Compiled
/// for AVX2 and SSE2 with its helpers inlined (ROBCAL_VECTOR_CLONES): the atan2 lanes and the
/// sink's turn arithmetic in vector code, 1.2 → 0.3 µs for all 8 branches.
ROBCAL_VECTOR_CLONES void solve(const ParallelAxesGeometry& g, const Pose<double>& T,
                                const Vector6d& seed, unsigned mask, IkSink& out) {
  const Eigen::Vector3d X = T.R.col(0), Y = T.R.col(1), Z = T.R.col(2);
  const Eigen::Vector3d P = T.p - g.d6 * Z;
  const double e = -g.s_alpha2 * g.delta;
  const double r_sq = P.x() * P.x() + P.y() * P.y();
  const double h_sq = r_sq - e * e;
  if (h_sq < -kShoulderReachMm2) return;
  const double h_abs = std::sqrt(std::max(h_sq, 0.0));
  const bool shoulder_singular = r_sq < kShoulderSingularMm * kShoulderSingularMm;
  const double inv_2a3a4 = 0.5 / (g.a3 * g.a4), a_sum_sq = g.a3 * g.a3 + g.a4 * g.a4;
  // The seed's θ1 and θ6, only at a singularity (rare).
  auto seed_angle = [&](int joint) { return link_angles_from_controller(g, seed)[joint]; };
  alignas(32) std::array<double, kLanes> y{}, x;
  x.fill(1.0);
  std::array<bool, 2> shoulder_used{}, wrist_singular{};
  std::array<bool, 4> reach{};  // per slot
  std::array<double, 2> c1{}, s1{};
  const double inv_he = shoulder_singular ? 0.0 : 1.0 / (h_sq > 0 ? r_sq : e * e);
  for (int b = 0; b < 2; ++b) {
    if (b == 1 && h_abs == 0.0) break;  // both shoulders coincide
    const double h = b == 0 ? h_abs : -h_abs;
    const unsigned backs = h_abs == 0.0 ? 3u : (b == 1 ? 2u : 1u);
    if ((mask & branch_bits(backs, 3u, 3u)) == 0) continue;
    shoulder_used[b] = true;
    // θ1 = atan2(P_y, P_x) − atan2(e, h): P rotated back by the angle of (h, e).
    if (shoulder_singular) {
      c1[b] = std::cos(seed_angle(0));
      s1[b] = std::sin(seed_angle(0));
    } else {
      c1[b] = (h * P.x() + e * P.y()) * inv_he;
      s1[b] = (h * P.y() - e * P.x()) * inv_he;
    }
    y[kTheta1 + b] = s1[b];
    x[kTheta1 + b] = c1[b];
    // n = −s_α2·y1 seen from the flange.
    const Eigen::Vector3d n(g.s_alpha2 * s1[b], -g.s_alpha2 * c1[b], 0.0);
    const Eigen::Vector3d nf = T.R.transpose() * n;
    const double s5_abs = std::sqrt(nf.x() * nf.x() + nf.y() * nf.y());
    const double c5 = -g.s_alpha5 * g.s_alpha6 * nf.z();
    wrist_singular[b] = s5_abs < kWristSingularSin;
    double c6, s6;
    if (wrist_singular[b]) {
      c6 = std::cos(seed_angle(5));
      s6 = std::sin(seed_angle(5));
    } else {
      const double inv_s5 = g.s_alpha5 / s5_abs;
      c6 = nf.x() * inv_s5;
      s6 = -nf.y() * inv_s5;
    }
    y[kTheta5 + b] = s5_abs;
    x[kTheta5 + b] = c5;
    y[kTheta6 + b] = s6;
    x[kTheta6 + b] = c6;
    // Frame 4's x axis and z5 without the flip; the flip negates both.
    const Eigen::Vector3d x4 = c5 * (c6 * X - s6 * Y) + (g.s_alpha6 * s5_abs) * Z;
    const Eigen::Vector3d z5 = g.s_alpha6 * (s6 * X + c6 * Y);
    const Eigen::Vector3d wrist_offset = g.d5 * z5 + g.a5 * x4;
    for (int flip = 0; flip < 2; ++flip) {
      if (flip == 1 && wrist_singular[b]) break;  // flip and no-flip coincide
      const unsigned flips = wrist_singular[b] ? 3u : (flip == 1 ? 2u : 1u);
      if ((mask & branch_bits(backs, 3u, flips)) == 0) continue;
      const double sign = flip == 0 ? 1.0 : -1.0;
      const int slot = 2 * b + flip;
      const Eigen::Vector3d O4 = P - sign * wrist_offset;
      // The planar arm in frame 2's plane.
      const double u = c1[b] * O4.x() + s1[b] * O4.y() - g.a2;
      const double v = g.s_alpha2 * (O4.z() - g.d1);
      y[kTheta234 + slot] = sign * g.s_alpha2 * x4.z();
      x[kTheta234 + slot] = sign * (c1[b] * x4.x() + s1[b] * x4.y());
      const double k = (u * u + v * v - a_sum_sq) * inv_2a3a4;
      reach[slot] = std::abs(k) <= 1.0 + kStretchedElbowCos;
      const double c3 = std::clamp(k, -1.0, 1.0);
      const double s3_abs = std::sqrt(1.0 - c3 * c3);
      y[kTheta3 + slot] = s3_abs;
      x[kTheta3 + slot] = c3;
      y[kUv + slot] = v;
      x[kUv + slot] = u;
      y[kElbow + slot] = g.a4 * s3_abs;
      x[kElbow + slot] = g.a3 + g.a4 * c3;
    }
  }
  alignas(32) std::array<double, kLanes> angle;
  for (int i = 0; i < kLanes; ++i) angle[i] = fast_atan2(y[i], x[i]);
  for (int b = 0; b < 2; ++b) {
    if (!shoulder_used[b]) continue;
    const bool back = b == 1;
    const unsigned backs = h_abs == 0.0 ? 3u : (back ? 2u : 1u);
    const double theta1 = angle[kTheta1 + b], theta5 = angle[kTheta5 + b];
    const double theta6 = angle[kTheta6 + b];
    for (int flip = 0; flip < 2; ++flip) {
      if (flip == 1 && wrist_singular[b]) break;
      const int slot = 2 * b + flip;
      if (!reach[slot]) continue;
      const unsigned flips = wrist_singular[b] ? 3u : (flip == 1 ? 2u : 1u);
      const double s3_abs = y[kTheta3 + slot];
      for (int elbow = 0; elbow < 2; ++elbow) {
        if (elbow == 1 && s3_abs == 0.0) break;  // stretched: both elbows coincide
        const double sign3 = elbow == 0 ? 1.0 : -1.0;
        // arm_config's side of the elbow, (W − S) × (E − S)·(−y1) = −s_α2·a3·a4·sin θ3.
        const double side = -g.s_alpha2 * g.a3 * g.a4 * sign3 * s3_abs;
        const bool down = (back ? -side : side) <= 0;
        const unsigned downs = s3_abs == 0.0 ? 3u : (down ? 2u : 1u);
        if ((mask & branch_bits(backs, downs, flips)) == 0) continue;
        const double theta3 = sign3 * angle[kTheta3 + slot];
        const double theta2 = angle[kUv + slot] - sign3 * angle[kElbow + slot];
        const double theta4 = angle[kTheta234 + slot] - theta2 - theta3;
        out.add({theta1, theta2, theta3, theta4, flip == 0 ? theta5 : -theta5,
                 flip == 0 ? theta6 : theta6 - std::copysign(std::numbers::pi, theta6)},
                ArmConfig{back, down, flip == 1}, wrist_singular[b], shoulder_singular);
      }
    }
  }
}

}  // namespace

std::optional<ParallelAxesGeometry> analyze_parallel_axes(const RobotModel& model,
                                                          std::string* why_not) {
  auto fail = [&](const char* reason) -> std::optional<ParallelAxesGeometry> {
    if (why_not) *why_not = reason;
    return std::nullopt;
  };
  const auto& m = model.mdh;
  auto zero_length = [](double v) { return std::abs(v) < kZeroLengthTolerance; };
  auto zero_angle = [](double v) { return std::abs(v) < kRightAngleTolerance; };
  if (!zero_angle(m[0].alpha) || !zero_length(m[0].a))
    return fail("link 1 must have alpha = a = 0");
  if (right_angle_sign(m[1].alpha) == 0) return fail("link 2 alpha must be ±90°");
  if (!zero_angle(m[2].alpha)) return fail("link 3 alpha must be 0 (axes 2 and 3 parallel)");
  if (zero_length(m[2].a)) return fail("link 3 a (upper arm) must not be 0");
  if (!zero_angle(m[3].alpha)) return fail("link 4 alpha must be 0 (axes 3 and 4 parallel)");
  if (zero_length(m[3].a)) return fail("link 4 a (forearm) must not be 0");
  if (right_angle_sign(m[4].alpha) == 0) return fail("link 5 alpha must be ±90°");
  if (right_angle_sign(m[5].alpha) == 0) return fail("link 6 alpha must be ±90°");
  if (!zero_length(m[5].a)) return fail("link 6 a must be 0 (axes 5 and 6 meet)");
  const auto joints = analyze_closed_form_joints(model, why_not);
  if (!joints) return std::nullopt;
  ParallelAxesGeometry g;
  static_cast<ClosedFormJoints&>(g) = *joints;
  g.d1 = m[0].d;
  g.a2 = m[1].a;
  g.a3 = m[2].a;
  g.a4 = m[3].a;
  g.a5 = m[4].a;
  g.d5 = m[4].d;
  g.d6 = m[5].d;
  g.delta = m[1].d + m[2].d + m[3].d;
  g.s_alpha2 = right_angle_sign(m[1].alpha);
  g.s_alpha5 = right_angle_sign(m[4].alpha);
  g.s_alpha6 = right_angle_sign(m[5].alpha);
  return g;
}

IkResult nominal_ik(const ParallelAxesGeometry& geometry, const Pose<double>& world_T_flange,
                    const Vector6d& seed, unsigned branch_mask) {
  IkResult result;
  IkSink sink(geometry, seed, result.solutions.data(), kMaxIkSolutions, false);
  solve(geometry, world_T_flange, seed, branch_mask, sink);
  sink.finish(result);
  return result;
}

IkBranchResult nominal_ik_branch(const ParallelAxesGeometry& geometry,
                                 const Pose<double>& world_T_flange, const ArmConfig& config,
                                 const Vector6d& seed) {
  IkBranchResult result;
  IkSink sink(geometry, seed, &result.solution, 1, true);
  solve(geometry, world_T_flange, seed, 1u << config.index(), sink);
  result.status = sink.status();
  return result;
}

}  // namespace robcal
