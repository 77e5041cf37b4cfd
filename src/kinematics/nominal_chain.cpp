#include "robcal/kinematics/nominal_chain.hpp"

#include <cmath>

namespace robcal {

NominalChain make_nominal_chain(const RobotModel& model) {
  NominalChain chain;
  for (int i = 0; i < kJointCount; ++i) {
    chain.cos_alpha[i] = std::cos(model.mdh[i].alpha);
    chain.sin_alpha[i] = std::sin(model.mdh[i].alpha);
    chain.a[i] = model.mdh[i].a;
    chain.d[i] = model.mdh[i].d;
    chain.theta_offset[i] = model.mdh[i].theta_offset;
  }
  chain.joint_map = model.joint_map;
  chain.map_identity = model.joint_map.is_identity();
  return chain;
}

Pose<double> nominal_flange_pose(const NominalChain& chain, const Vector6d& joints) {
  const Vector6d q = chain.map_identity ? joints : chain.joint_map.to_model(joints);
  Pose<double> T;
  const double t1 = q[0] + chain.theta_offset[0];
  const double c1 = std::cos(t1), s1 = std::sin(t1);
  T.R << c1, -s1, 0, s1, c1, 0, 0, 0, 1;
  T.p << 0, 0, chain.d[0];
  for (int i = 1; i < kJointCount; ++i) {
    const double ca = chain.cos_alpha[i], sa = chain.sin_alpha[i];
    const double t = q[i] + chain.theta_offset[i];
    const double ct = std::cos(t), st = std::sin(t);
    // R·Rot_x(α) has columns (r0, u, w) with u = ca·r1 + sa·r2, w = −sa·r1 + ca·r2; then Rot_z(θ)
    // mixes r0 and u. Translation: R·(a, 0, 0) + (R·Rot_x(α))·(0, 0, d) = a·r0 + d·w.
    const Eigen::Vector3d r0 = T.R.col(0);
    const Eigen::Vector3d u = ca * T.R.col(1) + sa * T.R.col(2);
    const Eigen::Vector3d w = -sa * T.R.col(1) + ca * T.R.col(2);
    T.p += chain.a[i] * r0 + chain.d[i] * w;
    T.R.col(0) = ct * r0 + st * u;
    T.R.col(1) = -st * r0 + ct * u;
    T.R.col(2) = w;
  }
  return T;
}

}  // namespace robcal
