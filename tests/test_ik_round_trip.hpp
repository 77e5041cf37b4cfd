#pragma once
/// \file
/// The nominal IK round-trip criterion shared by the robot-library tests and the
/// Any6r_Library100k benchmark.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/nominal_chain.hpp"

namespace robcal::test {

/// The nominal IK round trip of the robot library (issue 15, docs/method/02-frames.md §7):
/// `solved` reproduces `target` = FK(`drawn`) within 1e-9 mm and 1e-11 rad, and its joints are
/// the drawn ones within 1e-9 rad, or, near the wrist singularity, within 1e-11/|sin θ5| rad (and
/// likewise near the stretched or folded elbow): the
/// pose fixes θ4 and θ6 only with a conditioning that grows as 1/|sin θ5| (the closed forms'
/// worst cases in 100,000 configurations per robot: 2.4–3.2e-9 rad at |sin θ5| = 5e-4–2.5e-3
/// with the pose exact to 4e-13 mm and 1e-13 rad, |Δq|·|sin θ5| ≤ 6e-12). Below |sin θ5| =
/// 1e-4 (a continuum of solutions) only the pose is checked.
inline bool ik_round_trip_ok(const RobotModel& model, const NominalChain& chain,
                             const Vector6d& drawn, const Pose<double>& target,
                             const Vector6d& solved) {
  const Pose<double> back = nominal_flange_pose(chain, solved);
  const double rad = Eigen::AngleAxisd(Eigen::Matrix3d(back.R.transpose() * target.R)).angle();
  if ((back.p - target.p).norm() > 1e-9 || rad > 1e-11) return false;
  const double sin5 =
      std::abs(std::sin(model_joint_angles(model, drawn.data())[4] + model.mdh[4].theta_offset));
  if (sin5 < 1e-4) return true;
  // The elbow (sine of the angle between upper arm and forearm in the arm's plane) conditions
  // the joints the same way near full stretch (Stäubli TX2-60: 3.5e-8 rad at 6e-5).
  const auto frames = link_frames(model, PointMass{}, model.nominal().data(), drawn.data());
  const Eigen::Vector3d z3 = frames[2].R.col(2);
  Eigen::Vector3d upper = frames[2].p - frames[1].p, fore = frames[3].p - frames[2].p;
  upper -= upper.dot(z3) * z3;
  fore -= fore.dot(z3) * z3;
  const double elbow = upper.normalized().cross(fore.normalized()).norm();
  return (solved - drawn).cwiseAbs().maxCoeff() <= std::max(1e-9, 1e-11 / std::min(sin5, elbow));
}

}  // namespace robcal::test
