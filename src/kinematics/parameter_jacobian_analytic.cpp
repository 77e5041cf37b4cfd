#include <Eigen/Geometry>

#include "robcal/kinematics/parameter_jacobian.hpp"

namespace robcal {
namespace {

using Eigen::Vector3d;

/// sin and cos of one angle (the compiler merges them into one sincos call).
void sin_cos(double angle, double* s, double* c) {
  *s = std::sin(angle);
  *c = std::cos(angle);
}

/// sin and cos of θ + δ from those of θ; for the small gearbox deflections δ (< 0.01 rad) by
/// their series, whose next terms (δ⁷/5040, δ⁸/40320) are below double rounding.
void sin_cos_shifted(double s0, double c0, double delta, double* s, double* c) {
  double sd, cd;
  if (std::abs(delta) < 1e-2) {
    const double d2 = delta * delta;
    sd = delta * (1 - d2 / 6 * (1 - d2 / 20 * (1 - d2 / 42)));
    cd = 1 - d2 / 2 * (1 - d2 / 12 * (1 - d2 / 30));
  } else {
    sin_cos(delta, &sd, &cd);
  }
  *s = s0 * cd + c0 * sd;
  *c = c0 * cd - s0 * sd;
}

/// Cosine and sine of the parameter angles that do not depend on the joints (link twists α_i,
/// base α and β), shared by the undeflected and the deflected chain.
struct FixedAngles {
  std::array<double, kJointCount> ca{}, sa{};  ///< index k = link k+1 (k ≥ 1)
  Eigen::Matrix3d R_base_xy;                   ///< Rot_x(α_b)·Rot_y(β_b)
};

FixedAngles fixed_angles(const double* x) {
  FixedAngles f;
  for (int link = 2; link <= kJointCount; ++link)
    sin_cos(x[link_param(link, 0)], &f.sa[link - 1], &f.ca[link - 1]);
  double sa, ca, sb, cb;
  sin_cos(x[3], &sa, &ca);
  sin_cos(x[4], &sb, &cb);
  f.R_base_xy << cb, 0, sb, sa * sb, ca, -sa * cb, -ca * sb, sa, ca * cb;
  return f;
}

/// sin and cos of the link angles θ_1..θ_6 (θ_1 with the base γ added).
struct JointTrig {
  std::array<double, kJointCount> s{}, c{};
};

/// World frames Φ1..Φ6 for link angles given by their sin and cos, composed column by column:
/// Rot_x(α)·Trans_x(a) mixes the previous y, z axes and moves along the previous x;
/// Rot_z(θ)·Trans_z(d) mixes the new x, y and moves along the new z (METHOD §2).
std::array<Pose<double>, kJointCount> chain(const RobotModel& model, const double* x,
                                            const FixedAngles& f, const JointTrig& t) {
  std::array<Pose<double>, kJointCount> F;
  F[0].R.col(0) = t.c[0] * f.R_base_xy.col(0) + t.s[0] * f.R_base_xy.col(1);
  F[0].R.col(1) = t.c[0] * f.R_base_xy.col(1) - t.s[0] * f.R_base_xy.col(0);
  F[0].R.col(2) = f.R_base_xy.col(2);
  F[0].p = Vector3d(x[0], x[1], model.mdh[0].d + x[2]);
  for (int k = 1; k < kJointCount; ++k) {
    const int link = k + 1;
    const Eigen::Matrix3d& P = F[k - 1].R;
    const Vector3d y = f.ca[k] * P.col(1) + f.sa[k] * P.col(2);
    const Vector3d z = f.ca[k] * P.col(2) - f.sa[k] * P.col(1);
    F[k].R.col(0) = t.c[k] * P.col(0) + t.s[k] * y;
    F[k].R.col(1) = t.c[k] * y - t.s[k] * P.col(0);
    F[k].R.col(2) = z;
    F[k].p = F[k - 1].p + x[link_param(link, 1)] * P.col(0) + x[link_param(link, 3)] * z;
  }
  return F;
}

/// What the gravity torques need of the undeflected chain (METHOD §3 in world form):
/// v_k = Σ_{j≥k} m_j (c_j − o_k) (first moment about o_k), τ_k = z_k · (v_k × g).
/// An elementary motion of the frames ≥ f (and the bodies they carry) changes τ_k by:
/// - rotation ω = u about a line through p: u · a_k when frame k moves (k ≥ f),
///   a_k = z_k × (v_k × g) + v_k × (g × z_k); (u × (C_f − M_f·p)) · h_k when it does not
///   (k < f), h_k = g × z_k, C_f and M_f the moving bodies' first moment and mass;
/// - translation u: 0 when frame k moves, M_f·(u · h_k) when it does not.
struct TorqueGeometry {
  std::array<double, kJointCount> tau{};  ///< index k = joint k+1; tau[0] unused
  Eigen::Matrix<double, 3, kJointCount> a, h;
  std::array<Vector3d, kJointCount + 1> C;  ///< suffix first moments Σ_{j≥k} m_j c_j (world)
  std::array<double, kJointCount + 1> M{};  ///< suffix masses

  /// dτ_k/dξ (k = 1..5, joints 2..6) of a rotation about u through p moving frames ≥ f.
  [[nodiscard]] Vector6d rotation(const Vector3d& u, const Vector3d& p, int f) const {
    const Vector3d e = u.cross(C[f] - M[f] * p);
    Vector6d out;
    out[0] = 0;
    for (int k = 1; k < kJointCount; ++k) out[k] = k >= f ? u.dot(a.col(k)) : e.dot(h.col(k));
    return out;
  }
  /// dτ_k/dξ of a translation along u moving frames ≥ f.
  [[nodiscard]] Vector6d translation(const Vector3d& u, int f) const {
    Vector6d out = Vector6d::Zero();
    for (int k = 1; k < f; ++k) out[k] = M[f] * u.dot(h.col(k));
    return out;
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
    t.h.col(k) = g.cross(z);
    t.a.col(k) = z.cross(w) + v.cross(t.h.col(k));
    t.tau[k] = z.dot(w);
  }
  return t;
}

using Twist = Eigen::Matrix<double, 6, 1>;

Twist rotation_twist(const Vector3d& u, const Vector3d& p) {
  Twist t;
  t << p.cross(u), u;
  return t;
}

Twist translation_twist(const Vector3d& u) {
  Twist t;
  t << u, Vector3d::Zero();
  return t;
}

}  // namespace

void flange_twist_jacobian(const RobotModel& model, const PointMass& payload,
                           const ParameterVector& params, const Vector6d& joints,
                           Pose<double>* world_T_flange, TwistJacobian* jacobian) {
  const double* x = params.data();
  const Vector6d q = model.joint_map.matrix * joints + model.joint_map.offset;
  std::array<double, kJointCount> theta_u;
  theta_u[0] = x[scale_param(1)] * q[0] + model.mdh[0].theta_offset;
  for (int link = 2; link <= kJointCount; ++link)
    theta_u[link - 1] = x[scale_param(link)] * q[link - 1] + x[link_param(link, 2)];

  const FixedAngles fixed = fixed_angles(x);
  JointTrig trig_u;
  sin_cos(x[5] + theta_u[0], &trig_u.s[0], &trig_u.c[0]);
  for (int k = 1; k < kJointCount; ++k) sin_cos(theta_u[k], &trig_u.s[k], &trig_u.c[k]);
  const std::array<Pose<double>, kJointCount> Fu = chain(model, x, fixed, trig_u);
  const TorqueGeometry torque = torque_geometry(model, payload, Fu);
  Vector6d c = Vector6d::Zero();  // c[k]: compliance of joint k+1 (joint 1 has none)
  JointTrig trig_d = trig_u;      // θd_k = θu_k + c_k·τ_k
  for (int k = 1; k < kJointCount; ++k) {
    c[k] = x[compliance_param(k + 1)];
    if (c[k] != 0.0)
      sin_cos_shifted(trig_u.s[k], trig_u.c[k], c[k] * torque.tau[k], &trig_d.s[k], &trig_d.c[k]);
  }
  const bool compliant = !c.isZero(0.0);
  const std::array<Pose<double>, kJointCount> Fd = compliant ? chain(model, x, fixed, trig_d) : Fu;
  if (world_T_flange) *world_T_flange = Fd[kJointCount - 1];
  if (!jacobian) return;

  // J = G + Z·D: G the parameters' own elementary twists in the deflected chain, Z the joint
  // twists (o_j × z_j; z_j), D = dθd/dξ = dθu/dξ + diag(c)·dτ/dξ (+ τ_j for ξ = c_j).
  Eigen::Matrix<double, 6, kJointCount> Z;
  for (int j = 0; j < kJointCount; ++j) Z.col(j) = rotation_twist(Fd[j].R.col(2), Fd[j].p);
  TwistJacobian& G = *jacobian;
  G.setZero();
  Eigen::Matrix<double, kJointCount, kParameterCount> D;
  D.setZero();
  // dτ/dθu_j: rotation of frames ≥ j about z_j.
  Eigen::Matrix<double, kJointCount, kJointCount> dtau_dtheta;
  if (compliant)
    for (int j = 0; j < kJointCount; ++j)
      dtau_dtheta.col(j) = torque.rotation(Fu[j].R.col(2), Fu[j].p, j);

  // Base: translations along the world axes, rotations about x, Rot_x(α)·y and z_1 through o_1.
  const Vector3d base_axes[3] = {Vector3d::UnitX(), fixed.R_base_xy.col(1), Fd[0].R.col(2)};
  for (int i = 0; i < 3; ++i) {
    G.col(i) = translation_twist(Vector3d::Unit(i));
    G.col(3 + i) = rotation_twist(base_axes[i], Fd[0].p);
    if (compliant) D.col(3 + i) = c.cwiseProduct(torque.rotation(base_axes[i], Fu[0].p, 0));
  }
  for (int link = 2; link <= kJointCount; ++link) {
    const int f = link - 1, prev = link - 2;  // 0-based frames Φ_link and Φ_{link-1}
    const int ia = link_param(link, 0), i_a = link_param(link, 1), it = link_param(link, 2),
              id = link_param(link, 3);
    G.col(ia) = rotation_twist(Fd[prev].R.col(0), Fd[prev].p);
    G.col(i_a) = translation_twist(Fd[prev].R.col(0));
    G.col(id) = translation_twist(Fd[f].R.col(2));
    D(f, it) = 1.0;
    if (compliant) {
      D.col(ia) = c.cwiseProduct(torque.rotation(Fu[prev].R.col(0), Fu[prev].p, f));
      D.col(i_a) = c.cwiseProduct(torque.translation(Fu[prev].R.col(0), f));
      D.col(id) = c.cwiseProduct(torque.translation(Fu[f].R.col(2), f));
      D.col(it) += c.cwiseProduct(dtau_dtheta.col(f));
    }
    D(f, compliance_param(link)) = torque.tau[f];
  }
  for (int joint = 1; joint <= kJointCount; ++joint) {
    const int i = scale_param(joint);
    D(joint - 1, i) = q[joint - 1];
    if (compliant) D.col(i) += q[joint - 1] * c.cwiseProduct(dtau_dtheta.col(joint - 1));
  }
  G.noalias() += Z.lazyProduct(D);  // coefficient-wise: too small for a blocked GEMM
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
