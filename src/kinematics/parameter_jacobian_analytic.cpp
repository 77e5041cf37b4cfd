#include <Eigen/Geometry>

#include "robcal/kinematics/parameter_jacobian.hpp"

namespace robcal {
namespace {

using Eigen::Vector3d;

/// World frames Φ1..Φ6 for given link angles θ_1..θ_6 (rad).
std::array<Pose<double>, kJointCount> chain(const RobotModel& model, const double* x,
                                            const std::array<double, kJointCount>& theta) {
  std::array<Pose<double>, kJointCount> F;
  F[0] = detail::base_transform(x, model.mdh[0].d, theta[0]);
  for (int link = 2; link <= kJointCount; ++link)
    F[link - 1] =
        F[link - 2] * detail::mdh_transform(x[link_param(link, 0)], x[link_param(link, 1)],
                                            theta[link - 1], x[link_param(link, 3)]);
  return F;
}

/// An elementary motion of the chain: rotation about `axis` through `point`, or translation
/// along `axis`; frames with 0-based index ≥ `first` (and the bodies they carry) move.
struct Motion {
  bool rotation = false;
  Vector3d axis = Vector3d::Zero();
  Vector3d point = Vector3d::Zero();
  int first = 0;
};

/// What the gravity torques need of the undeflected chain (METHOD §3 in world form):
/// v_k = Σ_{j≥k} m_j (c_j − o_k) (first moment about o_k), τ_k = z_k · (v_k × g).
/// For a rotation ω = u of frames ≥ first: dτ_k = u · a_k when frame k moves
/// (a_k = z_k × (v_k × g) + v_k × (g × z_k)), and dτ_k = (u × (C_first − M_first·p)) · h_k when
/// it does not (h_k = g × z_k; C, M the moving bodies' first moment and mass). A translation u
/// changes only the torques of the frames that do not move: dτ_k = M_first·(u · h_k).
struct TorqueGeometry {
  std::array<double, kJointCount> tau{};  ///< index k = joint k+1; tau[0] unused
  std::array<Vector3d, kJointCount> a, h, z;
  std::array<Vector3d, kJointCount + 1> C;  ///< suffix first moments Σ_{j≥k} m_j c_j (world)
  std::array<double, kJointCount + 1> M{};  ///< suffix masses

  /// dτ_k/dξ, k = 1..5 (joints 2..6), of one elementary motion.
  void derivative(const Motion& m, std::array<double, kJointCount>& dtau) const {
    Vector3d e = Vector3d::Zero();
    if (m.rotation) e = m.axis.cross(C[m.first] - M[m.first] * m.point);
    for (int k = 1; k < kJointCount; ++k) {
      if (k >= m.first)
        dtau[k] = m.rotation ? m.axis.dot(a[k]) : 0.0;
      else
        dtau[k] = m.rotation ? e.dot(h[k]) : M[m.first] * m.axis.dot(h[k]);
    }
  }
};

TorqueGeometry torque_geometry(const RobotModel& model, const PointMass& payload,
                               const std::array<Pose<double>, kJointCount>& F) {
  TorqueGeometry t;
  const Vector3d g = model.gravity_m_s2;
  t.C[kJointCount].setZero();
  t.M[kJointCount] = 0;
  for (int j = kJointCount - 1; j >= 0; --j) {
    const PointMass& body = model.link_masses[j];
    t.C[j] = t.C[j + 1] + body.mass_kg * (F[j] * body.cog_mm);
    t.M[j] = t.M[j + 1] + body.mass_kg;
    if (j == kJointCount - 1) {  // the payload is lumped with link 6
      t.C[j] += payload.mass_kg * (F[j] * payload.cog_mm);
      t.M[j] += payload.mass_kg;
    }
  }
  for (int k = 0; k < kJointCount; ++k) {
    const Vector3d z = F[k].R.col(2);
    const Vector3d v = t.C[k] - t.M[k] * F[k].p;
    const Vector3d w = v.cross(g);
    t.z[k] = z;
    t.h[k] = g.cross(z);
    t.a[k] = z.cross(w) + v.cross(t.h[k]);
    t.tau[k] = z.dot(w);
  }
  return t;
}

/// The geometric motion of parameter `index` in frames F, or false for the parameters that act
/// only through joint angles (offsets, compliances, scales).
bool parameter_motion(int index, const double* x, const std::array<Pose<double>, kJointCount>& F,
                      Motion& m) {
  m.first = 0;
  if (index < 3) {  // base translation along world axes
    m.rotation = false;
    m.axis = Vector3d::Unit(index);
    return true;
  }
  if (index < kBaseParamCount) {
    m.rotation = true;
    m.point = F[0].p;
    if (index == 3) m.axis = Vector3d::UnitX();
    if (index == 4) m.axis = Vector3d(0, std::cos(x[3]), std::sin(x[3]));  // Rot_x(α)·e_y
    if (index == 5) m.axis = F[0].R.col(2);
    return true;
  }
  if (index >= kComplianceOffset) return false;
  const int link = 2 + (index - kLinkParamOffset) / 4;
  const int k = (index - kLinkParamOffset) % 4;
  const int previous = link - 2;  // 0-based frame index of Φ_{link-1}
  m.first = link - 1;
  switch (k) {
    case 0:
      m.rotation = true;
      m.axis = F[previous].R.col(0);
      m.point = F[previous].p;
      return true;
    case 1:
      m.rotation = false;
      m.axis = F[previous].R.col(0);
      return true;
    case 3:
      m.rotation = false;
      m.axis = F[link - 1].R.col(2);
      return true;
    default:
      return false;  // the joint offset acts through θ
  }
}

}  // namespace

void flange_twist_jacobian(const RobotModel& model, const PointMass& payload,
                           const ParameterVector& params, const Vector6d& joints,
                           Pose<double>* world_T_flange, TwistJacobian* jacobian) {
  const double* x = params.data();
  const std::array<double, kJointCount> q = model_joint_angles<double>(model, joints.data());
  std::array<double, kJointCount> theta_u;
  theta_u[0] = x[scale_param(1)] * q[0] + model.mdh[0].theta_offset;
  for (int link = 2; link <= kJointCount; ++link)
    theta_u[link - 1] = x[scale_param(link)] * q[link - 1] + x[link_param(link, 2)];

  const std::array<Pose<double>, kJointCount> Fu = chain(model, x, theta_u);
  const TorqueGeometry torque = torque_geometry(model, payload, Fu);
  std::array<double, kJointCount> c{};  // c[k]: compliance of joint k+1 (joint 1 has none)
  std::array<double, kJointCount> theta_d = theta_u;
  bool compliant = false;
  for (int k = 1; k < kJointCount; ++k) {
    c[k] = x[compliance_param(k + 1)];
    theta_d[k] += c[k] * torque.tau[k];
    compliant = compliant || c[k] != 0.0;
  }
  const std::array<Pose<double>, kJointCount> Fd = compliant ? chain(model, x, theta_d) : Fu;
  if (world_T_flange) *world_T_flange = Fd[kJointCount - 1];
  if (!jacobian) return;

  // Joint twists of the deflected chain, and dτ_k/dθu_j of the undeflected one (rotation of
  // frames ≥ j about z_j).
  std::array<Eigen::Matrix<double, 6, 1>, kJointCount> Z;
  for (int j = 0; j < kJointCount; ++j) {
    const Vector3d z = Fd[j].R.col(2);
    Z[j] << Fd[j].p.cross(z), z;
  }
  std::array<std::array<double, kJointCount>, kJointCount> dtau_dtheta{};  // [j][k]
  if (compliant)
    for (int j = 0; j < kJointCount; ++j)
      torque.derivative({true, Fu[j].R.col(2), Fu[j].p, j}, dtau_dtheta[j]);

  for (int i = 0; i < kParameterCount; ++i) {
    Eigen::Matrix<double, 6, 1> col = Eigen::Matrix<double, 6, 1>::Zero();
    std::array<double, kJointCount> dtheta_u{};  // direct change of the undeflected angles
    std::array<double, kJointCount> dtau{};
    Motion md, mu;
    if (parameter_motion(i, x, Fd, md)) {
      if (md.rotation)
        col << md.point.cross(md.axis), md.axis;
      else
        col << md.axis, Vector3d::Zero();
      if (compliant) {
        parameter_motion(i, x, Fu, mu);
        torque.derivative(mu, dtau);
      }
    } else if (i < kComplianceOffset) {
      dtheta_u[1 + (i - kLinkParamOffset) / 4] = 1.0;  // joint offset of link 2..6
    } else if (i >= kScaleOffset) {
      dtheta_u[i - kScaleOffset] = q[i - kScaleOffset];
    }
    if (compliant)
      for (int j = 0; j < kJointCount; ++j)
        if (dtheta_u[j] != 0.0)
          for (int k = 1; k < kJointCount; ++k) dtau[k] += dtau_dtheta[j][k] * dtheta_u[j];
    for (int k = 0; k < kJointCount; ++k) {
      double dtheta = dtheta_u[k] + c[k] * dtau[k];
      if (k > 0 && i == compliance_param(k + 1)) dtheta += torque.tau[k];
      if (dtheta != 0.0) col += Z[k] * dtheta;
    }
    jacobian->col(i) = col;
  }
}

PositionJacobian point_jacobian_from_twist(const TwistJacobian& twist, const Eigen::Vector3d& p) {
  PositionJacobian J;
  // v + ω × p = v − p × ω
  J.row(0) = twist.row(0) + p.z() * twist.row(4) - p.y() * twist.row(5);
  J.row(1) = twist.row(1) + p.x() * twist.row(5) - p.z() * twist.row(3);
  J.row(2) = twist.row(2) + p.y() * twist.row(3) - p.x() * twist.row(4);
  return J;
}

void target_position_jacobian(const RobotModel& model, const PointMass& payload,
                              const ParameterVector& params, const Vector6d& joints,
                              const Eigen::Vector3d& target_flange_mm, Eigen::Vector3d* position_mm,
                              PositionJacobian* jacobian) {
  Pose<double> flange;
  TwistJacobian twist;
  flange_twist_jacobian(model, payload, params, joints, &flange, jacobian ? &twist : nullptr);
  const Eigen::Vector3d p = flange * target_flange_mm;
  if (position_mm) *position_mm = p;
  if (jacobian) *jacobian = point_jacobian_from_twist(twist, p);
}

}  // namespace robcal
