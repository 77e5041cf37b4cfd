#include "robcal/compensate/calibrated_chain.hpp"

#include <cmath>

#include "robcal/kinematics/angle_shift.hpp"

namespace robcal {
namespace {

/// Φ_i = Φ_{i-1} · Rot_x(α)·Trans_x(a)·Rot_z(θ)·Trans_z(d) written on the columns r0, r1, r2 of
/// Φ_{i-1}'s rotation: u = cα·r1 + sα·r2, z = cα·r2 − sα·r1, x = cθ·r0 + sθ·u, y = cθ·u − sθ·r0,
/// p = p_{i-1} + a·r0 + d·z (the MDH product with its zeros left out).
void next_frame(const Pose<double>& prev, double ca, double sa, double a, double d, double ct,
                double st, Pose<double>& out) {
  const auto r0 = prev.R.col(0), r1 = prev.R.col(1), r2 = prev.R.col(2);
  const Eigen::Vector3d u = ca * r1 + sa * r2;
  out.R.col(2) = ca * r2 - sa * r1;
  out.R.col(0) = ct * r0 + st * u;
  out.R.col(1) = ct * u - st * r0;
  out.p = prev.p + a * r0 + d * out.R.col(2);
}

/// World frames Φ1..Φ6 (METHOD §2) from the cosines and sines of θ1 + γ_base and θ2..θ6.
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

CalibratedChain make_calibrated_chain(const RobotModel& model, const ParameterVector& params,
                                      const PointMass& payload, const Pose<double>& flange_T_tcp) {
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
    c.compliance[i] = params[compliance_param(link)];
    c.compliant = c.compliant || c.compliance[i] != 0.0;
  }
  for (int i = 0; i < kJointCount; ++i) {
    c.scale[i] = params[scale_param(i + 1)];
    c.mass[i] = model.link_masses[i].mass_kg;
    c.moment[i] = model.link_masses[i].mass_kg * model.link_masses[i].cog_mm;
  }
  c.mass[5] += payload.mass_kg;
  c.moment[5] += payload.mass_kg * payload.cog_mm;
  c.gravity = model.gravity_m_s2;
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
    const double theta = c.scale[i] * q[i] + c.theta_offset[i] + (i == 0 ? c.base_gamma : 0.0);
    const double step = theta - state.theta[i];
    if (state.has_angles && std::abs(step) < kSeriesShiftLimitRad) {
      sin_cos_shifted(state.sin_theta[i], state.cos_theta[i], step, &state.sin_theta[i],
                      &state.cos_theta[i]);
    } else {
      state.cos_theta[i] = std::cos(theta);
      state.sin_theta[i] = std::sin(theta);
    }
    state.theta[i] = theta;
  }
  state.has_angles = true;
  std::array<double, kJointCount> cos_t = state.cos_theta, sin_t = state.sin_theta;
  auto& frames = state.frames;
  chain_frames(c, cos_t, sin_t, frames);
  if (c.compliant) {
    // The torques are taken on the undeflected chain (METHOD §3); mass and first moment of
    // links i..6 (world) accumulate tip to base.
    double M = 0;
    Eigen::Vector3d C = Eigen::Vector3d::Zero();
    for (int i = kJointCount - 1; i >= 1; --i) {
      M += c.mass[i];
      C += c.mass[i] * frames[i].p + frames[i].R * c.moment[i];
      state.V[i] = C - M * frames[i].p;
    }
    for (int i = 0; i < kJointCount; ++i) state.z_undeflected[i] = frames[i].R.col(2);
    for (int i = 1; i < kJointCount; ++i) {
      const double tau = state.z_undeflected[i].dot(state.V[i].cross(c.gravity));
      sin_cos_shifted(sin_t[i], cos_t[i], c.compliance[i] * tau, &sin_t[i], &cos_t[i]);
    }
    for (int i = 1; i < kJointCount; ++i)
      next_frame(frames[i - 1], c.cos_alpha[i], c.sin_alpha[i], c.a[i], c.d[i], cos_t[i], sin_t[i],
                 frames[i]);
  }
  const Pose<double> tcp = frames[kJointCount - 1] * c.flange_T_tcp;
  state.tcp_p = tcp.p;
  return tcp;
}

void calibrated_jacobian(const CalibratedChain& c, const ChainState& state, Matrix6d& J) {
  Matrix6d J_theta;
  for (int k = 0; k < kJointCount; ++k) {
    const auto z_k = state.frames[k].R.col(2);
    J_theta.block<3, 1>(0, k) = z_k.cross(state.tcp_p - state.frames[k].p);
    J_theta.block<3, 1>(3, k) = z_k;
  }
  J = J_theta;
  if (c.compliant) {
    // J_θ·(I + diag(c)·∂τ/∂θu), one dot product per entry (file comment).
    const auto& z = state.z_undeflected;
    const auto& V = state.V;
    const Eigen::Vector3d& g = c.gravity;
    std::array<Eigen::Vector3d, kJointCount> w, u, y;
    for (int i = 1; i < kJointCount; ++i) {
      w[i] = g.cross(z[i]);
      u[i] = z[i].cross(V[i].cross(g)) + V[i].cross(w[i]);
      y[i] = z[i].cross(V[i]);
    }
    for (int i = 1; i < kJointCount; ++i) {
      const Vector6d column = c.compliance[i] * J_theta.col(i);
      for (int k = 0; k < kJointCount; ++k)
        J.col(k) += (k <= i ? z[k].dot(u[i]) : y[k].dot(w[i])) * column;
    }
  }
  for (int k = 0; k < kJointCount; ++k) J.col(k) *= c.scale[k];
  if (!c.map_identity) J = J * c.joint_map;
}

Pose<double> calibrated_tcp_pose(const CalibratedChain& c, const Vector6d& joints,
                                 Matrix6d* jacobian) {
  ChainState state;
  const Pose<double> tcp = calibrated_tcp_pose(c, joints, state);
  if (jacobian) calibrated_jacobian(c, state, *jacobian);
  return tcp;
}

}  // namespace robcal
