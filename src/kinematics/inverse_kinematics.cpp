#include "robcal/kinematics/inverse_kinematics.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <numbers>

#include "robcal/core/units.hpp"
#include "robcal/kinematics/fast_atan2.hpp"
#include "robcal/kinematics/numeric_ik.hpp"

namespace robcal {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kInvTwoPi = 0.5 / std::numbers::pi;
constexpr double kAngleTolerance = 1e-9;   // rad, for "α = ±90°" in a table written in degrees
constexpr double kLengthTolerance = 1e-9;  // mm, for "d = 0"
constexpr double kLimitTolerance = 1e-9;   // rad, as RobotModel::within_limits
constexpr double kReachTolerance = 1e-10;  // |cos| beyond 1 still taken as a stretched elbow
// Below this |sin θ5| θ6 is solved from the full residual rotation, which keeps the pose exact
// when θ4 is ill-conditioned (near the wrist singularity).
constexpr double kWristNearSingularSin = 1e-4;

/// ±1 when `alpha` is ±90° (within tolerance), 0 otherwise.
double right_angle_sign(double alpha) {
  if (std::abs(alpha - kPi / 2) < kAngleTolerance) return 1.0;
  if (std::abs(alpha + kPi / 2) < kAngleTolerance) return -1.0;
  return 0.0;
}

bool is_integer_matrix(const Matrix6d& m) {
  for (int i = 0; i < 36; ++i)
    if (std::abs(m.data()[i] - std::round(m.data()[i])) > 1e-12) return false;
  return true;
}

/// Rotation about x by ±90° applied to a vector: Rx(σ·90°)ᵀ·v = (v0, σ·v2, −σ·v1).
inline Eigen::Vector3d rx90_transpose_times(double sigma, const Eigen::Vector3d& v) {
  return {v[0], sigma * v[2], -sigma * v[1]};
}

/// One arm solution (θ1, θ2, θ3) with its cos/sin, before the wrist.
struct ArmSolution {
  double theta1, theta2, theta3;
  double c1, s1, c23, s23;
  bool back, down;
};

class Solver {
 public:
  Solver(const OrthoParallelGeometry& g, const Pose<double>& pose, const Vector6d& seed,
         IkResult& out)
      : g_(g), R_(pose.R), out_(out) {
    // Seed in link angles, for the singular cases.
    const Vector6d q_seed = g.map_identity ? seed : Vector6d(g.map_matrix * seed + g.map_offset);
    seed_theta1_ = q_seed[0] + g.theta_offset[0];
    seed_theta4_ = q_seed[3] + g.theta_offset[3];
    wrist_ = pose.p - g.d6 * pose.R.col(2);
  }

  void run() {
    const double wx = wrist_.x(), wy = wrist_.y();
    const double rxy = std::sqrt(wx * wx + wy * wy);
    double theta1, c1, s1;
    if (rxy < kShoulderSingularMm) {
      theta1 = seed_theta1_;
      c1 = std::cos(theta1);
      s1 = std::sin(theta1);
      shoulder_singular_ = true;
    } else {
      theta1 = fast_atan2(wy, wx);
      c1 = wx / rxy;
      s1 = wy / rxy;
    }
    arm_branches(theta1, c1, s1, rxy, false);
    arm_branches(theta1 + kPi, -c1, -s1, -rxy, true);
  }

 private:
  /// Both elbows for one θ1: W is at (r, 0, h) in frame 1.
  void arm_branches(double theta1, double c1, double s1, double r, bool back) {
    const double h = wrist_.z() - g_.d1;
    // W in frame 2's plane, relative to the shoulder: w = Rz(θ2)·v (see the header).
    const double wx = r - g_.a2, wy = g_.s_alpha2 * h;
    const double D = wx * wx + wy * wy;
    const double kappa = (D - g_.a3 * g_.a3 - g_.rho * g_.rho) / (2.0 * g_.a3 * g_.rho);
    if (std::abs(kappa) > 1.0 + kReachTolerance) return;
    const double k = std::clamp(kappa, -1.0, 1.0);
    const double sigma = std::sqrt(1.0 - k * k);
    // Wrist-side rotation Q = (Rz(θ1)·Rx(α2))ᵀ·R, shared by both elbows: rows of R rotated.
    Eigen::Matrix3d Q;
    Q.row(0) = c1 * R_.row(0) + s1 * R_.row(1);
    Q.row(1) = -s1 * R_.row(0) + c1 * R_.row(1);
    Q.row(2) = R_.row(2);
    Eigen::Matrix3d X;  // Rx(α2)ᵀ·Q
    X.row(0) = Q.row(0);
    X.row(1) = g_.s_alpha2 * Q.row(2);
    X.row(2) = -g_.s_alpha2 * Q.row(1);
    const double phi_abs = fast_atan2(sigma, k);
    for (int elbow = 0; elbow < 2; ++elbow) {
      if (elbow == 1 && sigma == 0.0) break;  // stretched: both elbows coincide
      const double sign = elbow == 0 ? 1.0 : -1.0;
      const double sphi = sign * sigma;  // φ = θ3 + ψ
      const double theta3 = sign * phi_abs - g_.psi;
      const double c3 = k * g_.cos_psi + sphi * g_.sin_psi;
      const double s3 = sphi * g_.cos_psi - k * g_.sin_psi;
      // v = (a3, 0) + ρ(cos φ, sin φ); θ2 turns v onto w.
      const double vx = g_.a3 + g_.rho * k, vy = g_.rho * sphi;
      const double dot = vx * wx + vy * wy, cross = vx * wy - vy * wx;
      const double theta2 = fast_atan2(cross, dot);
      const double c2 = D > 0 ? dot / D : 1.0, s2 = D > 0 ? cross / D : 0.0;
      ArmSolution arm{theta1, theta2, theta3, c1, s1, c2 * c3 - s2 * s3, s2 * c3 + c2 * s3,
                      back,   false};
      // Elbow up/down from the sign of the (x1, z1) cross product (header definition).
      arm.down = (back ? -1.0 : 1.0) * (-g_.s_alpha2 * g_.a3 * sphi) <= 0.0;
      wrist(arm, X);
    }
  }

  /// θ4, θ5, θ6 and the flipped wrist for one arm solution.
  void wrist(const ArmSolution& arm, const Eigen::Matrix3d& X) {
    // Y = Rz(θ23)ᵀ·X; M = Rx(α4)ᵀ·Y = Rz(θ4)·Rx(α5)·Rz(θ5)·Rx(α6)·Rz(θ6).
    const Eigen::RowVector3d y0 = arm.c23 * X.row(0) + arm.s23 * X.row(1);
    const Eigen::RowVector3d y1 = -arm.s23 * X.row(0) + arm.c23 * X.row(1);
    const double m02 = y0[2], m12 = g_.s_alpha4 * X(2, 2);
    const Eigen::RowVector3d m2 = -g_.s_alpha4 * y1;
    const double s5 = std::sqrt(m02 * m02 + m12 * m12);
    const double c5 = -g_.s_alpha5 * g_.s_alpha6 * m2[2];
    const double theta5 = fast_atan2(s5, c5);
    double theta4, theta6;
    const bool singular = s5 < kWristSingularSin;
    if (s5 >= kWristNearSingularSin) {
      theta4 = fast_atan2(g_.s_alpha6 * m12, g_.s_alpha6 * m02);
      theta6 = fast_atan2(-g_.s_alpha5 * m2[1], g_.s_alpha5 * m2[0]);
    } else {
      theta4 = singular ? seed_theta4_ : std::atan2(g_.s_alpha6 * m12, g_.s_alpha6 * m02);
      theta6 = residual_theta6(arm, X, theta4, theta5);
    }
    emit(arm, theta4, theta5, theta6, false, singular);
    ++out_.branches_reached;
    if (singular) return;  // the flip is the same pose with θ4 off the seed
    ++out_.branches_reached;
    emit(arm, theta4 > 0 ? theta4 - kPi : theta4 + kPi, -theta5,
         theta6 > 0 ? theta6 - kPi : theta6 + kPi, true, false);
  }

  /// θ6 from Rz(θ6) = (Rz(θ4)·Rx(α5)·Rz(θ5)·Rx(α6))ᵀ·M, exact for any θ4, θ5.
  double residual_theta6(const ArmSolution& arm, const Eigen::Matrix3d& X, double theta4,
                         double theta5) const {
    Eigen::Matrix3d Y;
    Y.row(0) = arm.c23 * X.row(0) + arm.s23 * X.row(1);
    Y.row(1) = -arm.s23 * X.row(0) + arm.c23 * X.row(1);
    Y.row(2) = X.row(2);
    Eigen::Matrix3d M;
    for (int c = 0; c < 3; ++c) M.col(c) = rx90_transpose_times(g_.s_alpha4, Y.col(c));
    const Eigen::Matrix3d W = (Eigen::AngleAxisd(theta4, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(g_.s_alpha5 * kPi / 2, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(theta5, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(g_.s_alpha6 * kPi / 2, Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    const Eigen::Matrix3d Rz6 = W.transpose() * M;
    return std::atan2(Rz6(1, 0), Rz6(0, 0));
  }

  /// Converts link angles to controller joints and emits every turn inside the limits.
  void emit(const ArmSolution& arm, double theta4, double theta5, double theta6, bool flip,
            bool singular) {
    const std::array<double, kJointCount> theta{arm.theta1, arm.theta2, arm.theta3,
                                                theta4,     theta5,     theta6};
    const Vector6d j = controller_from_link_angles(g_, theta);
    // Lowest equivalent value of each joint at or above its lower limit, and how many turns fit.
    std::array<double, kJointCount> first;
    std::array<int, kJointCount> turns;
    int total = 1;
    for (int i = 0; i < kJointCount; ++i) {
      const double lower = g_.limits[i].lower - kLimitTolerance;
      const double upper = g_.limits[i].upper + kLimitTolerance;
      double v = j[i];
      if (v < lower || v >= lower + kTwoPi) v -= kTwoPi * std::floor((v - lower) * kInvTwoPi);
      if (v > upper) return;
      first[i] = v;
      turns[i] = upper - v < kTwoPi ? 1 : 1 + static_cast<int>((upper - v) * kInvTwoPi);
      total *= turns[i];
    }
    std::array<int, kJointCount> k{};
    for (int n = 0; n < total; ++n) {
      if (out_.count == kMaxIkSolutions) {
        out_.status = IkStatus::Truncated;
        return;
      }
      IkSolution& s = out_.solutions[out_.count++];
      for (int i = 0; i < kJointCount; ++i) s.joints[i] = first[i] + kTwoPi * k[i];
      s.config = ArmConfig{arm.back, arm.down, flip};
      s.wrist_singular = singular;
      s.shoulder_singular = shoulder_singular_;
      for (int i = kJointCount - 1; i >= 0; --i) {  // odometer over the turns
        if (++k[i] < turns[i]) break;
        k[i] = 0;
      }
    }
  }

  const OrthoParallelGeometry& g_;
  const Eigen::Matrix3d& R_;
  IkResult& out_;
  Eigen::Vector3d wrist_;
  double seed_theta1_ = 0, seed_theta4_ = 0;
  bool shoulder_singular_ = false;
};

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
  for (int i = 0; i < kJointCount; ++i) g.theta_offset[i] = m[i].theta_offset;

  const Matrix6d& M = model.joint_map.matrix;
  if (!is_integer_matrix(M)) return fail("joint map matrix is not integer (signs and couplings)");
  Eigen::FullPivLU<Matrix6d> lu(M);
  if (!lu.isInvertible()) return fail("joint map matrix is singular");
  const Matrix6d inverse = lu.inverse();
  if (!is_integer_matrix(inverse)) return fail("joint map inverse is not integer");
  g.map_matrix = M;
  g.map_inverse = inverse.array().round().matrix();
  g.map_offset = model.joint_map.offset;
  g.map_identity = model.joint_map.is_identity();
  g.limits = model.limits;
  return g;
}

Vector6d controller_from_link_angles(const OrthoParallelGeometry& g,
                                     const std::array<double, kJointCount>& theta) {
  Vector6d q;
  for (int i = 0; i < kJointCount; ++i) q[i] = theta[i] - g.theta_offset[i];
  if (g.map_identity) return q;
  return g.map_inverse * (q - g.map_offset);
}

IkResult nominal_ik(const OrthoParallelGeometry& geometry, const Pose<double>& world_T_flange,
                    const Vector6d& seed) {
  IkResult result;
  result.status = IkStatus::Solved;
  Solver(geometry, world_T_flange, seed, result).run();
  if (result.status == IkStatus::Truncated) return result;
  if (result.branches_reached == 0)
    result.status = IkStatus::Unreachable;
  else if (result.count == 0)
    result.status = IkStatus::OutsideLimits;
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
  c.back = (W - frames[0].p).dot(x1) < 0;
  const double side = (W - S).cross(E - S).dot(-y1);
  c.down = (c.back ? -side : side) <= 0;
  c.flip = std::sin(model.joint_map.to_model(joints)[4] + model.mdh[4].theta_offset) < 0;
  return c;
}

AnyIkResult solve_ik(const RobotModel& model, const Pose<double>& world_T_flange,
                     const Vector6d& seed) {
  AnyIkResult out;
  std::string why_not;
  if (const auto geometry = analyze_ortho_parallel(model, &why_not)) {
    out.method = "closed form (ortho-parallel, spherical wrist)";
    const IkResult r = nominal_ik(*geometry, world_T_flange, seed);
    out.status = r.status;
    out.solutions.assign(r.begin(), r.end());
    return out;
  }
  out.method =
      fmt::format("numeric (damped least squares from the seed); not ortho-parallel: {}", why_not);
  const NumericIkResult r = numeric_ik(model, PointMass{}, model.nominal(), world_T_flange, seed);
  if (r.status != NumericIkStatus::Converged) {
    out.status = IkStatus::Unreachable;
    out.method += fmt::format("; {} after {} iterations, {:.3g} mm and {:.3g}° from the pose",
                              to_string(r.status), r.iterations, r.position_error_mm,
                              rad2deg(r.orientation_error_rad));
    return out;
  }
  if (!r.within_limits) {
    out.status = IkStatus::OutsideLimits;
    return out;
  }
  out.status = IkStatus::Solved;
  out.solutions.push_back({r.joints, arm_config(model, r.joints), false, false});
  return out;
}

}  // namespace robcal
