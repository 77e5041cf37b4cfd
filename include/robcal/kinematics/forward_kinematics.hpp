#pragma once
/// \file
/// Forward kinematics of the error model (docs/method/02-frames.md §3–§6, 03-error-model.md §3–§8),
/// templated on the scalar type so that `ceres::Jet` gives exact derivatives with respect to joints
/// and parameters.
///
/// Frame naming: `world_T_flange` maps flange coordinates to world coordinates. Joint values
/// passed in are the controller's (rad); the model's joint map turns them into model angles.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>

#include "robcal/model/parameters.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

template <typename T>
using Vector3 = Eigen::Matrix<T, 3, 1>;
template <typename T>
using Matrix3 = Eigen::Matrix<T, 3, 3>;

/// A rigid transform as rotation + translation (mm), cheaper than a 4×4 and Jet-friendly.
template <typename T>
struct Pose {
  Matrix3<T> R = Matrix3<T>::Identity();
  Vector3<T> p = Vector3<T>::Zero();

  [[nodiscard]] Vector3<T> operator*(const Vector3<T>& x) const { return R * x + p; }
  [[nodiscard]] Pose operator*(const Pose& other) const { return {R * other.R, R * other.p + p}; }
  [[nodiscard]] Pose inverse() const {
    Pose out;
    out.R = R.transpose();
    out.p = -(out.R * p);
    return out;
  }
};

namespace detail {

/// Rot_x(alpha) · Trans_x(a) · Rot_z(theta) · Trans_z(d), closed form (Craig eq. 3.6).
template <typename T>
Pose<T> mdh_transform(const T& alpha, const T& a, const T& theta, const T& d) {
  using std::cos;
  using std::sin;
  const T ca = cos(alpha), sa = sin(alpha), ct = cos(theta), st = sin(theta);
  Pose<T> A;
  A.R << ct, -st, T(0), st * ca, ct * ca, -sa, st * sa, ct * sa, ca;
  A.p << a, -sa * d, ca * d;
  return A;
}

/// world_A_1 = Trans(x, y, d1 + z) · Rot_x(alpha) · Rot_y(beta) · Rot_z(gamma + θ1)
/// (docs/method/02-frames.md §4).
template <typename T>
Pose<T> base_transform(const T* params, const T& d1, const T& theta1) {
  using std::cos;
  using std::sin;
  const T ca = cos(params[3]), sa = sin(params[3]);
  const T cb = cos(params[4]), sb = sin(params[4]);
  const T g = params[5] + theta1;
  const T cg = cos(g), sg = sin(g);
  Matrix3<T> Rxy;
  Rxy << cb, T(0), sb, sa * sb, ca, -sa * cb, -ca * sb, sa, ca * cb;
  Matrix3<T> Rz;
  Rz << cg, -sg, T(0), sg, cg, T(0), T(0), T(0), T(1);
  Pose<T> A;
  A.R = Rxy * Rz;
  A.p << params[0], params[1], d1 + params[2];
  return A;
}

/// True when x is non-zero or, for a ceres::Jet, carries a derivative: a compliance of zero
/// must still be differentiated.
template <typename T>
bool is_nonzero(const T& x) {
  if constexpr (requires { x.v; })
    return x.a != 0.0 || !x.v.isZero(0.0);
  else
    return x != T(0);
}

}  // namespace detail

/// Model joint angles (rad) from controller joint values (rad), through the robot's joint map.
template <typename T>
std::array<T, kJointCount> model_joint_angles(const RobotModel& model, const T* controller) {
  std::array<T, kJointCount> q;
  if (model.joint_map.is_identity()) {
    for (int i = 0; i < kJointCount; ++i) q[i] = controller[i];
    return q;
  }
  for (int i = 0; i < kJointCount; ++i) {
    q[i] = T(model.joint_map.offset[i]);
    for (int j = 0; j < kJointCount; ++j)
      if (model.joint_map.matrix(i, j) != 0.0) q[i] += model.joint_map.matrix(i, j) * controller[j];
  }
  return q;
}

/// Static gravity torques τ_1..τ_6 (N·mm) about joint axes 1..6 for undeflected joint angles
/// `theta` (rad, θ_i of links 1..6 before compliance), docs/method/03-error-model.md §3: τ_i =
/// (Σ_{j≥i} m_j u_j^i × g_i)_z. Computed tip to base with the first moment S_i = Σ_{j≥i} m_j u_j^i,
/// so it is O(n). `payload` (flange frame) is lumped with link 6. τ_1 is zero on a floor-mounted
/// robot (gravity along axis 1) and loads joint 1 on an inclined, wall or ceiling mounting (§7).
/// The axes the gravity group tilts the robot file's gravity about (docs/method/03-error-model.md
/// §11), both perpendicular to it, in the frame it is given in: a = x of that frame made
/// perpendicular to g (y when g lies within 25° of x), b = ĝ × a.
inline std::array<Eigen::Vector3d, 2> gravity_tilt_axes(const Eigen::Vector3d& g) {
  const Eigen::Vector3d u = g.normalized();
  const Eigen::Vector3d x =
      std::abs(u.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d a = (x - x.dot(u) * u).normalized();
  return {a, u.cross(a)};
}

/// v turned by `angle` about the unit `axis` (Rodrigues).
template <typename T>
Vector3<T> turned(const Vector3<T>& v, const Vector3<T>& axis, const T& angle) {
  using std::cos;
  using std::sin;
  const T c = cos(angle), s = sin(angle);
  return v * c + axis.cross(v) * s + axis * (axis.dot(v) * (T(1) - c));
}

/// The robot file's gravity turned by the gravity group's tilts (§11): R(a, tilt_a)·R(b, tilt_b)·g
/// (gravity_tilt_axes), in the frame g is given in (world, or base when model.gravity_in_base).
template <typename T>
Vector3<T> tilted_gravity(const RobotModel& model, const T* params) {
  if (!detail::is_nonzero(params[kGravityTiltA]) && !detail::is_nonzero(params[kGravityTiltB]))
    return model.gravity_m_s2.template cast<T>();
  const std::array<Eigen::Vector3d, 2> axes = gravity_tilt_axes(model.gravity_m_s2);
  const Vector3<T> tilted_b = turned<T>(model.gravity_m_s2.template cast<T>(),
                                        axes[1].template cast<T>(), params[kGravityTiltB]);
  return turned<T>(tilted_b, axes[0].template cast<T>(), params[kGravityTiltA]);
}

template <typename T>
std::array<T, kJointCount> gravity_torques(const RobotModel& model, const PointMass& payload,
                                           const T* params,
                                           const std::array<T, kJointCount>& theta) {
  // Relative transforms A_2..A_6 with the undeflected angles.
  std::array<Pose<T>, kJointCount> A;  // A[i] = A_{i+1}, frame i -> i+1 (0-based: A[1] = A_2)
  for (int link = 2; link <= kJointCount; ++link)
    A[link - 1] = detail::mdh_transform(params[link_param(link, 0)], params[link_param(link, 1)],
                                        theta[link - 1], params[link_param(link, 3)]);
  // Gravity in each link frame: g_1 = R_world_1^T g_world (the base tilt alpha, beta matters:
  // gravity acts in the world, which the reference data set confirms), or g_1 = Rot_z(θ1)^T g_base
  // when the mounting gives it in the base frame (§7); g_i = R_{i-1,i}^T g_{i-1}.
  std::array<Vector3<T>, kJointCount> g;
  if (model.gravity_in_base) {
    using std::cos;
    using std::sin;
    const Vector3<T> gb = tilted_gravity(model, params);
    const T c = cos(theta[0]), s = sin(theta[0]);
    g[0] << c * gb.x() + s * gb.y(), c * gb.y() - s * gb.x(), gb.z();
  } else {
    g[0] = detail::base_transform(params, T(0), theta[0]).R.transpose() *
           tilted_gravity(model, params);
  }
  for (int i = 1; i < kJointCount; ++i) g[i] = A[i].R.transpose() * g[i - 1];
  // First moments from the tip: S_6 = m_6 u_6 + m_p u_p; S_i = m_i u_i + A_{i+1}·(S_{i+1},
  // M_{i+1}).
  Vector3<T> S = (model.link_masses[5].mass_kg * model.link_masses[5].cog_mm +
                  payload.mass_kg * payload.cog_mm)
                     .template cast<T>();
  double M = model.link_masses[5].mass_kg + payload.mass_kg;
  std::array<T, kJointCount> tau;
  for (int i = kJointCount - 1; i >= 0; --i) {  // 0-based frame index i = link i+1
    if (i < kJointCount - 1) {
      S = A[i + 1].R * S + A[i + 1].p * T(M) +
          (model.link_masses[i].mass_kg * model.link_masses[i].cog_mm).template cast<T>();
      M += model.link_masses[i].mass_kg;
    }
    tau[i] = S.x() * g[i].y() - S.y() * g[i].x();
  }
  return tau;
}

/// The periodic error's basis at model joint angle q (rad), in the layout's order of
/// jointI.periodicH.cos|sin: cos q, sin q, cos 2q, sin 2q (docs/method/03-error-model.md §5).
template <typename T>
std::array<T, kPeriodicPerJoint> periodic_basis(const T& q) {
  static_assert(kPeriodicHarmonics == 2, "the basis below lists two harmonics");
  using std::cos;
  using std::sin;
  const T c = cos(q), s = sin(q);
  return {c, s, c * c - s * s, T(2) * s * c};
}

/// The motor-angle periodic error's basis of model joint `joint` (1..6) at model angle q (rad):
/// periodic_basis of the motor angle r·q, r the joint's gear ratio, in the layout's order of
/// jointI.motor_periodicH.cos|sin (docs/method/03-error-model.md §9); zeros without a ratio.
template <typename T>
std::array<T, kPeriodicPerJoint> motor_periodic_basis(const RobotModel& model, int joint,
                                                      const T& q) {
  const double ratio = model.gear_ratio[static_cast<size_t>(joint - 1)];
  if (ratio == 0.0) return {T(0), T(0), T(0), T(0)};
  return periodic_basis(T(ratio) * q);
}

/// The periodic error term Σ_k e_k·b_k of one joint: `e` its four coefficients (periodic or
/// motor-periodic), `basis` the matching basis; the coefficients all zero (and, for a Jet,
/// underived) leave `theta` as it is without evaluating the basis.
template <typename T, typename Basis>
void add_periodic_error(const T* e, const Basis& basis, T& theta) {
  bool periodic = false;
  for (int k = 0; k < kPeriodicPerJoint; ++k) periodic = periodic || detail::is_nonzero(e[k]);
  if (!periodic) return;
  const std::array<T, kPeriodicPerJoint> b = basis();
  for (int k = 0; k < kPeriodicPerJoint; ++k) theta += e[k] * b[k];
}

/// The side model joint `joint` (1..6) is approached from: +1 from below, −1 from above, 0
/// unknown (the middle of the dead band), the controller joint's `approach` (null: every joint
/// from below, the measurement programs' practice), reversed where the joint map reverses the
/// joint (docs/method/03-error-model.md §6).
inline double model_approach(const RobotModel& model, const double* approach, int joint) {
  const double s = approach ? approach[joint - 1] : 1.0;
  return model.joint_map.matrix(joint - 1, joint - 1) < 0 ? -s : s;
}

/// The backlash term −s·b/2 of joint `joint` approached from side s (model_approach).
template <typename T>
T backlash_shift(const T* params, double side, int joint) {
  return params[backlash_param(joint)] * (-0.5 * side);
}

/// Joint angles θ_1..θ_6 (rad) used in the links: θ_i = scale_i·q_i + offset_i + δθ_i(q_i)
/// + δμ_i(r_i·q_i) − s_i·b_i/2 (+ c_i·τ_i when the model has compliance, joint 1's included),
/// δθ_i the periodic error, δμ_i the motor's (r_i the gear ratio), b_i the backlash and s_i the
/// approach of joint i (`approach`, see backlash_shift), docs/method/02-frames.md §5,
/// 03-error-model.md §3, §5, §6, §9. `q` are model joint angles.
template <typename T>
std::array<T, kJointCount> link_angles(const RobotModel& model, const PointMass& payload,
                                       const T* params, const std::array<T, kJointCount>& q,
                                       const double* approach = nullptr) {
  std::array<T, kJointCount> theta;
  theta[0] = params[scale_param(1)] * q[0] + T(model.mdh[0].theta_offset);
  for (int link = 2; link <= kJointCount; ++link)
    theta[link - 1] = params[scale_param(link)] * q[link - 1] + params[link_param(link, 2)];
  for (int joint = 1; joint <= kJointCount; ++joint) {
    const T& qj = q[joint - 1];
    add_periodic_error(
        params + periodic_param(joint, 1, false), [&] { return periodic_basis(qj); },
        theta[joint - 1]);
    if (model.gear_ratio[static_cast<size_t>(joint - 1)] != 0.0)
      add_periodic_error(
          params + motor_periodic_param(joint, 1, false),
          [&] { return motor_periodic_basis(model, joint, qj); }, theta[joint - 1]);
  }
  for (int joint = 1; joint <= kJointCount; ++joint)
    if (detail::is_nonzero(params[backlash_param(joint)]))
      theta[joint - 1] += backlash_shift(params, model_approach(model, approach, joint), joint);
  bool compliant = false;
  for (int joint = 1; joint <= kJointCount; ++joint)
    compliant = compliant || detail::is_nonzero(params[compliance_param(joint)]);
  if (compliant) {
    const std::array<T, kJointCount> tau = gravity_torques(model, payload, params, theta);
    for (int joint = 1; joint <= kJointCount; ++joint)
      theta[joint - 1] += params[compliance_param(joint)] * tau[joint - 1];
  }
  return theta;
}

/// What a measurement row records beyond its joints, that the opt-in groups depend on.
struct RowConditions {
  /// Each controller joint's approach (+1 from below, −1 from above, 0 unknown; null: from
  /// below), the backlash group's sign (§6).
  const Vector6d* approach = nullptr;
  /// Temperature minus the robot's reference temperature (K), the thermal group's factor (§8).
  double temperature_rise_k = 0;
  /// How far the arm has warmed up, φ = 1 − exp(−t/τ) of the row's time (warmup_fraction), 1
  /// warm, 0 cold or no time: the warm-up group's factor (§10).
  double warmup_fraction = 0;
};

/// The warm-up's progress φ(t) = 1 − exp(−t/τ) after `time_s` of work, τ the model's
/// warmup_time_constant_s (docs/method/03-error-model.md §10).
inline double warmup_fraction(const RobotModel& model, double time_s) {
  return 1.0 - std::exp(-time_s / model.warmup_time_constant_s);
}

/// 1/L_i of link i (2..6), L_i = √(a_i² + d_i²) its nominal length, 0 for a link without
/// length: the warm-up growth w_i (mm) is a fraction w_i/L_i of the link (§10).
inline double inverse_link_length(const RobotModel& model, int link) {
  const double length = std::hypot(model.mdh[link - 1].a, model.mdh[link - 1].d);
  return length > 0 ? 1.0 / length : 0.0;
}

/// True when the thermal or the warm-up group moves the links at `row` (or, for a ceres::Jet, is
/// differentiated there): a temperature rise and an expansion coefficient, or a warm-up and a
/// growth.
template <typename T>
bool thermal_active(const T* params, const RowConditions& row) {
  for (int link = 2; link <= kJointCount; ++link)
    if ((row.temperature_rise_k != 0 && detail::is_nonzero(params[expansion_param(link)])) ||
        (row.warmup_fraction != 0 && detail::is_nonzero(params[warmup_param(link)])))
      return true;
  return false;
}

/// The parameters at the row's temperature and warm-up: a_i and d_i of links 2..6 scaled by
/// (1 + e_i·ΔT + φ·w_i/L_i) (docs/method/03-error-model.md §8, §10), every other value as given.
template <typename T>
std::array<T, kParameterCount> warm_parameters(const RobotModel& model, const T* params,
                                               const RowConditions& row) {
  std::array<T, kParameterCount> warm;
  for (int i = 0; i < kParameterCount; ++i) warm[i] = params[i];
  for (int link = 2; link <= kJointCount; ++link) {
    const T growth =
        T(1) + params[expansion_param(link)] * row.temperature_rise_k +
        params[warmup_param(link)] * (row.warmup_fraction * inverse_link_length(model, link));
    warm[link_param(link, 1)] = params[link_param(link, 1)] * growth;
    warm[link_param(link, 3)] = params[link_param(link, 3)] * growth;
  }
  return warm;
}

/// World poses of the link frames Φ1..Φ6 (frames[5] is the flange, Φ6).
/// \param params  parameter vector (docs/method/03-error-model.md §1 layout, internal units),
/// kParameterCount values \param joints  controller joint values, rad \param row  the row's
/// approach, temperature and warm-up (RowConditions; default: from below, at the reference
/// temperature, cold)
template <typename T>
std::array<Pose<T>, kJointCount> link_frames(const RobotModel& model, const PointMass& payload,
                                             const T* params, const T* joints,
                                             const RowConditions& row = {}) {
  if (thermal_active(params, row)) {
    const std::array<T, kParameterCount> warm = warm_parameters(model, params, row);
    return link_frames(model, payload, warm.data(), joints, {row.approach, 0, 0});
  }
  const double* approach = row.approach ? row.approach->data() : nullptr;
  const std::array<T, kJointCount> q = model_joint_angles(model, joints);
  const std::array<T, kJointCount> theta = link_angles(model, payload, params, q, approach);
  std::array<Pose<T>, kJointCount> frames;
  frames[0] = detail::base_transform(params, T(model.mdh[0].d), theta[0]);
  for (int link = 2; link <= kJointCount; ++link)
    frames[link - 1] =
        frames[link - 2] * detail::mdh_transform(params[link_param(link, 0)],
                                                 params[link_param(link, 1)], theta[link - 1],
                                                 params[link_param(link, 3)]);
  return frames;
}

/// World pose of the flange (Φ6): world_T_flange = world_A_1 · A_2 ⋯ A_6.
template <typename T>
Pose<T> flange_pose(const RobotModel& model, const PointMass& payload, const T* params,
                    const T* joints, const RowConditions& row = {}) {
  return link_frames(model, payload, params, joints, row)[kJointCount - 1];
}

/// Convenience for double: flange pose from a parameter vector and controller joints (rad) at
/// the row's approach and temperature.
Pose<double> flange_pose(const RobotModel& model, const PointMass& payload,
                         const ParameterVector& params, const Vector6d& joints,
                         const RowConditions& row = {});

}  // namespace robcal
