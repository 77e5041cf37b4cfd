/// `robcal ik`: inverse kinematics of the nominal robot, every solution with its configuration.
/// The robot's closed form or, for any other 6R arm, the general 6R method (kinematics/
/// closed_form_ik.hpp: every solution, every turn inside the limits); the damped-least-squares
/// solver from the seed (one solution) only for a joint map without an integer inverse.

#include <fmt/format.h>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::cli {
namespace {

struct IkOptions {
  std::string robot;
  std::string pose;
  std::string seed;
  bool json = false;
};

struct PrintedSolution {
  Vector6d joints;
  std::string config;
  bool wrist_singular = false;
};

Pose<double> parse_pose(const std::string& text) {
  const std::vector<double> v = parse_numbers(text, 7, "--pose");
  try {
    return pose_from_position_quaternion(Eigen::Vector3d(v[0], v[1], v[2]),
                                         Eigen::Vector4d(v[3], v[4], v[5], v[6]));
  } catch (const InputError& e) {
    throw InputError({"", 0, 0, "--pose"}, e.what());
  }
}

std::vector<PrintedSolution> solve(const RobotModel& model, const Pose<double>& target,
                                   const Vector6d& seed, std::string& method) {
  const AnyIkResult result = solve_ik(model, target, seed);
  method = result.method;
  if (result.status == IkStatus::Unreachable)
    throw InputError({"", 0, 0, "--pose"},
                     fmt::format("pose unreachable for {}: {}", model.name, result.method));
  if (result.status == IkStatus::OutsideLimits)
    throw InputError({"", 0, 0, "--pose"},
                     fmt::format("the pose is reachable by {}, but every solution violates a "
                                 "joint limit",
                                 model.name));
  std::vector<PrintedSolution> out;
  for (const IkSolution& s : result.solutions)
    out.push_back({s.joints, s.config.label(), s.wrist_singular});
  return out;
}

void run_ik(const IkOptions& o) {
  const RobotModel model = load_robot(o.robot);
  const Pose<double> target = parse_pose(o.pose);
  const Vector6d seed =
      o.seed.empty() ? Vector6d::Zero() : parse_joints_deg(o.seed, "--seed-joints");
  std::string method;
  const std::vector<PrintedSolution> solutions = solve(model, target, seed, method);
  if (o.json) {
    nlohmann::json out;
    out["robot"] = model.name;
    out["method"] = method;
    out["solutions"] = nlohmann::json::array();
    for (const PrintedSolution& s : solutions) {
      nlohmann::json joints = nlohmann::json::array();
      for (int i = 0; i < kJointCount; ++i) joints.push_back(tidy(rad2deg(s.joints[i])));
      out["solutions"].push_back(
          {{"joints_deg", joints}, {"config", s.config}, {"wrist_singular", s.wrist_singular}});
    }
    print_json(out);
    return;
  }
  fmt::print("{}: {} solution{} ({})\n", model.name, solutions.size(),
             solutions.size() == 1 ? "" : "s", method);
  fmt::print("  {:<17} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "config", "J1", "J2", "J3",
             "J4", "J5", "J6");
  for (const PrintedSolution& s : solutions) {
    fmt::print("  {:<17}", s.config);
    for (int i = 0; i < kJointCount; ++i) fmt::print(" {:>10.4f}", tidy(rad2deg(s.joints[i])));
    fmt::print("{}\n", s.wrist_singular ? "  (wrist singular: J4 kept at the seed)" : "");
  }
}

const bool registered = register_command(11, [](CLI::App& app) {
  auto* ik = app.add_subcommand(
      "ik", "Inverse kinematics of the nominal robot: every solution with its configuration");
  auto o = std::make_shared<IkOptions>();
  ik->add_option("--robot", o->robot, "Built-in robot name or robot file")->required();
  ik->add_option("--pose", o->pose,
                 "Flange pose x,y,z,qw,qx,qy,qz (mm, unit quaternion w first), base frame")
      ->required();
  ik->add_option("--seed-joints", o->seed,
                 "Controller joints j1,...,j6 (deg): J4 at a wrist singularity, the start of "
                 "the numeric solver (default all zero)");
  ik->add_flag("--json", o->json,
               "Machine-readable output: {\"solutions\":[{\"joints_deg\":[...],\"config\":...}]}");
  ik->callback([o] { run_ik(*o); });
});

}  // namespace
}  // namespace robcal::cli
