#pragma once
/// \file
/// Derivatives of measured quantities with respect to the robot's parameter vector (the
/// identification Jacobian's blocks, docs/method/04-identification.md §1–§2), in internal units (mm
/// per mm, mm per rad).
///
/// Two implementations of the same derivative: the analytic kinematic regressor (fast, used by
/// the identification) and automatic differentiation through the templated FK (the reference
/// the regressor is checked against in the tests).

#include <Eigen/Core>
#include <array>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/model/parameters.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

using PositionJacobian = Eigen::Matrix<double, 3, kParameterCount>;

/// Spatial (world-frame) twist Jacobian of the flange: column ξ is (v; ω) such that a point p
/// rigidly attached to the flange moves by dp/dξ = v + ω × p (world, mm per unit of ξ) and the
/// flange rotates by ω (rad per unit of ξ, world axes).
using TwistJacobian = Eigen::Matrix<double, 6, kParameterCount>;

/// World pose of the flange and its twist Jacobian with respect to all kParameterCount
/// parameters, analytically (the kinematic regressor):
/// - each geometric parameter is an elementary motion along the chain: a base translation, a
///   rotation about a base axis, a link's Rot_x(α_i) about x_{i-1} through o_{i-1}, Trans_x(a_i)
///   along x_{i-1}, Trans_z(d_i) along z_i;
/// - joint offsets, scales, periodic errors (of the joints and of their motors), backlash and
///   compliances act through the joint angles θ_i,
///   whose column is the joint twist (o_i × z_i; z_i) of the deflected chain;
/// - with compliance, θ_i = θu_i + c_i·τ_i(θu, params) (docs/method/03-error-model.md §3), so every
/// parameter also
///   moves θ_i through the gravity torque τ_i; its derivative follows from the same elementary
///   motions applied to τ_i = z_i · ((Σ_{j≥i} m_j (c_j − o_i)) × g) in the undeflected chain.
/// - the thermal and warm-up groups scale a_i, d_i by (1 + e_i·ΔT + φ·w_i/L_i): the chain is
///   evaluated with the warm lengths, whose columns the chain rule turns into those of a_i, d_i,
///   e_i and w_i (§8, §10).
/// Cost: two chain evaluations plus O(parameters × joints) dot products, ≈1 µs.
/// `row`: the row's approach and temperature (forward_kinematics.hpp RowConditions).
void flange_twist_jacobian(const RobotModel& model, const PointMass& payload,
                           const ParameterVector& params, const Vector6d& joints,
                           Pose<double>* world_T_flange, TwistJacobian* jacobian,
                           const RowConditions& row = {});

/// The sines and cosines that depend on the parameters alone (link twists α_2..α_6, base α and
/// β): computed once per parameter vector, shared by every configuration.
struct ParameterTrig {
  std::array<double, kJointCount> ca{}, sa{};  ///< index k = link k+1 (k ≥ 1)
  Eigen::Matrix3d R_base_xy;                   ///< Rot_x(α_b)·Rot_y(β_b)
};
ParameterTrig parameter_trig(const ParameterVector& params);

/// A configuration prepared for many evaluations at nearby parameter vectors (the iterations of
/// an identification): its model joint values and its link angles θ_1..θ_6 (θ_1 with the base
/// γ) with their sines and cosines at reference parameters. Near the reference the link angles
/// move by small shifts (joint offset and scale errors), whose sine and cosine follow from a
/// short series: an evaluation makes no trigonometric call.
using PeriodicBasis = std::array<std::array<double, kPeriodicPerJoint>, kJointCount>;
struct PreparedConfiguration {
  Vector6d q = Vector6d::Zero();  ///< model joint values (joint map applied)
  PeriodicBasis basis{};          ///< periodic_basis of each q (the periodic errors' factors)
  PeriodicBasis motor_basis{};    ///< motor_periodic_basis of each q (the motors' factors)
  /// Each model joint's side (model_approach: +1 below, −1 above, 0 unknown), the backlash's
  /// factor.
  Vector6d approach = Vector6d::Ones();
  double temperature_rise_k = 0;  ///< the thermal group's ΔT (K)
  double warmup_fraction = 0;     ///< the warm-up group's φ (RowConditions)
  std::array<double, kJointCount> theta{}, s{}, c{};
};
PreparedConfiguration prepare_configuration(const RobotModel& model,
                                            const ParameterVector& reference,
                                            const Vector6d& joints, const RowConditions& row = {});

/// The analytic regressor in two steps, for residuals whose derivative depends on the flange
/// pose: construction evaluates the chain at a prepared configuration (the flange pose), then
/// `jacobian(P)` gives the rows P·J of the flange twist Jacobian J for an output map P (K × 6):
/// the derivative of any quantity that a flange twist ξ changes by P·ξ (P = I: the twist
/// Jacobian; P = [I −[p]×]: a world point p carried by the flange; a distance or a pose
/// residual). Projecting before the joint-coupling product Z·D costs K/6 of forming J.
/// Same values as flange_twist_jacobian to rounding.
class FlangeRegressor {
 public:
  FlangeRegressor(const RobotModel& model, const PointMass& payload, const ParameterVector& params,
                  const ParameterTrig& trig, const PreparedConfiguration& configuration);
  [[nodiscard]] const Pose<double>& flange() const { return deflected_[kJointCount - 1]; }
  /// K = 1, 3 or 6.
  template <int K>
  void jacobian(const Eigen::Matrix<double, K, 6>& P,
                Eigen::Matrix<double, K, kParameterCount>* out) const;

 private:
  Vector6d q_, c_;  ///< model joint values; compliances (c_[0]: joint 1's, §7)
  PeriodicBasis basis_, motor_basis_;
  Vector6d approach_;
  /// ΔT, and per link (index link − 1) the cold a_i, d_i, their growth 1 + e_i·ΔT + φ·w_i/L_i and
  /// the warm-up's factor φ/L_i.
  double temperature_rise_k_ = 0;
  std::array<double, kJointCount> cold_a_{}, cold_d_{}, growth_{}, warmup_per_length_{};
  bool compliant_ = false;
  bool gravity_turns_with_base_ = false;  ///< RobotModel::gravity_in_base
  /// World axes of the gravity group's tilts rx, ry (docs/method/03-error-model.md §11).
  Eigen::Matrix<double, 3, 2> gravity_axes_;
  Eigen::Matrix3d R_base_xy_;
  std::array<Pose<double>, kJointCount> undeflected_, deflected_;
  /// Gravity torques of the undeflected chain and what their derivatives need
  /// (docs/method/03-error-model.md §3 in world form): v_k = Σ_{j≥k} m_j (c_j − o_k), τ_k = z_k ·
  /// (v_k × g), a_k = z_k × (v_k × g) + v_k × (g × z_k), h_k = g × z_k; suffix first moments C_k
  /// and masses M_k of the bodies carried by frame k.
  std::array<double, kJointCount> tau_{};
  Eigen::Matrix<double, 3, kJointCount> a_, h_;
  std::array<Eigen::Vector3d, kJointCount + 1> C_;
  std::array<double, kJointCount + 1> M_{};
};

/// World position of a flange-frame point and its derivative with respect to all parameters,
/// from the analytic twist Jacobian: dp/dξ = v_ξ + ω_ξ × p.
void target_position_jacobian(const RobotModel& model, const PointMass& payload,
                              const ParameterVector& params, const Vector6d& joints,
                              const Eigen::Vector3d& target_flange_mm, Eigen::Vector3d* position_mm,
                              PositionJacobian* jacobian, const RowConditions& row = {});

/// The output map [I −[p]×] of a world point p carried by the flange (its change under a
/// flange twist), for FlangeRegressor::jacobian.
Eigen::Matrix<double, 3, 6> point_output_map(const Eigen::Vector3d& p);

/// Position rows of a twist Jacobian for the world point p: J_v − [p]× J_ω.
PositionJacobian point_jacobian_from_twist(const TwistJacobian& twist, const Eigen::Vector3d& p);

/// World position of a flange-frame point and its derivative with respect to all
/// kParameterCount parameters, by automatic differentiation through the templated FK
/// (exact; the reference the analytic regressor is checked against).
void target_position_jacobian_autodiff(const RobotModel& model, const PointMass& payload,
                                       const ParameterVector& params, const Vector6d& joints,
                                       const Eigen::Vector3d& target_flange_mm,
                                       Eigen::Vector3d* position_mm, PositionJacobian* jacobian,
                                       const RowConditions& row = {});

}  // namespace robcal
