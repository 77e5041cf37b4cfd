#pragma once
// Shared by the compensation tests and bench/bench_compensate.cpp: a calibrated robot with
// realistic errors, random joints, and the singular labels of BENCHMARKS.md.

#include <Eigen/Geometry>
#include <random>
#include <string>

#include "robcal/core/units.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"

namespace robcal::test {

inline constexpr const char* kRobots[] = {"abb-irb120", "fanuc-lrmate200ic", "kuka-kr6-r900-sixx"};

/// Compliance of the identified IRB 120 (tests/data/irb120-published/truth.yaml), rad/(N·mm).
inline constexpr double kPublishedCompliance[5] = {3.2e-8, 1.3e-7, 6.05e-7, 4.19e-7, 6.47e-7};

/// A calibrated robot: the nominal one placed in a tracker's world with the error magnitudes
/// of METHOD §10 (links ±0.5 mm / ±0.1°, compliance of the published IRB 120 order), a 2.6 kg
/// payload and a TCP 150 mm out.
inline CalibratedRobot random_calibrated(const std::string& name, std::mt19937_64& rng) {
  const RobotModel model = load_robot(name);
  Tool tool;
  tool.payload = {2.6, Eigen::Vector3d(-23, 0, 100)};
  tool.flange_T_tcp.translation() = Eigen::Vector3d(10, -20, 150);
  tool.flange_T_tcp.linear() =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  CalibratedRobot robot = CalibratedRobot::nominal(model, tool);
  std::uniform_real_distribution<double> u(-1, 1);
  robot.params[0] = -812 + 5 * u(rng);
  robot.params[1] = 1503 + 5 * u(rng);
  robot.params[2] = -95 + 5 * u(rng);
  robot.params[3] = deg2rad(0.3 * u(rng));
  robot.params[4] = deg2rad(0.3 * u(rng));
  robot.params[5] = deg2rad(-57 + u(rng));
  for (int link = 2; link <= 6; ++link) {
    robot.params[link_param(link, 0)] += deg2rad(0.1 * u(rng));
    robot.params[link_param(link, 1)] += 0.5 * u(rng);
    robot.params[link_param(link, 2)] += deg2rad(0.1 * u(rng));
    robot.params[link_param(link, 3)] += 0.5 * u(rng);
    robot.params[compliance_param(link)] = kPublishedCompliance[link - 2] * (1 + 0.5 * u(rng));
  }
  robot.level = "full";
  return robot;
}

inline Vector6d random_joints(const RobotModel& model, std::mt19937_64& rng) {
  Vector6d j;
  for (int i = 0; i < kJointCount; ++i)
    j[i] =
        std::uniform_real_distribution<double>(model.limits[i].lower, model.limits[i].upper)(rng);
  return j;
}

/// BENCHMARKS.md singular labels on the nominal robot: θ5 within `margin_deg` (5°) of 0 or
/// 180°, elbow stretched or folded within `margin_deg`, or the wrist centre within 50 mm of
/// axis 1.
inline bool near_singular(const RobotModel& model, const Vector6d& joints, double margin_deg = 5) {
  const auto frames = link_frames(model, PointMass{}, model.nominal().data(), joints.data());
  const auto q = model_joint_angles(model, joints.data());
  const double theta5 = q[4] + model.mdh[4].theta_offset;
  if (std::abs(std::sin(theta5)) < std::sin(deg2rad(margin_deg))) return true;
  const Eigen::Vector3d upper = frames[2].p - frames[1].p, fore = frames[4].p - frames[2].p;
  if (upper.normalized().cross(fore.normalized()).norm() < std::sin(deg2rad(margin_deg)))
    return true;
  const Eigen::Vector3d w = frames[4].p - frames[0].p;
  return std::hypot(w.x(), w.y()) < 50;
}

}  // namespace robcal::test
