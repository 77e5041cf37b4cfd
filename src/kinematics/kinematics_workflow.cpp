#include "robcal/kinematics/kinematics_workflow.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "robcal/core/error.hpp"
#include "robcal/core/rounding.hpp"
#include "robcal/core/units.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal {
namespace {

nlohmann::json joints_deg_json(const Vector6d& joints) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < kJointCount; ++i) out.push_back(rounded(rad2deg(joints[i])));
  return out;
}

}  // namespace

FkReport forward_kinematics(const FkRequest& request) {
  const RobotModel& model = request.robot;
  if (request.check_limits && !model.within_limits(request.joints)) {
    std::string detail;
    for (int i = 0; i < kJointCount; ++i)
      if (request.joints[i] < model.limits[i].lower || request.joints[i] > model.limits[i].upper)
        detail +=
            fmt::format(" J{}={:.3f} outside [{:.1f}, {:.1f}];", i + 1, rad2deg(request.joints[i]),
                        rad2deg(model.limits[i].lower), rad2deg(model.limits[i].upper));
    throw InputError({"", 0, 0, "--joints"}, "joints outside the robot's limits:" + detail);
  }
  FkReport result;
  result.robot = model.name;
  result.joints = request.joints;
  result.flange = flange_pose(model, PointMass{}, model.nominal(), request.joints);
  result.euler = model.euler;
  result.euler_deg = euler_angles_deg(result.flange.R, model.euler);
  return result;
}

nlohmann::json fk_json(const FkReport& result) {
  const Eigen::Quaterniond q = to_quaternion(result.flange.R);
  const Eigen::Vector3d& p = result.flange.p;
  const auto labels = euler_labels(result.euler);
  nlohmann::json out;
  out["robot"] = result.robot;
  out["joints_deg"] = joints_deg_json(result.joints);
  out["position_mm"] = {rounded(p.x()), rounded(p.y()), rounded(p.z())};
  out["quaternion_wxyz"] = {rounded(q.w(), 12), rounded(q.x(), 12), rounded(q.y(), 12),
                            rounded(q.z(), 12)};
  out["euler_deg"] = {{labels[0], rounded(result.euler_deg[0])},
                      {labels[1], rounded(result.euler_deg[1])},
                      {labels[2], rounded(result.euler_deg[2])}};
  return out;
}

IkReport inverse_kinematics(const IkRequest& request) {
  IkReport result{request.robot.name, solve_ik(request.robot, request.pose, request.seed)};
  if (!request.require_solution) return result;
  if (result.ik.status == IkStatus::Unreachable)
    throw InputError({"", 0, 0, "--pose"},
                     fmt::format("pose unreachable for {}: {}", result.robot, result.ik.method));
  if (result.ik.status == IkStatus::OutsideLimits)
    throw InputError({"", 0, 0, "--pose"},
                     fmt::format("the pose is reachable by {}, but every solution violates a "
                                 "joint limit",
                                 result.robot));
  return result;
}

nlohmann::json ik_json(const IkReport& result) {
  nlohmann::json out;
  out["robot"] = result.robot;
  out["status"] = to_string(result.ik.status);
  out["method"] = result.ik.method;
  out["solutions"] = nlohmann::json::array();
  for (const IkSolution& s : result.ik.solutions)
    out["solutions"].push_back({{"joints_deg", joints_deg_json(s.joints)},
                                {"config", s.config.label()},
                                {"wrist_singular", s.wrist_singular}});
  return out;
}

IkPath inverse_kinematics_path(const RobotModel& robot, const std::vector<Pose<double>>& poses,
                               const Vector6d& seed) {
  IkPath path;
  Vector6d previous = seed;
  for (const Pose<double>& pose : poses) {
    const AnyIkResult ik = solve_ik(robot, pose, previous);
    path.status.push_back(ik.status);
    std::optional<IkSolution> best;
    for (const IkSolution& s : ik.solutions)
      if (!best || (s.joints - previous).cwiseAbs().maxCoeff() <
                       (best->joints - previous).cwiseAbs().maxCoeff())
        best = s;
    if (ik.status == IkStatus::Unreachable || ik.status == IkStatus::OutsideLimits) best.reset();
    if (best) previous = best->joints;
    path.chosen.push_back(best);
  }
  return path;
}

}  // namespace robcal
