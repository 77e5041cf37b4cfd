#pragma once
/// \file
/// Frames set up the way the published method does before any calibration (issue 16 item 3):
///
/// - **Base frame from single-joint sweeps**: a target measured while joint 1 turns (the others
///   still), then while joint 2 turns. Each sweep's circle (campaign/circle_fit.hpp) gives a
///   joint axis; axis 1 is the base z axis, the common normal of axes 1 and 2 is frame 1's x
///   axis (MDH: z1 × z2 = sin α2 · x1), turned back by joint 1's angle it is the base x axis;
///   frame 1's origin is where that normal meets axis 1, d1 above the base origin
///   (docs/method/02-frames.md §4: world_A_1 = Trans(x, y, d1 + z)·Rx(α)·Ry(β)·Rz(γ + θ1)).
/// - **Tool target from sweeps of joints 5 and 6**: axes 5 and 6 meet (common normal) at the
///   wrist; the flange origin is d6 along axis 6; x6 is x5 (z5 × z6 = sin α6 · x5) turned by
///   θ6; the target's flange coordinates are then read off the joint-6 circle.
/// - **Tool point from ≥ 4 flange poses**: touching one fixed point (pivot) or measured by the
///   instrument, linear least squares.
/// - **A frame from ≥ 3 nests**: measured nest centres against their coordinates in the frame
///   to set up (the table's drawing), a rigid least-squares fit (Kabsch/Horn).
///
/// Every estimate carries its covariance: the results are smooth functions of the measured
/// points, so the covariance is σ²·G·Gᵀ with G the derivative of the result with respect to
/// every measured coordinate (central differences) and σ the instrument's per-axis noise,
/// estimated from the fits' residuals unless given.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "robcal/campaign/circle_fit.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal::campaign {

/// One target measured while one joint turns: the controller joints of every reading (rad,
/// only the swept joint changes) and the measured points (mm, world frame).
struct JointSweep {
  int joint = 1;  ///< 1..6
  std::vector<Vector6d> joints;
  std::vector<Eigen::Vector3d> points_mm;
};

/// A frame's six numbers x, y, z (mm) and α, β, γ (rad; R = Rx(α)·Ry(β)·Rz(γ)) with their
/// covariance (mm, rad) and standard deviations.
struct FrameEstimate {
  Pose<double> pose;  ///< the frame in the measurement (world) frame
  Eigen::Matrix<double, 6, 1> values = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> sigma = Eigen::Matrix<double, 6, 1>::Zero();
  double sigma_mm = 0;  ///< the per-axis noise used (estimated or given)
  double rms_mm = 0;    ///< fit residual RMS
};

/// The robot's base placement (the six base parameters of docs/method/02-frames.md §4, in `values`)
/// from a joint-1 and a joint-2 sweep. `sigma_mm` > 0 gives the instrument's σ; 0 estimates it from
/// the circle residuals. \throws InputError naming the sweep that cannot be used (wrong joint,
/// another joint moving, too few points) or parallel axes 1 and 2.
FrameEstimate base_from_sweeps(const RobotModel& model, const JointSweep& joint1,
                               const JointSweep& joint2, double sigma_mm = 0);

/// A target's flange coordinates with their covariance.
struct PointEstimate {
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  Eigen::Vector3d sigma = Eigen::Vector3d::Zero();
  double sigma_mm = 0;
  double rms_mm = 0;
};

/// The target's coordinates in the flange frame from a joint-5 and a joint-6 sweep (both with
/// joints 1–4 at the same values), through the nominal d6, α6 and θ6 offset of `model`.
PointEstimate tool_from_sweeps(const RobotModel& model, const JointSweep& joint5,
                               const JointSweep& joint6, double sigma_mm = 0);

/// A tool point in the flange frame from ≥ 4 flange poses (world_T_flange, e.g. the robot's
/// FK with its base): with `measured_mm` empty, the point touches one fixed unknown spot in
/// every pose (pivot: R_k·t + p_k = P); otherwise it was measured at `measured_mm[k]`
/// (R_k·t + p_k = m_k). `sigma_mm` as above (from the residuals when 0).
/// \throws InputError for fewer than 4 poses or orientations too alike to fix the point.
PointEstimate tool_point_from_poses(const std::vector<Pose<double>>& world_T_flange,
                                    const std::vector<Eigen::Vector3d>& measured_mm = {},
                                    double sigma_mm = 0);

/// The frame F in which nests have coordinates `nominal_mm` (a drawing), from their centres
/// measured in the instrument frame `measured_mm` (≥ 3, not on one line): `pose` is
/// instrument_T_F. \throws InputError for fewer than 3 nests, different counts or collinear
/// nests.
FrameEstimate frame_from_nests(const std::vector<Eigen::Vector3d>& measured_mm,
                               const std::vector<Eigen::Vector3d>& nominal_mm, double sigma_mm = 0);

/// R = Rx(α)·Ry(β)·Rz(γ) → (α, β, γ), rad.
Eigen::Vector3d xyz_angles(const Eigen::Matrix3d& R);

}  // namespace robcal::campaign
