#pragma once
/// \file
/// Orientation conversions for printing and reading poses: quaternions (w, x, y, z order,
/// always) and the robot makers' Euler angles (degrees outside).

#include <Eigen/Geometry>
#include <array>
#include <string>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

/// Unit quaternion (w ≥ 0) of a rotation matrix.
Eigen::Quaterniond to_quaternion(const Eigen::Matrix3d& R);

/// The maker's Euler angles (deg) of R = Rz(a)·Ry(b)·Rx(c): ZYX prints (A, B, C) = (a, b, c);
/// WPR prints (W, P, R) = (c, b, a).
Eigen::Vector3d euler_angles_deg(const Eigen::Matrix3d& R, EulerConvention convention);

/// Rotation from the maker's Euler angles (deg), inverse of euler_angles_deg.
Eigen::Matrix3d rotation_from_euler_deg(const Eigen::Vector3d& angles, EulerConvention convention);

/// Labels of the three printed angles: {"A","B","C"} or {"W","P","R"}.
std::array<std::string, 3> euler_labels(EulerConvention convention);

/// A pose from position (mm) and quaternion (w, x, y, z); the quaternion must be unit within
/// 1e-6 (InputError otherwise) and is normalised.
Pose<double> pose_from_position_quaternion(const Eigen::Vector3d& p_mm,
                                           const Eigen::Vector4d& q_wxyz);

/// Rotation angle (rad) of R_a^T R_b: the orientation distance of two rotations.
double rotation_distance(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb);

}  // namespace robcal
