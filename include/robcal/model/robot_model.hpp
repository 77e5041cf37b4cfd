#pragma once
/// \file
/// The immutable description of a six-revolute serial robot (docs/method/02-frames.md §3–§7,
/// 03-error-model.md §3): nominal Modified-DH table, joint limits, controller joint map, link
/// masses and gravity. Algorithms never modify a model; per-call state lives in their own
/// workspaces.

#include <Eigen/Core>
#include <array>
#include <string>

#include "robcal/model/parameters.hpp"

namespace robcal {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using ParameterVector = Eigen::Matrix<double, kParameterCount, 1>;

/// One row of a Modified DH table (Craig): A = Rot_x(alpha)·Trans_x(a)·Rot_z(theta)·Trans_z(d).
struct MdhRow {
  double alpha = 0;         ///< rad
  double a = 0;             ///< mm
  double theta_offset = 0;  ///< rad, added to the joint angle
  double d = 0;             ///< mm
};

/// A point mass: a link's (or a payload's) mass and centre of gravity in its own frame.
struct PointMass {
  double mass_kg = 0;
  Eigen::Vector3d cog_mm = Eigen::Vector3d::Zero();
};

/// How the robot's controller numbers its joints. Model joint angles (rad) are
/// q = matrix · j + offset, with j the controller's values (rad). A Fanuc reports J3 relative
/// to the horizontal, so the model's q3 = J3 + J2: matrix(2,1) = 1.
struct JointMap {
  Matrix6d matrix = Matrix6d::Identity();
  Vector6d offset = Vector6d::Zero();  ///< rad
  [[nodiscard]] bool is_identity() const { return matrix.isIdentity(0.0) && offset.isZero(0.0); }
  /// Model joint angles from controller joint values (both rad).
  [[nodiscard]] Vector6d to_model(const Vector6d& controller) const {
    return matrix * controller + offset;
  }
  /// Controller joint values from model joint angles (both rad).
  [[nodiscard]] Vector6d to_controller(const Vector6d& model) const;
};

/// Joint range in controller values, rad.
struct JointLimit {
  double lower = 0;
  double upper = 0;
};

/// Orientation convention a robot maker prints (the angles all describe R = Rz·Ry·Rx):
/// ABB and KUKA print (A=z, B=y, C=x); Fanuc prints (W=x, P=y, R=z).
enum class EulerConvention { ZyxABC, XyzWPR };

/// Immutable robot description. `nominal()` gives the parameter vector of the nominal robot
/// placed at the world origin (base parameters zero, compliance zero, scales one).
struct RobotModel {
  std::string name;
  std::string manufacturer;
  std::string source;   ///< where the numbers come from (data sheet, paper)
  double reach_mm = 0;  ///< the data sheet's reach, 0 when not given
  EulerConvention euler = EulerConvention::ZyxABC;

  std::array<MdhRow, kJointCount> mdh{};  ///< links 1..6; link 1 must have alpha = a = 0
  std::array<JointLimit, kJointCount> limits{};
  JointMap joint_map;
  std::array<PointMass, kJointCount> link_masses{};  ///< links 1..6, CoG in the link frame
  Eigen::Vector3d gravity_m_s2{0, 0, -9.81};         ///< in the world (measurement) frame, levelled
  /// True when gravity_m_s2 is in the robot's base frame (frame 1 at θ1 = 0, without the base
  /// γ), as a wall, ceiling or inclined mounting gives it (robot file `gravity_base_m_s2` or
  /// `mounting_deg`): it then turns with the base placement (docs/method/03-error-model.md §7).
  bool gravity_in_base = false;
  /// Temperature (°C) at which the link lengths hold (robot file `reference_temperature_c`,
  /// default 20 °C, ISO 1's reference for dimensional specifications): the thermal group scales
  /// a_i, d_i by (1 + e_i·(T − this)) (docs/method/03-error-model.md §8).
  double reference_temperature_c = 20;
  /// Motor turns per turn of each model joint (robot file `gear_ratio`, ~ or absent: unknown, 0):
  /// the motor-angle periodic group of a joint needs it (docs/method/03-error-model.md §9).
  std::array<double, kJointCount> gear_ratio{};
  /// Time constant τ (s) of the arm's first-order warm-up ΔT(t) = ΔT∞·(1 − exp(−t/τ)), for the
  /// warm-up group of rows that record a time but no temperature (robot file
  /// `warmup_time_constant_s`, IdentifyOptions::warmup_time_constant_s; default 30 min,
  /// docs/method/03-error-model.md §10).
  double warmup_time_constant_s = 1800;

  /// Nominal parameter vector (docs/method/03-error-model.md §1 layout, internal units).
  [[nodiscard]] ParameterVector nominal() const;

  /// True when the controller joint values are all inside the limits (with `tolerance` rad).
  [[nodiscard]] bool within_limits(const Vector6d& controller_joints,
                                   double tolerance = 1e-9) const;
};

}  // namespace robcal
