#pragma once
/// \file
/// The task region a calibration is for (docs/method/05-observability.md §5: predicted accuracy
/// before measuring): a Cartesian box of TCP positions in the world frame, sampled to reachable
/// configurations by inverse kinematics, or a list of TCP poses in the world frame, each solved by
/// inverse kinematics; the calibrated robot's position error is predicted over these
/// configurations.

#include <random>
#include <string>
#include <vector>

#include "robcal/design/candidates.hpp"
#include "robcal/io/pose_list_file.hpp"
#include "robcal/model/robot_model.hpp"
#include "robcal/model/tool.hpp"

namespace robcal {

/// TCP positions x ∈ [x_min, x_max], … in the world (instrument) frame, mm.
struct TaskBox {
  Eigen::Vector3d min_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_mm = Eigen::Vector3d::Zero();
};

/// Parses "xmin,xmax,ymin,ymax,zmin,zmax" (mm). InputError naming `flag` for anything else
/// (six finite numbers with min ≤ max).
TaskBox parse_task_box(const std::string& text, const std::string& flag);

/// Configurations that put the TCP at `count` points drawn uniformly in the box, the tool
/// axis (TCP z) pointing down (world −z) and turned about it by a uniform angle: the closed-form
/// nominal inverse kinematics of the robot placed by `params`' base parameters, the solution
/// reaching the pose inside the constrained joint box nearest to its middle. Points no solution
/// reaches are drawn again; InputError (key `flag`) when fewer than one in `draws_per_point` is
/// reachable.
std::vector<Vector6d> task_box_configurations(const RobotModel& model, const Tool& tool,
                                              const ParameterVector& params,
                                              const JointConstraints& constraints,
                                              const TaskBox& box, int count, std::mt19937_64& rng,
                                              const std::string& flag = "--task-box",
                                              int draws_per_point = 50);

/// Configurations reaching listed TCP poses (world frame, mm) by the same inverse kinematics:
/// per pose the solution inside the constrained joint box, in the pose's configuration branch
/// when it names one (else in any branch), nearest the box's middle. InputError naming `file`,
/// the pose's line and name when no configuration reaches the pose, the named branch does not,
/// or every solution reaching it is outside the joint constraints.
std::vector<Vector6d> task_pose_configurations(const RobotModel& model, const Tool& tool,
                                               const ParameterVector& params,
                                               const JointConstraints& constraints,
                                               const std::vector<ListedPose>& poses,
                                               const std::string& file);

}  // namespace robcal
