#pragma once
/// \file
/// Universal Robots' factory calibration (`calibration.conf`, section `[mounting]`), read as a
/// starting model and written from a calibrated one.
///
/// The file holds corrections to the nominal standard-DH table the controller knows from the
/// robot type (UR's published "DH parameters for calculations of kinematics and dynamics"):
///   delta_theta, delta_a, delta_d, delta_alpha = [ v1, …, v6 ]   (metres and radians),
/// one per joint, with `#` comments; other keys (joint_checksum, calibration_status,
/// joint_raw_offset, …) identify the joint hardware and are kept only as text. The controller's
/// model is the sum, nominal + delta (what its KinematicsInfo message reports), in UR's
/// standard DH with the joint values as DH angles:
///   base_T_flange = Π_i Rz(q_i + θ_i)·Tz(d_i)·Tx(a_i)·Rx(α_i).
/// The deltas can be large (metres along nearly parallel axes 2–4): the calibration moves the
/// common normals of those axes far out; the sum is exact all the same.
///
/// In robcal's Modified DH (model/parameters.hpp): DH link i's α_i and a_i are MDH link i+1's,
/// its θ_i and d_i MDH link i's; link 1's θ1 and d1 go to base.gamma and base.z (the robot
/// file's link 1 row holds the nominal part). Not representable: a6 and α6 (robcal's flange is
/// DH frame 6; UR's files have them 0) — refused when not 0. Written out from robcal: the base
/// placement x, y, alpha, beta (calibration.conf's base frame is on axis 1), the tool,
/// compliance, joint scales and periodic errors have no place (identify/model_exchange.hpp
/// names them); the robot's model must have the identity joint map.

#include <array>
#include <string>
#include <vector>

#include "robcal/model/robot_model.hpp"

namespace robcal {

/// The four delta rows of a calibration.conf, internal units (rad, mm).
struct UrCalibration {
  std::array<double, kJointCount> delta_theta{}, delta_a{}, delta_d{}, delta_alpha{};
  /// `calibration_status` when the file gives it (UR: 0 not initialized, 1 not linearised,
  /// 2 linearised), else -1.
  int calibration_status = -1;
  std::string file;  ///< where it was read from (named in errors), empty when built here
};

/// Parses calibration.conf text; `path` names the file in errors (line, column and key).
UrCalibration parse_ur_calibration(const std::string& text, const std::string& path);

/// Reads a calibration.conf file.
UrCalibration load_ur_calibration(const std::string& path);

/// The `[mounting]` section with the four delta rows (metres, radians; 17 significant digits)
/// and a comment saying what the file leaves out.
std::string ur_calibration_text(const UrCalibration& calibration);

/// Parameters of `model` (identity joint map) holding nominal + the deltas. InputError naming
/// the key when a6 or α6 is not 0 or the model's joint map is not the identity.
ParameterVector params_from_ur_calibration(const RobotModel& model,
                                           const UrCalibration& calibration);

/// The deltas of `params` against `model`'s nominal table (base x, y, alpha, beta and what is
/// not geometry are not looked at: see the file comment). InputError when the joint map is not
/// the identity.
UrCalibration ur_calibration_from_params(const RobotModel& model, const ParameterVector& params);

}  // namespace robcal
