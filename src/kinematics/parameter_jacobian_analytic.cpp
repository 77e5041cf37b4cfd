#include <Eigen/Geometry>

#include "robcal/kinematics/parameter_jacobian.hpp"

#include "angle_shift.hpp"

namespace robcal {
namespace {

using Eigen::Vector3d;

/// sin and cos of one angle (the compiler merges them into one sincos call).
void sin_cos(double angle, double* s, double* c) {
  *s = std::sin(angle);
  *c = std::cos(angle);
}

/// World frames Φ1..Φ6 for link angles given by their sin and cos, composed column by column:
/// Rot_x(α)·Trans_x(a) mixes the previous y, z axes and moves along the previous x;
/// Rot_z(θ)·Trans_z(d) mixes the new x, y and moves along the new z (docs/method/02-frames.md §3).
std::array<Pose<double>, kJointCount> chain(const RobotModel& model, const double* x,
                                            const ParameterTrig& f,
                                            const std::array<double, kJointCount>& s,
                                            const std::array<double, kJointCount>& c) {
  std::array<Pose<double>, kJointCount> F;
  F[0].R.col(0) = c[0] * f.R_base_xy.col(0) + s[0] * f.R_base_xy.col(1);
  F[0].R.col(1) = c[0] * f.R_base_xy.col(1) - s[0] * f.R_base_xy.col(0);
  F[0].R.col(2) = f.R_base_xy.col(2);
  F[0].p = Vector3d(x[0], x[1], model.mdh[0].d + x[2]);
  for (int k = 1; k < kJointCount; ++k) {
    const int link = k + 1;
    const Eigen::Matrix3d& P = F[k - 1].R;
    const Vector3d y = f.ca[k] * P.col(1) + f.sa[k] * P.col(2);
    const Vector3d z = f.ca[k] * P.col(2) - f.sa[k] * P.col(1);
    F[k].R.col(0) = c[k] * P.col(0) + s[k] * y;
    F[k].R.col(1) = c[k] * y - s[k] * P.col(0);
    F[k].R.col(2) = z;
    F[k].p = F[k - 1].p + x[link_param(link, 1)] * P.col(0) + x[link_param(link, 3)] * z;
  }
  return F;
}

/// Undeflected link angles θu_1..θu_6 (θ_1 with the base γ) of model joint values q, the
/// periodic errors (`basis`: periodic_basis of each q; `motor_basis`: motor_periodic_basis) and
/// the backlash (`approach`: the model joints' sides) included.
std::array<double, kJointCount> undeflected_angles(const RobotModel& model, const double* x,
                                                   const Vector6d& q, const PeriodicBasis& basis,
                                                   const PeriodicBasis& motor_basis,
                                                   const Vector6d& approach) {
  std::array<double, kJointCount> theta;
  theta[0] = x[scale_param(1)] * q[0] + model.mdh[0].theta_offset + x[5];
  for (int link = 2; link <= kJointCount; ++link)
    theta[link - 1] = x[scale_param(link)] * q[link - 1] + x[link_param(link, 2)];
  for (int joint = 1; joint <= kJointCount; ++joint)
    for (int k = 0; k < kPeriodicPerJoint; ++k)
      theta[joint - 1] += x[periodic_param(joint, 1, false) + k] * basis[joint - 1][k] +
                          x[motor_periodic_param(joint, 1, false) + k] * motor_basis[joint - 1][k];
  for (int joint = 1; joint <= kJointCount; ++joint)
    theta[joint - 1] += backlash_shift(x, approach[joint - 1], joint);
  return theta;
}

/// The rotation from the frame the robot file gives gravity in to the world: identity, or for
/// gravity given in the base frame the base rotation R_xy(α, β)·Rot_z(γ)
/// (docs/method/03-error-model.md §7).
Eigen::Matrix3d gravity_frame(const RobotModel& model, const ParameterTrig& f, const double* x) {
  if (!model.gravity_in_base) return Eigen::Matrix3d::Identity();
  return f.R_base_xy * Eigen::AngleAxisd(x[5], Vector3d::UnitZ()).toRotationMatrix();
}

}  // namespace

ParameterTrig parameter_trig(const ParameterVector& params) {
  const double* x = params.data();
  ParameterTrig f;
  for (int link = 2; link <= kJointCount; ++link)
    sin_cos(x[link_param(link, 0)], &f.sa[link - 1], &f.ca[link - 1]);
  double sa, ca, sb, cb;
  sin_cos(x[3], &sa, &ca);
  sin_cos(x[4], &sb, &cb);
  f.R_base_xy << cb, 0, sb, sa * sb, ca, -sa * cb, -ca * sb, sa, ca * cb;
  return f;
}

PreparedConfiguration prepare_configuration(const RobotModel& model,
                                            const ParameterVector& reference,
                                            const Vector6d& joints, const RowConditions& row) {
  PreparedConfiguration out;
  out.temperature_rise_k = row.temperature_rise_k;
  out.warmup_fraction = row.warmup_fraction;
  out.q = model.joint_map.matrix * joints + model.joint_map.offset;
  for (int k = 0; k < kJointCount; ++k) {
    out.basis[k] = periodic_basis(out.q[k]);
    out.motor_basis[k] = motor_periodic_basis(model, k + 1, out.q[k]);
  }
  for (int joint = 1; joint <= kJointCount; ++joint)
    out.approach[joint - 1] =
        model_approach(model, row.approach ? row.approach->data() : nullptr, joint);
  out.theta =
      undeflected_angles(model, reference.data(), out.q, out.basis, out.motor_basis, out.approach);
  for (int k = 0; k < kJointCount; ++k) sin_cos(out.theta[k], &out.s[k], &out.c[k]);
  return out;
}

FlangeRegressor::FlangeRegressor(const RobotModel& model, const PointMass& payload,
                                 const ParameterVector& params, const ParameterTrig& trig,
                                 const PreparedConfiguration& configuration)
    : q_(configuration.q),
      c_(Vector6d::Zero()),
      basis_(configuration.basis),
      motor_basis_(configuration.motor_basis),
      approach_(configuration.approach),
      temperature_rise_k_(configuration.temperature_rise_k),
      R_base_xy_(trig.R_base_xy) {
  // The chain at the row's temperature (§8): the warm lengths; jacobian() applies the chain rule.
  std::array<double, kParameterCount> warm;
  const double* x = params.data();
  const RowConditions row{nullptr, temperature_rise_k_, configuration.warmup_fraction};
  for (int link = 2; link <= kJointCount; ++link) {
    cold_a_[link - 1] = x[link_param(link, 1)];
    cold_d_[link - 1] = x[link_param(link, 3)];
    warmup_per_length_[link - 1] = row.warmup_fraction * inverse_link_length(model, link);
    growth_[link - 1] = 1 + x[expansion_param(link)] * temperature_rise_k_ +
                        x[warmup_param(link)] * warmup_per_length_[link - 1];
  }
  if (thermal_active(x, row)) {
    warm = warm_parameters(model, x, row);
    x = warm.data();
  }
  const std::array<double, kJointCount> theta_u =
      undeflected_angles(model, x, q_, basis_, motor_basis_, approach_);
  std::array<double, kJointCount> s_u, c_u;
  for (int k = 0; k < kJointCount; ++k)
    sin_cos_shifted(configuration.s[k], configuration.c[k], theta_u[k] - configuration.theta[k],
                    &s_u[k], &c_u[k]);
  undeflected_ = chain(model, x, trig, s_u, c_u);

  // Gravity torques (docs/method/03-error-model.md §3): suffix sums of the bodies' first moments
  // and masses.
  const std::array<Pose<double>, kJointCount>& F = undeflected_;
  // Gravity in the world (m/s²), tilted by the gravity group (§11), and the world axes of the
  // tilts: a, then b turned about a by tilt_a.
  const Eigen::Matrix3d G = gravity_frame(model, trig, x);
  const Vector3d g = G * tilted_gravity(model, x);
  const std::array<Vector3d, 2> axes = gravity_tilt_axes(model.gravity_m_s2);
  gravity_axes_.col(0) = G * axes[0];
  gravity_axes_.col(1) = G * turned(axes[1], axes[0], x[kGravityTiltA]);
  C_[kJointCount].setZero();
  M_[kJointCount] = 0;
  for (int j = kJointCount - 1; j >= 0; --j) {
    const PointMass& body = model.link_masses[j];
    C_[j] = C_[j + 1] + body.mass_kg * (F[j] * body.cog_mm);
    M_[j] = M_[j + 1] + body.mass_kg;
    if (j == kJointCount - 1) {  // the payload is lumped with link 6
      C_[j] += payload.mass_kg * (F[j] * payload.cog_mm);
      M_[j] += payload.mass_kg;
    }
  }
  for (int k = 0; k < kJointCount; ++k) {
    const Vector3d z = F[k].R.col(2);
    const Vector3d v = C_[k] - M_[k] * F[k].p;
    const Vector3d w = v.cross(g);
    h_.col(k) = g.cross(z);
    a_.col(k) = z.cross(w) + v.cross(h_.col(k));
    tau_[k] = z.dot(w);
  }

  std::array<double, kJointCount> s_d = s_u, c_d = c_u;  // θd_k = θu_k + c_k·τ_k
  for (int k = 0; k < kJointCount; ++k) {
    c_[k] = x[compliance_param(k + 1)];
    if (c_[k] != 0.0) sin_cos_shifted(s_u[k], c_u[k], c_[k] * tau_[k], &s_d[k], &c_d[k]);
  }
  compliant_ = !c_.isZero(0.0);
  gravity_turns_with_base_ = model.gravity_in_base;
  deflected_ = compliant_ ? chain(model, x, trig, s_d, c_d) : undeflected_;
}

template <int K>
void FlangeRegressor::jacobian(const Eigen::Matrix<double, K, 6>& P,
                               Eigen::Matrix<double, K, kParameterCount>* out) const {
  using Rows = Eigen::Matrix<double, K, 1>;
  const auto PL = P.template leftCols<3>();   // on the twist's linear part
  const auto PR = P.template rightCols<3>();  // on its angular part
  const std::array<Pose<double>, kJointCount>& Fu = undeflected_;
  const std::array<Pose<double>, kJointCount>& Fd = deflected_;
  // An elementary motion of the frames ≥ f (and the bodies they carry) changes τ_k (k ≥ 1) by:
  // rotation ω = u about a line through p: u · a_k when frame k moves (k ≥ f),
  // (u × (C_f − M_f·p)) · h_k when it does not; translation u: M_f·(u · h_k) when frame k does
  // not move, else 0. Scaled by the compliances, the change of the deflected joint angles.
  const auto rotation = [&](const Vector3d& u, const Vector3d& p, int f) {
    const Vector3d e = u.cross(C_[f] - M_[f] * p);
    Vector6d d;
    for (int k = 0; k < kJointCount; ++k)
      d[k] = c_[k] * (k >= f ? u.dot(a_.col(k)) : e.dot(h_.col(k)));
    return d;
  };
  const auto translation = [&](const Vector3d& u, int f) {
    Vector6d d = Vector6d::Zero();
    for (int k = 0; k < f; ++k) d[k] = c_[k] * M_[f] * u.dot(h_.col(k));
    return d;
  };

  // P·J = P·G + (P·Z)·D: G the parameters' own elementary twists in the deflected chain, Z the
  // joint twists (o_j × z_j; z_j), D = dθd/dξ = dθu/dξ + diag(c)·dτ/dξ (+ τ_j for ξ = c_j).
  Eigen::Matrix<double, K, kJointCount> PZ;
  for (int j = 0; j < kJointCount; ++j)
    PZ.col(j) = PL * Fd[j].p.cross(Fd[j].R.col(2)) + PR * Fd[j].R.col(2);
  Eigen::Matrix<double, K, kParameterCount>& J = *out;
  const auto rotation_column = [&](const Vector3d& u, const Vector3d& p) -> Rows {
    return PL * p.cross(u) + PR * u;
  };
  // dτ/dθu_j: rotation of frames ≥ j about z_j.
  Eigen::Matrix<double, kJointCount, kJointCount> dtheta;  // diag(c)·dτ/dθu
  if (compliant_)
    for (int j = 0; j < kJointCount; ++j) dtheta.col(j) = rotation(Fu[j].R.col(2), Fu[j].p, j);

  // Base: translations along the world axes, rotations about x, Rot_x(α)·y and z_1 through o_1.
  // Gravity given in the base frame turns with the base: the torques do not change (§7).
  const Vector3d base_axes[3] = {Vector3d::UnitX(), R_base_xy_.col(1), Fd[0].R.col(2)};
  for (int i = 0; i < 3; ++i) {
    J.col(i) = PL.col(i);
    J.col(3 + i) = rotation_column(base_axes[i], Fd[0].p);
    if (compliant_ && !gravity_turns_with_base_)
      J.col(3 + i).noalias() += PZ * rotation(base_axes[i], Fu[0].p, 0);
  }
  J.col(kJoint1Compliance) = tau_[0] * PZ.col(0);
  // Gravity turned by ω changes the torques as the whole robot turned by −ω under fixed gravity
  // (§11); the chain itself does not move.
  for (int k = 0; k < 2; ++k) {
    if (compliant_)
      J.col(kGravityTiltA + k).noalias() = -(PZ * rotation(gravity_axes_.col(k), Fu[0].p, 0));
    else
      J.col(kGravityTiltA + k).setZero();
  }
  for (int link = 2; link <= kJointCount; ++link) {
    const int f = link - 1, prev = link - 2;  // 0-based frames Φ_link and Φ_{link-1}
    const int ia = link_param(link, 0), i_a = link_param(link, 1), it = link_param(link, 2),
              id = link_param(link, 3);
    J.col(ia) = rotation_column(Fd[prev].R.col(0), Fd[prev].p);
    J.col(i_a) = PL * Fd[prev].R.col(0);
    J.col(id) = PL * Fd[f].R.col(2);
    J.col(it) = PZ.col(f);
    J.col(compliance_param(link)) = tau_[f] * PZ.col(f);
    if (compliant_) {
      J.col(ia).noalias() += PZ * rotation(Fu[prev].R.col(0), Fu[prev].p, f);
      J.col(i_a).noalias() += PZ * translation(Fu[prev].R.col(0), f);
      J.col(id).noalias() += PZ * translation(Fu[f].R.col(2), f);
      J.col(it).noalias() += PZ * dtheta.col(f);
    }
  }
  // Scales, periodic errors (of the joint and of its motor) and backlash move θu_j by q_j, by the
  // periodic basis at q_j or r_j·q_j and by −s_j/2: the column of θu_j (joint twist, plus the
  // deflections it causes) times that factor.
  for (int joint = 1; joint <= kJointCount; ++joint) {
    Rows joint_column = PZ.col(joint - 1);
    if (compliant_) joint_column.noalias() += PZ * dtheta.col(joint - 1);
    J.col(scale_param(joint)) = q_[joint - 1] * joint_column;
    for (int k = 0; k < kPeriodicPerJoint; ++k) {
      J.col(periodic_param(joint, 1, false) + k) = basis_[joint - 1][k] * joint_column;
      J.col(motor_periodic_param(joint, 1, false) + k) = motor_basis_[joint - 1][k] * joint_column;
    }
    J.col(backlash_param(joint)) = (-0.5 * approach_[joint - 1]) * joint_column;
  }
  // Thermal and warm-up groups: the columns above are those of the warm lengths a'_i = a_i·g_i,
  // d'_i = d_i·g_i (g_i = 1 + e_i·ΔT + φ·w_i/L_i); da'/da = g_i, da'/de_i = a_i·ΔT, da'/dw_i =
  // a_i·φ/L_i (likewise d).
  for (int link = 2; link <= kJointCount; ++link) {
    const int i_a = link_param(link, 1), id = link_param(link, 3);
    const Rows cold_column = cold_a_[link - 1] * J.col(i_a) + cold_d_[link - 1] * J.col(id);
    J.col(expansion_param(link)) = temperature_rise_k_ * cold_column;
    J.col(warmup_param(link)) = warmup_per_length_[link - 1] * cold_column;
    J.col(i_a) *= growth_[link - 1];
    J.col(id) *= growth_[link - 1];
  }
}

template void FlangeRegressor::jacobian<1>(const Eigen::Matrix<double, 1, 6>&,
                                           Eigen::Matrix<double, 1, kParameterCount>*) const;
template void FlangeRegressor::jacobian<3>(const Eigen::Matrix<double, 3, 6>&,
                                           Eigen::Matrix<double, 3, kParameterCount>*) const;
template void FlangeRegressor::jacobian<6>(const Eigen::Matrix<double, 6, 6>&,
                                           Eigen::Matrix<double, 6, kParameterCount>*) const;

void flange_twist_jacobian(const RobotModel& model, const PointMass& payload,
                           const ParameterVector& params, const Vector6d& joints,
                           Pose<double>* world_T_flange, TwistJacobian* jacobian,
                           const RowConditions& row) {
  const FlangeRegressor regressor(model, payload, params, parameter_trig(params),
                                  prepare_configuration(model, params, joints, row));
  if (world_T_flange) *world_T_flange = regressor.flange();
  if (jacobian) regressor.jacobian<6>(Eigen::Matrix<double, 6, 6>::Identity(), jacobian);
}

PositionJacobian point_jacobian_from_twist(const TwistJacobian& twist, const Eigen::Vector3d& p) {
  PositionJacobian J;
  // v + ω × p = v − p × ω
  J.row(0) = twist.row(0) + p.z() * twist.row(4) - p.y() * twist.row(5);
  J.row(1) = twist.row(1) + p.x() * twist.row(5) - p.z() * twist.row(3);
  J.row(2) = twist.row(2) + p.y() * twist.row(3) - p.x() * twist.row(4);
  return J;
}

Eigen::Matrix<double, 3, 6> point_output_map(const Eigen::Vector3d& p) {
  Eigen::Matrix<double, 3, 6> P;
  // dp = v + ω × p = v − [p]× ω
  P << 1, 0, 0, 0, p.z(), -p.y(), 0, 1, 0, -p.z(), 0, p.x(), 0, 0, 1, p.y(), -p.x(), 0;
  return P;
}

void target_position_jacobian(const RobotModel& model, const PointMass& payload,
                              const ParameterVector& params, const Vector6d& joints,
                              const Eigen::Vector3d& target_flange_mm, Eigen::Vector3d* position_mm,
                              PositionJacobian* jacobian, const RowConditions& row) {
  const FlangeRegressor regressor(model, payload, params, parameter_trig(params),
                                  prepare_configuration(model, params, joints, row));
  const Eigen::Vector3d p = regressor.flange() * target_flange_mm;
  if (position_mm) *position_mm = p;
  if (jacobian) regressor.jacobian<3>(point_output_map(p), jacobian);
}

}  // namespace robcal
