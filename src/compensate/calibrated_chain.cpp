#include "robcal/compensate/calibrated_chain.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "../kinematics/angle_shift.hpp"

namespace robcal {
namespace {

constexpr int kTableSize = 256;  // a power of two: k mod 256 is k & 255, negative k included

/// The table's step 2π/256 split Cody–Waite style: kStepHigh has its low 12 bits zero, so
/// k·kStepHigh is exact for |k| < 4096 (|θ| < 100 rad), and kStepLow carries the rest of the
/// exact step, so that θ − k·2π/256 loses nothing to the step's rounding.
constexpr long double kStep = 2 * std::numbers::pi_v<long double> / kTableSize;
constexpr double kStepHigh = std::bit_cast<double>(
    std::bit_cast<std::uint64_t>(static_cast<double>(kStep)) & ~std::uint64_t{0xfff});
constexpr double kStepLow = static_cast<double>(kStep - kStepHigh);

/// sin and cos of k·2π/256, each correctly rounded (long double); built on first use, so that
/// no other static initialiser can see it empty.
const std::array<std::array<double, 2>, kTableSize>& sin_cos_table() {
  static const auto kTable = [] {
    std::array<std::array<double, 2>, kTableSize> t{};
    for (int k = 0; k < kTableSize; ++k)
      t[k] = {static_cast<double>(std::sin(k * kStep)), static_cast<double>(std::cos(k * kStep))};
    return t;
  }();
  return kTable;
}

}  // namespace

void table_sin_cos(double theta, double* s, double* c) {
  const double x = theta * static_cast<double>(1 / kStep);
  if (!(std::abs(x) < 4096)) {  // beyond the reduction's range, or not a number
    *s = std::sin(theta);
    *c = std::cos(theta);
    return;
  }
  // Nearest multiple by truncation (no libm call without SSE4.1's roundsd).
  const auto k = static_cast<std::int64_t>(x + (x >= 0 ? 0.5 : -0.5));
  const double kd = static_cast<double>(k);
  const auto& entry = sin_cos_table()[static_cast<std::size_t>(k & (kTableSize - 1))];
  sin_cos_shifted(entry[0], entry[1], (theta - kd * kStepHigh) - kd * kStepLow, s, c);
}

namespace {

/// A periodic error Σ_h (e_cos,h·cos(h·r·q) + e_sin,h·sin(h·r·q)) added to `theta` and its
/// slope in q to `rate` (r = 1: the joint's own, §5; r the gear ratio: its motor's, §9).
void add_periodic_error(const std::array<double, kPeriodicPerJoint>& e, double q, double ratio,
                        double& theta, double& rate) {
  double s1, c1;
  table_sin_cos(ratio * q, &s1, &c1);
  const double c2 = c1 * c1 - s1 * s1, s2 = 2 * s1 * c1;
  theta += e[0] * c1 + e[1] * s1 + e[2] * c2 + e[3] * s2;
  rate += ratio * (-e[0] * s1 + e[1] * c1 + 2 * (-e[2] * s2 + e[3] * c2));
}

/// Φ_i = Φ_{i-1} · Rot_x(α)·Trans_x(a)·Rot_z(θ)·Trans_z(d) written on the columns r0, r1, r2 of
/// Φ_{i-1}'s rotation: u = cα·r1 + sα·r2, z = cα·r2 − sα·r1, x = cθ·r0 + sθ·u, y = cθ·u − sθ·r0,
/// p = p_{i-1} + a·r0 + d·z (the MDH product with its zeros left out).
void next_frame(const Pose<double>& prev, double ca, double sa, double a, double d, double ct,
                double st, Pose<double>& out) {
  // Columns copied out (an Eigen Block operand costs here, as in the Jacobians).
  const Eigen::Vector3d r0 = prev.R.col(0), r1 = prev.R.col(1), r2 = prev.R.col(2);
  const Eigen::Vector3d u = ca * r1 + sa * r2, z = ca * r2 - sa * r1;
  out.R.col(0) = ct * r0 + st * u;
  out.R.col(1) = ct * u - st * r0;
  out.R.col(2) = z;
  out.p = prev.p + a * r0 + d * z;
}

/// World frames Φ1..Φ6 (docs/method/02-frames.md §5) from the cosines and sines of θ1 + γ_base and
/// θ2..θ6.
void chain_frames(const CalibratedChain& c, const std::array<double, kJointCount>& cos_t,
                  const std::array<double, kJointCount>& sin_t,
                  std::array<Pose<double>, kJointCount>& frames) {
  const auto bx = c.base_R_xy.col(0), by = c.base_R_xy.col(1);
  frames[0].R.col(0) = cos_t[0] * bx + sin_t[0] * by;
  frames[0].R.col(1) = cos_t[0] * by - sin_t[0] * bx;
  frames[0].R.col(2) = c.base_R_xy.col(2);
  frames[0].p = c.base_p;
  for (int i = 1; i < kJointCount; ++i)
    next_frame(frames[i - 1], c.cos_alpha[i], c.sin_alpha[i], c.a[i], c.d[i], cos_t[i], sin_t[i],
               frames[i]);
}

}  // namespace

CalibratedChain make_calibrated_chain(const RobotModel& model, const ParameterVector& cold_params,
                                      const PointMass& payload, const Pose<double>& flange_T_tcp,
                                      const RowConditions& row) {
  // At the target's temperature and warm-up the links have their warm lengths (§8, §10).
  const ParameterVector params =
      thermal_active(cold_params.data(), row)
          ? ParameterVector(warm_parameters(model, cold_params.data(), row).data())
          : cold_params;
  const double* approach = row.approach ? row.approach->data() : nullptr;
  CalibratedChain c;
  const double ca = std::cos(params[3]), sa = std::sin(params[3]);
  const double cb = std::cos(params[4]), sb = std::sin(params[4]);
  c.base_R_xy << cb, 0, sb, sa * sb, ca, -sa * cb, -ca * sb, sa, ca * cb;
  c.base_p << params[0], params[1], model.mdh[0].d + params[2];
  c.base_gamma = params[5];
  c.theta_offset[0] = model.mdh[0].theta_offset;
  for (int link = 2; link <= kJointCount; ++link) {
    const int i = link - 1;
    c.cos_alpha[i] = std::cos(params[link_param(link, 0)]);
    c.sin_alpha[i] = std::sin(params[link_param(link, 0)]);
    c.a[i] = params[link_param(link, 1)];
    c.theta_offset[i] = params[link_param(link, 2)];
    c.d[i] = params[link_param(link, 3)];
  }
  for (int i = 0; i < kJointCount; ++i) {
    c.compliance[i] = params[compliance_param(i + 1)];
    c.compliant = c.compliant || c.compliance[i] != 0.0;
  }
  for (int i = 0; i < kJointCount; ++i) {
    c.scale[i] = params[scale_param(i + 1)];
    for (int k = 0; k < kPeriodicPerJoint; ++k) {
      c.periodic[i][k] = params[periodic_param(i + 1, 1, false) + k];
      c.has_periodic[i] = c.has_periodic[i] || c.periodic[i][k] != 0.0;
    }
    c.gear_ratio[i] = model.gear_ratio[i];
    for (int k = 0; k < kPeriodicPerJoint; ++k) {
      c.motor_periodic[i][k] =
          c.gear_ratio[i] != 0.0 ? params[motor_periodic_param(i + 1, 1, false) + k] : 0.0;
      c.has_motor_periodic[i] = c.has_motor_periodic[i] || c.motor_periodic[i][k] != 0.0;
    }
    c.mass[i] = model.link_masses[i].mass_kg;
    c.moment[i] = model.link_masses[i].mass_kg * model.link_masses[i].cog_mm;
  }
  for (int joint = 1; joint <= kJointCount; ++joint)
    c.theta_offset[joint - 1] +=
        backlash_shift(params.data(), model_approach(model, approach, joint), joint);
  c.mass[5] += payload.mass_kg;
  c.moment[5] += payload.mass_kg * payload.cog_mm;
  c.gravity = tilted_gravity(model, params.data());  // the gravity group's tilt (§11)
  if (model.gravity_in_base) {  // given in the base frame: turned by R_xy·Rot_z(γ) (§7)
    const Eigen::Vector3d g = c.gravity;
    const double cg = std::cos(c.base_gamma), sg = std::sin(c.base_gamma);
    c.gravity =
        c.base_R_xy * Eigen::Vector3d(cg * g.x() - sg * g.y(), sg * g.x() + cg * g.y(), g.z());
  }
  c.joint_map = model.joint_map.matrix;
  c.joint_offset = model.joint_map.offset;
  c.map_identity = model.joint_map.is_identity();
  c.flange_T_tcp = flange_T_tcp;
  return c;
}

Pose<double> calibrated_tcp_pose(const CalibratedChain& c, const Vector6d& joints,
                                 ChainState& state) {
  const Vector6d q = c.map_identity ? joints : Vector6d(c.joint_map * joints + c.joint_offset);
  for (int i = 0; i < kJointCount; ++i) {
    double theta = c.scale[i] * q[i] + c.theta_offset[i] + (i == 0 ? c.base_gamma : 0.0);
    state.rate[i] = c.scale[i];
    // δθ = Σ_h (cos_h·cos hq + sin_h·sin hq), docs/method/03-error-model.md §5, and the motor's
    // δμ at r·q, §9.
    if (c.has_periodic[i]) add_periodic_error(c.periodic[i], q[i], 1.0, theta, state.rate[i]);
    if (c.has_motor_periodic[i])
      add_periodic_error(c.motor_periodic[i], q[i], c.gear_ratio[i], theta, state.rate[i]);
    const double step = theta - state.theta[i];
    if (state.has_angles && std::abs(step) < kSeriesShiftLimitRad) {
      sin_cos_shifted(state.sin_theta[i], state.cos_theta[i], step, &state.sin_theta[i],
                      &state.cos_theta[i]);
    } else {
      table_sin_cos(theta, &state.sin_theta[i], &state.cos_theta[i]);
    }
    state.theta[i] = theta;
  }
  state.has_angles = true;
  std::array<double, kJointCount> cos_t = state.cos_theta, sin_t = state.sin_theta;
  auto& frames = state.frames;
  chain_frames(c, cos_t, sin_t, frames);
  if (c.compliant) {
    // The torques are taken on the undeflected chain (docs/method/03-error-model.md §3); mass and
    // first moment of links i..6 (world) accumulate tip to base.
    double M = 0;
    Eigen::Vector3d C = Eigen::Vector3d::Zero();
    for (int i = kJointCount - 1; i >= 0; --i) {
      const Eigen::Vector3d p = frames[i].p, m = c.moment[i];
      M += c.mass[i];
      C += c.mass[i] * p + m.x() * Eigen::Vector3d(frames[i].R.col(0)) +
           m.y() * Eigen::Vector3d(frames[i].R.col(1)) +
           m.z() * Eigen::Vector3d(frames[i].R.col(2));
      state.V[i] = C - M * p;
    }
    for (int i = 0; i < kJointCount; ++i) state.z_undeflected[i] = frames[i].R.col(2);
    for (int i = 0; i < kJointCount; ++i) {
      if (c.compliance[i] == 0.0) continue;
      const double tau = state.z_undeflected[i].dot(state.V[i].cross(c.gravity));
      sin_cos_shifted(sin_t[i], cos_t[i], c.compliance[i] * tau, &sin_t[i], &cos_t[i]);
    }
    chain_frames(c, cos_t, sin_t, frames);
  }
  // frames[5] · flange_T_tcp on copied columns (as in next_frame).
  const Eigen::Vector3d x = frames[kJointCount - 1].R.col(0), y = frames[kJointCount - 1].R.col(1),
                        z = frames[kJointCount - 1].R.col(2);
  Pose<double> tcp;
  for (int j = 0; j < 3; ++j)
    tcp.R.col(j) =
        x * c.flange_T_tcp.R(0, j) + y * c.flange_T_tcp.R(1, j) + z * c.flange_T_tcp.R(2, j);
  tcp.p = frames[kJointCount - 1].p + x * c.flange_T_tcp.p.x() + y * c.flange_T_tcp.p.y() +
          z * c.flange_T_tcp.p.z();
  state.tcp_p = tcp.p;
  return tcp;
}

void calibrated_jacobian(const CalibratedChain& c, const ChainState& state, Matrix6d& J) {
  for (int k = 0; k < kJointCount; ++k) {
    const Eigen::Vector3d z_k = state.frames[k].R.col(2);
    J.block<3, 1>(0, k) = z_k.cross(state.tcp_p - state.frames[k].p);
    J.block<3, 1>(3, k) = z_k;
  }
  if (c.compliant) {
    // J_θ + J_θ·diag(c)·∂τ/∂θu, ∂τ_i/∂θu_k = y_max(i,k) · w_min(i,k) (file comment).
    const auto& z = state.z_undeflected;
    std::array<Eigen::Vector3d, kJointCount> w, y;
    Matrix6d J_c;
    for (int i = 0; i < kJointCount; ++i) {
      w[i] = c.gravity.cross(z[i]);
      y[i] = z[i].cross(state.V[i]);
      J_c.col(i) = c.compliance[i] * J.col(i);
    }
    Matrix6d dtau;
    for (int i = 0; i < kJointCount; ++i)
      for (int k = 0; k < kJointCount; ++k) dtau(i, k) = k <= i ? y[i].dot(w[k]) : y[k].dot(w[i]);
    J.noalias() += J_c * dtau;
  }
  for (int k = 0; k < kJointCount; ++k) J.col(k) *= state.rate[k];
  if (!c.map_identity) J = J * c.joint_map;
}

Vector6d calibrated_jacobian_derivative(const CalibratedChain& c, const ChainState& state,
                                        const Vector6d& along, const Vector6d& v) {
  const Vector6d du = c.map_identity ? along : Vector6d(c.joint_map * along);
  const Vector6d dv = c.map_identity ? v : Vector6d(c.joint_map * v);
  // Σ_k ν_k·z_k × (ṗ − ȯ_k) = ω_v × ṗ − Σ_k ν_k·z_k × ȯ_k, ω_v = Σ_k ν_k·z_k: one pass. Link
  // 0 is still (ż_1 = ȯ_1 = 0) and only starts ω and ω_v.
  const Eigen::Vector3d z_1 = state.frames[0].R.col(2);
  Eigen::Vector3d omega = (state.rate[0] * du[0]) * z_1, omega_v = (state.rate[0] * dv[0]) * z_1,
                  o_dot = Eigen::Vector3d::Zero(), linear = Eigen::Vector3d::Zero(),
                  angular = Eigen::Vector3d::Zero();
  for (int k = 1; k < kJointCount; ++k) {
    const Pose<double>& f = state.frames[k];
    o_dot += omega.cross(f.p - state.frames[k - 1].p);
    const Eigen::Vector3d z = f.R.col(2);
    const Eigen::Vector3d z_dot = omega.cross(z);
    const double nu = state.rate[k] * dv[k];
    linear += nu * (z_dot.cross(state.tcp_p - f.p) - z.cross(o_dot));
    angular += nu * z_dot;
    omega_v += nu * z;
    omega += (state.rate[k] * du[k]) * z;
  }
  const Eigen::Vector3d p_dot = o_dot + omega.cross(state.tcp_p - state.frames[kJointCount - 1].p);
  Vector6d out;
  out.head<3>() = linear + omega_v.cross(p_dot);
  out.tail<3>() = angular;
  return out;
}

Pose<double> calibrated_tcp_pose(const CalibratedChain& c, const Vector6d& joints,
                                 Matrix6d* jacobian) {
  ChainState state;
  Pose<double> tcp = calibrated_tcp_pose(c, joints, state);
  if (jacobian) calibrated_jacobian(c, state, *jacobian);
  return tcp;
}

}  // namespace robcal
