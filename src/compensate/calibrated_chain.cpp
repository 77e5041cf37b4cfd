#include "robcal/compensate/calibrated_chain.hpp"

#include <cmath>

namespace robcal {
namespace {

/// World frames Φ1..Φ6 for link angles θ1..θ6 (METHOD §2; θ1 without the base γ).
void chain_frames(const CalibratedChain& c, const std::array<double, kJointCount>& theta,
                  std::array<Pose<double>, kJointCount>& frames) {
  const double g = c.base_gamma + theta[0];
  const double cg = std::cos(g), sg = std::sin(g);
  Eigen::Matrix3d Rz;
  Rz << cg, -sg, 0, sg, cg, 0, 0, 0, 1;
  frames[0].R = c.base_R_xy * Rz;
  frames[0].p = c.base_p;
  for (int i = 1; i < kJointCount; ++i) {
    const double ct = std::cos(theta[i]), st = std::sin(theta[i]);
    const double ca = c.cos_alpha[i], sa = c.sin_alpha[i];
    Eigen::Matrix3d R;
    R << ct, -st, 0, st * ca, ct * ca, -sa, st * sa, ct * sa, ca;
    const Eigen::Vector3d p(c.a[i], -sa * c.d[i], ca * c.d[i]);
    frames[i].p = frames[i - 1].R * p + frames[i - 1].p;
    frames[i].R = frames[i - 1].R * R;
  }
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
                                 Matrix6d* jacobian) {
  const Vector6d q = c.map_identity ? joints : Vector6d(c.joint_map * joints + c.joint_offset);
  std::array<double, kJointCount> theta;
  for (int i = 0; i < kJointCount; ++i) theta[i] = c.scale[i] * q[i] + c.theta_offset[i];
  std::array<Pose<double>, kJointCount> frames;
  // dθ/dθu = I + diag(c)·∂τ/∂θu (rows of joints 2..6), identity without compliance.
  Matrix6d deflection = Matrix6d::Identity();
  if (c.compliant) {
    chain_frames(c, theta, frames);  // undeflected: the torques are taken there (METHOD §3)
    // Mass and first moment of links i..6 (world), tip to base.
    std::array<Eigen::Vector3d, kJointCount> V;
    double M = 0;
    Eigen::Vector3d C = Eigen::Vector3d::Zero();
    for (int i = kJointCount - 1; i >= 1; --i) {
      M += c.mass[i];
      C += c.mass[i] * frames[i].p + frames[i].R * c.moment[i];
      V[i] = C - M * frames[i].p;
    }
    std::array<double, kJointCount> tau{};
    for (int i = 1; i < kJointCount; ++i) {
      const Eigen::Vector3d z_i = frames[i].R.col(2);
      tau[i] = z_i.dot(V[i].cross(c.gravity));
      if (jacobian) {
        for (int k = 0; k < kJointCount; ++k) {
          const Eigen::Vector3d z_k = frames[k].R.col(2);
          const double dtau = k <= i ? z_k.cross(z_i).dot(V[i].cross(c.gravity)) +
                                           z_i.dot(z_k.cross(V[i]).cross(c.gravity))
                                     : z_i.dot(z_k.cross(V[k]).cross(c.gravity));
          deflection(i, k) += c.compliance[i] * dtau;
        }
      }
    }
    for (int i = 1; i < kJointCount; ++i) theta[i] += c.compliance[i] * tau[i];
  }
  chain_frames(c, theta, frames);
  const Pose<double> tcp = frames[kJointCount - 1] * c.flange_T_tcp;
  if (jacobian) {
    Matrix6d J_theta;
    for (int k = 0; k < kJointCount; ++k) {
      const Eigen::Vector3d z_k = frames[k].R.col(2);
      J_theta.block<3, 1>(0, k) = z_k.cross(tcp.p - frames[k].p);
      J_theta.block<3, 1>(3, k) = z_k;
    }
    Matrix6d dtheta_dj =
        deflection * Vector6d(Eigen::Map<const Vector6d>(c.scale.data())).asDiagonal();
    if (!c.map_identity) dtheta_dj = dtheta_dj * c.joint_map;
    *jacobian = J_theta * dtheta_dj;
  }
  return tcp;
}

}  // namespace robcal
