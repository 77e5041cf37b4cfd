#pragma once
/// \file
/// The calibrated robot prepared for inverse kinematics: constants of the error model
/// (docs/method/02-frames.md §5, 03-error-model.md §1) precomputed once in an immutable
/// CalibratedChain; a solve evaluates the TCP pose into a per-call ChainState and, only when it
/// needs a step, the exact joint Jacobian from what that evaluation left there.
///
/// Jacobian (world frame, rows v then ω, columns = controller joints, mm/rad and rad/rad):
///   with θu the undeflected link angles (θu = scale·q + offset + δθ(q) + δμ(r·q), δθ the
///   periodic joint errors, δμ the motors'), θ = θu + c·τ(θu) the deflected ones and q = M·j +
///   offset the model angles from controller joints j,
///   J = J_θ · (I + diag(c)·∂τ/∂θu) · diag(scale + δθ'(q) + r·δμ'(r·q)) · M,
/// J_θ the geometric Jacobian of the deflected chain (column k: [z_k × (p_tcp − o_k); z_k]).
/// The gravity torque τ_i = z_i · (V_i × g), with M_i, C_i the mass and first moment of links
/// i..6 and the payload (world frame) and V_i = C_i − M_i·o_i, has the derivatives
///   ∂τ_i/∂θu_k = y_m · w_n,  m = max(i, k), n = min(i, k),  y = z × V,  w = g × z
/// (from d z_i = z_k × z_i, d V_i = z_k × V_i for k ≤ i, d V_i = z_k × V_k for k > i: for
/// k ≤ i the triple products sum to z_k · (y_i × g) by the Jacobi identity, for k > i to
/// y_k · w_i; one dot product per entry).
/// Checked against ceres::Jet autodiff of `flange_pose<T>` and finite differences in the tests.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// Immutable constants of one calibrated robot with one payload and one tool.
struct CalibratedChain {
  Eigen::Matrix3d base_R_xy = Eigen::Matrix3d::Identity();  ///< Rot_x(α_b)·Rot_y(β_b)
  Eigen::Vector3d base_p = Eigen::Vector3d::Zero();         ///< (x_b, y_b, d1 + z_b)
  double base_gamma = 0;
  std::array<double, kJointCount> cos_alpha{}, sin_alpha{}, a{}, d{};  ///< links 2..6 at [1..5]
  std::array<double, kJointCount> theta_offset{};  ///< link 1: the model's θ offset; + backlash
  std::array<double, kJointCount> scale{};
  /// Periodic error coefficients of each joint (jointI.periodicH.cos|sin, rad).
  std::array<std::array<double, kPeriodicPerJoint>, kJointCount> periodic{};
  std::array<bool, kJointCount> has_periodic{};
  /// Motor-angle periodic error coefficients of each joint (jointI.motor_periodicH.cos|sin, rad)
  /// and the gear ratio r whose motor angle r·q they follow (docs/method/03-error-model.md §9).
  std::array<std::array<double, kPeriodicPerJoint>, kJointCount> motor_periodic{};
  std::array<bool, kJointCount> has_motor_periodic{};
  std::array<double, kJointCount> gear_ratio{};
  std::array<double, kJointCount> compliance{};  ///< [0]: joint 1's (opt-in, §7)
  bool compliant = false;
  std::array<double, kJointCount> mass{};             ///< link 6 includes the payload
  std::array<Eigen::Vector3d, kJointCount> moment{};  ///< m·CoG in the link frame (kg·mm)
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< world, m/s² (base-frame gravity turned)
  Matrix6d joint_map = Matrix6d::Identity();
  Vector6d joint_offset = Vector6d::Zero();
  bool map_identity = true;
  Pose<double> flange_T_tcp;
};

/// Per-call workspace: what one pose evaluation leaves for the Jacobian at the same joints,
/// and the undeflected link angles with their cosines and sines, from which the next
/// evaluation of an iteration (a small step away) gets its own by the angle-addition formulas
/// instead of calling cos and sin. A default-constructed state starts afresh.
struct ChainState {
  std::array<Pose<double>, kJointCount> frames;               ///< deflected world frames Φ1..Φ6
  std::array<Eigen::Vector3d, kJointCount> z_undeflected, V;  ///< axes and V_i before deflection
  Eigen::Vector3d tcp_p;
  bool has_angles = false;
  std::array<double, kJointCount> theta{}, cos_theta{}, sin_theta{};  ///< θu (θ1 with γ_base)
  std::array<double, kJointCount> rate{};  ///< dθu/dq: scale + the periodic errors' slopes
};

/// sin θ and cos θ from a table at the multiples of 2π/256 and the angle-addition series for
/// the rest (|δ| ≤ π/256, inside sin_cos_shifted's series range): within a few ulp of
/// std::sin and std::cos, without their calls, which took ~40 % of a fresh chain evaluation.
void table_sin_cos(double theta, double* s, double* c);

/// Precomputes the chain for `params` (docs/method/03-error-model.md §1 layout), the payload
/// carried and the tool, every target reached at `row`: each joint approached from `row.approach`
/// (+1 below, −1 above, 0 unknown; null: from below, the programs' practice), so the backlash shift
/// −s·b/2 is constant and joins the joint's θ offset (§6), and at `row.temperature_rise_k`, so
/// the links keep their warm lengths (§8).
CalibratedChain make_calibrated_chain(const RobotModel& model, const ParameterVector& params,
                                      const PointMass& payload, const Pose<double>& flange_T_tcp,
                                      const RowConditions& row = {});

/// World pose of the TCP for controller joints (rad), recording in `state` what
/// calibrated_jacobian needs. Equals flange_pose(model, payload, params, joints) · flange_T_tcp.
Pose<double> calibrated_tcp_pose(const CalibratedChain& chain, const Vector6d& joints,
                                 ChainState& state);

/// The joint Jacobian at the joints of the last calibrated_tcp_pose into `state`.
void calibrated_jacobian(const CalibratedChain& chain, const ChainState& state, Matrix6d& jacobian);

/// The change of the joint Jacobian along a joint motion `along` (rad), applied to `v`:
/// d/dt [J(j + t·along)·v] at t = 0, at the joints j of the last calibrated_tcp_pose into
/// `state`; with v = along, the second derivative (p̈, ω̇) of the TCP's motion, so that the pose
/// at j + along is the one at j moved by J·along + ½·(p̈, ω̇) to second order. For the rigid
/// deflected chain: with link angle rates δ = rate·(M·along), ν = rate·(M·v), link k − 1
/// turning at ω_{k−1} = Σ_{i<k} δ_i·z_i and origin o_k moving at ȯ_k = ȯ_{k−1} + ω_{k−1} ×
/// (o_k − o_{k−1}), the axes turn at ż_k = ω_{k−1} × z_k and, ṗ being the TCP's velocity,
///   d(J·v)/dt = Σ_k ν_k·(ż_k × (p − o_k) + z_k × (ṗ − ȯ_k), ż_k).
/// The compliance's own change (the deflection varying along the motion, up to ~3 % of the
/// whole) and the periodic errors' curvature (below 1e-3 of the rate for the joints' own; a
/// motor's, (H·r)² times its amplitude, can be comparable to the rate) are left out: this serves
/// Newton steps, whose answers the forward model verifies.
Vector6d calibrated_jacobian_derivative(const CalibratedChain& chain, const ChainState& state,
                                        const Vector6d& along, const Vector6d& v);

/// Convenience: the pose, and the Jacobian too when `jacobian` is not null.
Pose<double> calibrated_tcp_pose(const CalibratedChain& chain, const Vector6d& joints,
                                 Matrix6d* jacobian = nullptr);

}  // namespace robcal
