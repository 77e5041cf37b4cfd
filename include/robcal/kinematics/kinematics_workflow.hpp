#pragma once
/// \file
/// The workflows behind `robcal fk` and `robcal ik` and Python's `fk`/`ik`: the nominal robot's
/// flange pose at controller joints (limits checked when asked), and every IK solution of a
/// flange pose with the solver that ran; each with its one JSON serializer (mm, degrees).

#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal {

struct FkRequest {
  RobotModel robot;
  Vector6d joints = Vector6d::Zero();  ///< controller joints, rad
  bool check_limits = true;            ///< refuse joints outside the robot's limits
};

struct FkReport {
  std::string robot;          ///< the robot's name
  Vector6d joints;            ///< as requested, rad
  Pose<double> flange;        ///< nominal model, base at the origin (mm)
  Eigen::Vector3d euler_deg;  ///< in the robot's own convention (RobotModel::euler)
  EulerConvention euler = EulerConvention::ZyxABC;
};

/// Throws InputError (key "--joints") naming every joint outside its limits when asked to check.
FkReport forward_kinematics(const FkRequest& request);

/// {robot, joints_deg, position_mm, quaternion_wxyz, euler_deg: {A|W: …}} rounded for reading
/// (1e-9 mm and deg, 1e-12 for the quaternion).
nlohmann::json fk_json(const FkReport& result);

struct IkRequest {
  RobotModel robot;
  Pose<double> pose;                 ///< flange in the base frame (mm)
  Vector6d seed = Vector6d::Zero();  ///< J4 at a wrist singularity; the numeric solver's start
  bool require_solution = true;      ///< throw when there is no solution inside the limits
};

struct IkReport {
  std::string robot;
  AnyIkResult ik;  ///< status, solutions with their configuration, the solver that ran
};

/// Every solution (closed form for ortho-parallel and UR-family robots, numeric otherwise).
/// With require_solution, an unreachable pose or one whose every solution violates a limit
/// throws InputError (key "--pose") saying which.
IkReport inverse_kinematics(const IkRequest& request);

/// {robot, status, method, solutions: [{joints_deg, config, wrist_singular}]}, joints rounded to
/// 1e-9 deg.
nlohmann::json ik_json(const IkReport& result);

/// IK along a list of flange poses (Python's batched ik): per pose the solution inside the
/// limits nearest (max-norm over joints) to the previous pose's, the first nearest `seed`, so
/// that a path stays on one branch; a pose without one keeps the last joints for the next.
struct IkPath {
  std::vector<IkStatus> status;  ///< per pose
  /// Per pose; empty when it is unreachable or every solution violates a limit.
  std::vector<std::optional<IkSolution>> chosen;
};
IkPath inverse_kinematics_path(const RobotModel& robot, const std::vector<Pose<double>>& poses,
                               const Vector6d& seed = Vector6d::Zero());

}  // namespace robcal
