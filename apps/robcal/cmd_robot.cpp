/// `robcal robots`, `robcal robot show`, `robcal fk`: the robot library and forward kinematics.

#include <fmt/format.h>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_catalogue.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/kinematics_workflow.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::cli {
namespace {

void run_robots(bool json) {
  const std::vector<RobotEntry> entries = robot_catalogue();
  if (json) {
    print_json(robot_catalogue_json(entries));
    return;
  }
  for (const RobotEntry& e : entries)
    fmt::print("{:<24} {:<17} {:<24} {}\n", e.name, e.manufacturer, e.model,
               e.reach_mm > 0 ? fmt::format("{:.0f} mm", e.reach_mm) : "reach not given");
}

void run_robot_show(const std::string& robot, bool json) {
  const RobotModel model = load_robot(robot);
  if (json) {
    print_json(robot_description_json(model));
    return;
  }
  fmt::print("{} ({})\nsource: {}\n\n", model.name, model.manufacturer, model.source);
  fmt::print("link  alpha(deg)     a(mm)  theta0(deg)     d(mm)   limits(deg)        mass(kg)\n");
  for (int i = 0; i < kJointCount; ++i) {
    const MdhRow& row = model.mdh[i];
    fmt::print("{:>4} {:>11.3f} {:>9.3f} {:>12.3f} {:>9.3f}   [{:>7.1f}, {:>7.1f}] {:>8.2f}\n",
               i + 1, tidy(rad2deg(row.alpha)), row.a, tidy(rad2deg(row.theta_offset)), row.d,
               rad2deg(model.limits[i].lower), rad2deg(model.limits[i].upper),
               model.link_masses[i].mass_kg);
  }
  if (!model.joint_map.is_identity())
    fmt::print("\ncontroller joints map to model joints: q = M·J + offset (see the robot file)\n");
}

void run_fk(const std::string& robot, const std::string& joints_text, bool json) {
  const FkReport result =
      forward_kinematics({load_robot(robot), parse_joints_deg(joints_text), true});
  if (json) {
    print_json(fk_json(result));
    return;
  }
  const Eigen::Vector3d& p = result.flange.p;
  const Eigen::Quaterniond q = to_quaternion(result.flange.R);
  const auto labels = euler_labels(result.euler);
  const Eigen::Vector3d& euler = result.euler_deg;
  fmt::print("flange of {} (nominal model, base at the origin)\n", result.robot);
  fmt::print("  position   x {:.4f}  y {:.4f}  z {:.4f} mm\n", tidy(p.x()), tidy(p.y()),
             tidy(p.z()));
  fmt::print("  quaternion w {:.9f}  x {:.9f}  y {:.9f}  z {:.9f}\n", tidy(q.w(), 12),
             tidy(q.x(), 12), tidy(q.y(), 12), tidy(q.z(), 12));
  fmt::print("  Euler      {} {:.4f}  {} {:.4f}  {} {:.4f} deg\n", labels[0], tidy(euler[0]),
             labels[1], tidy(euler[1]), labels[2], tidy(euler[2]));
}

const bool robot_registered = register_command(10, [](CLI::App& app) {
  auto* robots = app.add_subcommand("robots", "List the built-in robots");
  auto robots_json = std::make_shared<bool>(false);
  robots->add_flag("--json", *robots_json, "Machine-readable output");
  robots->callback([robots_json] { run_robots(*robots_json); });

  auto* robot = app.add_subcommand("robot", "Inspect a robot model");
  robot->require_subcommand(1);
  auto* show = robot->add_subcommand("show", "Print a robot's MDH table, limits and masses");
  auto show_name = std::make_shared<std::string>();
  auto show_json = std::make_shared<bool>(false);
  show->add_option("robot", *show_name, "Built-in robot name or robot file")->required();
  show->add_flag("--json", *show_json, "Machine-readable output");
  show->callback([show_name, show_json] { run_robot_show(*show_name, *show_json); });

  auto* fk = app.add_subcommand("fk", "Forward kinematics: flange pose of the nominal robot");
  auto fk_robot = std::make_shared<std::string>();
  auto fk_joints = std::make_shared<std::string>();
  auto fk_json = std::make_shared<bool>(false);
  fk->add_option("--robot", *fk_robot, "Built-in robot name or robot file")->required();
  fk->add_option("--joints", *fk_joints, "Controller joint values j1,...,j6 in degrees")
      ->required();
  fk->add_flag("--json", *fk_json, "Machine-readable output");
  fk->callback([=] { run_fk(*fk_robot, *fk_joints, *fk_json); });
});

}  // namespace
}  // namespace robcal::cli
