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
#include "robcal/kinematics/kinematics_workflow.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::cli {
namespace {

struct IkOptions {
  std::string robot;
  std::string pose;
  std::string seed;
  bool json = false;
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

void run_ik(const IkOptions& o) {
  IkRequest request{load_robot(o.robot), parse_pose(o.pose), Vector6d::Zero(), true};
  if (!o.seed.empty()) request.seed = parse_joints_deg(o.seed, "--seed-joints");
  const IkReport result = inverse_kinematics(request);
  if (o.json) {
    print_json(ik_json(result));
    return;
  }
  const std::vector<IkSolution>& solutions = result.ik.solutions;
  fmt::print("{}: {} solution{} ({})\n", result.robot, solutions.size(),
             solutions.size() == 1 ? "" : "s", result.ik.method);
  fmt::print("  {:<17} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "config", "J1", "J2", "J3",
             "J4", "J5", "J6");
  for (const IkSolution& s : solutions) {
    fmt::print("  {:<17}", s.config.label());
    for (int i = 0; i < kJointCount; ++i) fmt::print(" {:>10.4f}", tidy(rad2deg(s.joints[i])));
    fmt::print("{}\n", s.wrist_singular ? "  (wrist singular: J4 kept at the seed)" : "");
  }
}

const bool ik_registered = register_command(11, [](CLI::App& app) {
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
