#include "robcal/kinematics/parallel_axes_ik.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ik_sink.hpp"

namespace robcal {
namespace {

constexpr double kReachTolerance = 1e-10;  // |cos θ3| beyond 1 still taken as a stretched elbow
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

/// The derivation of the header, branch by branch.
void solve(const ParallelAxesGeometry& g, const Pose<double>& T, const Vector6d& seed,
           unsigned mask, IkSink& out) {
  const std::array<double, kJointCount> seed_theta = link_angles_from_controller(g, seed);
  const Eigen::Vector3d X = T.R.col(0), Y = T.R.col(1), Z = T.R.col(2);
  const Eigen::Vector3d P = T.p - g.d6 * Z;
  const double e = -g.s_alpha2 * g.delta;
  const double r_sq = P.x() * P.x() + P.y() * P.y();
  const double h_sq = r_sq - e * e;
  if (h_sq < -kShoulderReachMm2) return;
  const double h_abs = std::sqrt(std::max(h_sq, 0.0));
  const bool shoulder_singular = r_sq < kShoulderSingularMm * kShoulderSingularMm;
  const double phi = std::atan2(P.y(), P.x());
  for (int shoulder = 0; shoulder < 2; ++shoulder) {
    if (shoulder == 1 && h_abs == 0.0) break;  // both shoulders coincide
    const double h = shoulder == 0 ? h_abs : -h_abs;
    const bool back = h < 0;
    const unsigned backs = h_abs == 0.0 ? 3u : (back ? 2u : 1u);
    if ((mask & branch_bits(backs, 3u, 3u)) == 0) continue;
    const double theta1 = shoulder_singular ? seed_theta[0] : phi - std::atan2(e, h);
    const double c1 = std::cos(theta1), s1 = std::sin(theta1);
    // n = −s_α2·y1 seen from the flange.
    const Eigen::Vector3d n(g.s_alpha2 * s1, -g.s_alpha2 * c1, 0.0);
    const Eigen::Vector3d nf = T.R.transpose() * n;
    const double s5_abs = std::hypot(nf.x(), nf.y());
    const double c5 = -g.s_alpha5 * g.s_alpha6 * nf.z();
    const bool wrist_singular = s5_abs < kWristSingularSin;
    for (int flip = 0; flip < 2; ++flip) {
      if (flip == 1 && wrist_singular) break;  // flip and no-flip coincide
      const double s5 = flip == 0 ? s5_abs : -s5_abs;
      const double theta5 = std::atan2(s5, c5);
      const double sign5 = flip == 0 ? 1.0 : -1.0;
      const double theta6 =
          wrist_singular ? seed_theta[5]
                         : std::atan2(-sign5 * g.s_alpha5 * nf.y(), sign5 * g.s_alpha5 * nf.x());
      const double c6 = std::cos(theta6), s6 = std::sin(theta6);
      const Eigen::Vector3d x4 = c5 * (c6 * X - s6 * Y) + (g.s_alpha6 * s5) * Z;
      const Eigen::Vector3d z5 = g.s_alpha6 * (s6 * X + c6 * Y);
      const Eigen::Vector3d O4 = P - g.d5 * z5 - g.a5 * x4;
      // The planar arm in frame 2's plane.
      const double u = c1 * O4.x() + s1 * O4.y() - g.a2;
      const double v = g.s_alpha2 * (O4.z() - g.d1);
      const double theta234 = std::atan2(g.s_alpha2 * x4.z(), c1 * x4.x() + s1 * x4.y());
      const double k = (u * u + v * v - g.a3 * g.a3 - g.a4 * g.a4) / (2.0 * g.a3 * g.a4);
      if (std::abs(k) > 1.0 + kReachTolerance) continue;
      const double c3 = std::clamp(k, -1.0, 1.0);
      const double s3_abs = std::sqrt(1.0 - c3 * c3);
      const unsigned flips = wrist_singular ? 3u : (s5 < 0 ? 2u : 1u);
      for (int elbow = 0; elbow < 2; ++elbow) {
        if (elbow == 1 && s3_abs == 0.0) break;  // stretched: both elbows coincide
        const double s3 = elbow == 0 ? s3_abs : -s3_abs;
        // arm_config's side of the elbow, (W − S) × (E − S)·(−y1) = −s_α2·a3·a4·sin θ3.
        const double side = -g.s_alpha2 * g.a3 * g.a4 * s3;
        const bool down = (back ? -side : side) <= 0;
        const unsigned downs = s3_abs == 0.0 ? 3u : (down ? 2u : 1u);
        if ((mask & branch_bits(backs, downs, flips)) == 0) continue;
        const double theta3 = std::atan2(s3, c3);
        const double theta2 = std::atan2(v, u) - std::atan2(g.a4 * s3, g.a3 + g.a4 * c3);
        const double theta4 = theta234 - theta2 - theta3;
        out.add({theta1, theta2, theta3, theta4, theta5, theta6}, ArmConfig{back, down, s5 < 0},
                wrist_singular, shoulder_singular);
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
