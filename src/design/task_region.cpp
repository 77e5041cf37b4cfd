#include "robcal/design/task_region.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "robcal/core/error.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"

namespace robcal {

namespace {
constexpr double kReachToleranceMm = 1e-6;
}  // namespace

TaskBox parse_task_box(const std::string& text, const std::string& flag) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string cell;
  while (std::getline(stream, cell, ',')) {
    size_t used = 0;
    double value = 0;
    try {
      value = std::stod(cell, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    const auto rest = cell.find_first_not_of(" \t", used);
    if (used == 0 || rest != std::string::npos || !std::isfinite(value))
      throw InputError({"", 0, 0, flag},
                       fmt::format("expected a number (mm), found '{}' in '{}'", cell, text));
    values.push_back(value);
  }
  if (values.size() != 6)
    throw InputError({"", 0, 0, flag},
                     fmt::format("expected xmin,xmax,ymin,ymax,zmin,zmax (6 numbers, mm), found "
                                 "{} in '{}'",
                                 values.size(), text));
  TaskBox box;
  for (int k = 0; k < 3; ++k) {
    box.min_mm[k] = values[2 * static_cast<size_t>(k)];
    box.max_mm[k] = values[2 * static_cast<size_t>(k) + 1];
    if (box.min_mm[k] > box.max_mm[k])
      throw InputError({"", 0, 0, flag}, fmt::format("{} range [{}, {}] has min > max", "xyz"[k],
                                                     box.min_mm[k], box.max_mm[k]));
  }
  return box;
}

namespace {

/// The placed robot's TCP poses to joints by the closed-form nominal inverse kinematics, the
/// solutions kept inside the constrained joint box (the task box and the task poses share it).
class TcpPoseSolver {
 public:
  TcpPoseSolver(const RobotModel& model, const Tool& tool, const ParameterVector& params,
                const JointConstraints& constraints)
      : model_(model),
        tool_(tool),
        params_(params),
        joint_box_(constrained_joint_box(model, constraints)) {
    for (int j = 0; j < kJointCount; ++j)
      middle_[j] = 0.5 * (joint_box_[static_cast<size_t>(j)].lower +
                          joint_box_[static_cast<size_t>(j)].upper);
    // The placement taking the nominal robot (base at the origin, which the closed-form IK
    // solves) onto the placed one: the base offset d1 is applied along world z
    // (docs/method/02-frames.md §4), so world_T_base = world_A_1(params, θ1 = 0) · Trans_z(−d1).
    Pose<double> lower_d1;
    lower_d1.p.z() = -model.mdh[0].d;
    base_T_world_ =
        (detail::base_transform(params.data(), model.mdh[0].d, 0.0) * lower_d1).inverse();
    tcp_T_flange_.R = tool.flange_T_tcp.linear().transpose();
    tcp_T_flange_.p = -(tcp_T_flange_.R * tool.flange_T_tcp.translation());
  }

  /// The solution reaching `world_T_tcp` inside the constrained joint box (in branch `config`
  /// when given) nearest the box's middle; std::nullopt with the reason in `why_not` (if given).
  std::optional<Vector6d> solve(const Pose<double>& world_T_tcp,
                                const std::optional<ArmConfig>& config = std::nullopt,
                                std::string* why_not = nullptr) const {
    const Pose<double> world_T_flange = world_T_tcp * tcp_T_flange_;
    const AnyIkResult ik = solve_ik(model_, base_T_world_ * world_T_flange, middle_);
    const IkSolution* best = nullptr;
    double best_distance = 0;
    std::vector<std::string> reaching, in_branch_outside;
    for (const IkSolution& s : ik.solutions) {
      // Only solutions that reach the pose on the placed robot (a singular wrist or a numeric
      // fallback may not).
      const Pose<double> reached = flange_pose(model_, tool_.payload, params_, s.joints);
      if ((reached.p - world_T_flange.p).norm() >= kReachToleranceMm) continue;
      reaching.push_back(s.config.label());
      if (config && !(s.config == *config)) continue;
      bool inside = true;
      for (int j = 0; j < kJointCount; ++j)
        inside = inside && s.joints[j] >= joint_box_[static_cast<size_t>(j)].lower &&
                 s.joints[j] <= joint_box_[static_cast<size_t>(j)].upper;
      if (!inside) {
        in_branch_outside.push_back(s.config.label());
        continue;
      }
      const double distance = (s.joints - middle_).cwiseAbs().maxCoeff();
      if (!best || distance < best_distance) best = &s, best_distance = distance;
    }
    if (best) return best->joints;
    if (why_not) {
      const auto unique = [](std::vector<std::string> v) {
        std::sort(v.begin(), v.end());
        v.erase(std::unique(v.begin(), v.end()), v.end());
        return fmt::format("{}", fmt::join(v, ", "));
      };
      if (reaching.empty())
        *why_not = fmt::format("no configuration reaches it ({})", to_string(ik.status));
      else if (in_branch_outside.empty())
        *why_not = fmt::format("configuration {} does not reach it (reached in: {})",
                               config->label(), unique(reaching));
      else
        *why_not = fmt::format("reached in {} but outside the joint constraints",
                               unique(in_branch_outside));
    }
    return std::nullopt;
  }

 private:
  const RobotModel& model_;
  const Tool& tool_;
  const ParameterVector& params_;
  std::array<JointLimit, kJointCount> joint_box_;
  Vector6d middle_;
  Pose<double> base_T_world_, tcp_T_flange_;
};

}  // namespace

std::vector<Vector6d> task_box_configurations(const RobotModel& model, const Tool& tool,
                                              const ParameterVector& params,
                                              const JointConstraints& constraints,
                                              const TaskBox& box, int count, std::mt19937_64& rng,
                                              const std::string& flag, int draws_per_point) {
  const TcpPoseSolver solver(model, tool, params, constraints);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vector6d> out;
  const long budget = static_cast<long>(count) * draws_per_point;
  for (long draw = 0; draw < budget && static_cast<int>(out.size()) < count; ++draw) {
    Pose<double> world_T_tcp;
    for (int k = 0; k < 3; ++k)
      world_T_tcp.p[k] = box.min_mm[k] + (box.max_mm[k] - box.min_mm[k]) * unit(rng);
    // Tool axis down: TCP z = world −z (a half turn about world x), then a turn about it.
    const double turn = (2 * unit(rng) - 1) * M_PI;
    world_T_tcp.R = (Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
    if (const auto joints = solver.solve(world_T_tcp)) out.push_back(*joints);
  }
  if (static_cast<int>(out.size()) < count)
    throw InputError(
        {"", 0, 0, flag},
        fmt::format("only {} of {} task points reachable in {} draws (tool pointing down, "
                    "joint constraints applied): move or shrink the box, box is x [{}, {}], y "
                    "[{}, {}], z [{}, {}] mm in the world frame",
                    out.size(), count, budget, box.min_mm.x(), box.max_mm.x(), box.min_mm.y(),
                    box.max_mm.y(), box.min_mm.z(), box.max_mm.z()));
  return out;
}

std::vector<Vector6d> task_pose_configurations(const RobotModel& model, const Tool& tool,
                                               const ParameterVector& params,
                                               const JointConstraints& constraints,
                                               const std::vector<ListedPose>& poses,
                                               const std::string& file) {
  const TcpPoseSolver solver(model, tool, params, constraints);
  std::vector<Vector6d> out;
  for (const ListedPose& pose : poses) {
    std::string why_not;
    const auto joints = solver.solve(pose.world_T_tcp, pose.config, &why_not);
    if (!joints) {
      const Eigen::Vector3d& p = pose.world_T_tcp.p;
      throw InputError({file, pose.line, 0, pose.name},
                       fmt::format("task pose ({:.3f}, {:.3f}, {:.3f}) mm in the world frame: {}",
                                   p.x(), p.y(), p.z(), why_not));
    }
    out.push_back(*joints);
  }
  return out;
}

}  // namespace robcal
