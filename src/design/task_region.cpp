#include "robcal/design/task_region.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
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
    box.min_mm[k] = values[static_cast<size_t>(2 * k)];
    box.max_mm[k] = values[static_cast<size_t>(2 * k + 1)];
    if (box.min_mm[k] > box.max_mm[k])
      throw InputError({"", 0, 0, flag}, fmt::format("{} range [{}, {}] has min > max", "xyz"[k],
                                                     box.min_mm[k], box.max_mm[k]));
  }
  return box;
}

std::vector<Vector6d> task_box_configurations(const RobotModel& model, const Tool& tool,
                                              const ParameterVector& params,
                                              const JointConstraints& constraints,
                                              const TaskBox& box, int count, std::mt19937_64& rng,
                                              const std::string& flag, int draws_per_point) {
  const std::array<JointLimit, kJointCount> joint_box = constrained_joint_box(model, constraints);
  Vector6d middle;
  for (int j = 0; j < kJointCount; ++j)
    middle[j] =
        0.5 * (joint_box[static_cast<size_t>(j)].lower + joint_box[static_cast<size_t>(j)].upper);
  // The placement taking the nominal robot (base at the origin, which the closed-form IK
  // solves) onto the placed one: the base offset d1 is applied along world z (METHOD §2), so
  // world_T_base = world_A_1(params, θ1 = 0) · Trans_z(−d1).
  Pose<double> lower_d1;
  lower_d1.p.z() = -model.mdh[0].d;
  const Pose<double> world_T_base =
      detail::base_transform(params.data(), model.mdh[0].d, 0.0) * lower_d1;
  const Pose<double> base_T_world = world_T_base.inverse();
  Pose<double> tcp_T_flange;
  tcp_T_flange.R = tool.flange_T_tcp.linear().transpose();
  tcp_T_flange.p = -(tcp_T_flange.R * tool.flange_T_tcp.translation());
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
    const Pose<double> world_T_flange = world_T_tcp * tcp_T_flange;
    const AnyIkResult ik = solve_ik(model, base_T_world * world_T_flange, middle);
    const IkSolution* best = nullptr;
    double best_distance = 0;
    for (const IkSolution& s : ik.solutions) {
      // Keep only solutions that reach the pose on the placed robot (a singular wrist or a
      // numeric fallback may not).
      const Pose<double> reached = flange_pose(model, tool.payload, params, s.joints);
      bool inside = (reached.p - world_T_flange.p).norm() < kReachToleranceMm;
      for (int j = 0; j < kJointCount; ++j)
        inside = inside && s.joints[j] >= joint_box[static_cast<size_t>(j)].lower &&
                 s.joints[j] <= joint_box[static_cast<size_t>(j)].upper;
      const double distance = (s.joints - middle).cwiseAbs().maxCoeff();
      if (inside && (!best || distance < best_distance)) best = &s, best_distance = distance;
    }
    if (best) out.push_back(best->joints);
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

}  // namespace robcal
