/// `robcal robots`, `robcal robot show`, `robcal fk`: the robot library and forward kinematics.

#include <fmt/format.h>

#include <iostream>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::cli {
namespace {

void run_robots(bool json) {
  nlohmann::json out = nlohmann::json::array();
  for (const std::string& name : builtin_robot_names()) {
    const RobotModel model = load_robot(name);
    out.push_back({{"name", name},
                   {"model", model.name},
                   {"manufacturer", model.manufacturer},
                   {"reach_mm", model.reach_mm}});
    if (!json)
      fmt::print("{:<24} {:<17} {:<24} {}\n", name, model.manufacturer, model.name,
                 model.reach_mm > 0 ? fmt::format("{:.0f} mm", model.reach_mm) : "reach not given");
  }
  if (json) print_json(out);
}

void run_robot_show(const std::string& robot, bool json) {
  const RobotModel model = load_robot(robot);
  if (json) {
    nlohmann::json out;
    out["name"] = model.name;
    out["manufacturer"] = model.manufacturer;
    out["source"] = model.source;
    for (int i = 0; i < kJointCount; ++i) {
      const MdhRow& row = model.mdh[i];
      out["mdh"].push_back({{"link", i + 1},
                            {"alpha_deg", tidy(rad2deg(row.alpha))},
                            {"a_mm", row.a},
                            {"theta_offset_deg", tidy(rad2deg(row.theta_offset))},
                            {"d_mm", row.d}});
      out["joint_limits_deg"].push_back(
          {tidy(rad2deg(model.limits[i].lower)), tidy(rad2deg(model.limits[i].upper))});
    }
    print_json(out);
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
  const RobotModel model = load_robot(robot);
  const Vector6d joints = parse_joints_deg(joints_text);
  if (!model.within_limits(joints)) {
    std::string detail;
    for (int i = 0; i < kJointCount; ++i)
      if (joints[i] < model.limits[i].lower || joints[i] > model.limits[i].upper)
        detail += fmt::format(" J{}={:.3f} outside [{:.1f}, {:.1f}];", i + 1, rad2deg(joints[i]),
                              rad2deg(model.limits[i].lower), rad2deg(model.limits[i].upper));
    throw InputError({"", 0, 0, "--joints"}, "joints outside the robot's limits:" + detail);
  }
  const Pose<double> pose = flange_pose(model, PointMass{}, model.nominal(), joints);
  const Eigen::Quaterniond q = to_quaternion(pose.R);
  const Eigen::Vector3d euler = euler_angles_deg(pose.R, model.euler);
  const auto labels = euler_labels(model.euler);
  if (json) {
    nlohmann::json out;
    out["robot"] = model.name;
    out["joints_deg"] = parse_numbers(joints_text, kJointCount, "--joints");
    out["position_mm"] = {tidy(pose.p.x()), tidy(pose.p.y()), tidy(pose.p.z())};
    out["quaternion_wxyz"] = {tidy(q.w(), 12), tidy(q.x(), 12), tidy(q.y(), 12), tidy(q.z(), 12)};
    out["euler_deg"] = {
        {labels[0], tidy(euler[0])}, {labels[1], tidy(euler[1])}, {labels[2], tidy(euler[2])}};
    print_json(out);
    return;
  }
  fmt::print("flange of {} (nominal model, base at the origin)\n", model.name);
  fmt::print("  position   x {:.4f}  y {:.4f}  z {:.4f} mm\n", tidy(pose.p.x()), tidy(pose.p.y()),
             tidy(pose.p.z()));
  fmt::print("  quaternion w {:.9f}  x {:.9f}  y {:.9f}  z {:.9f}\n", tidy(q.w(), 12),
             tidy(q.x(), 12), tidy(q.y(), 12), tidy(q.z(), 12));
  fmt::print("  Euler      {} {:.4f}  {} {:.4f}  {} {:.4f} deg\n", labels[0], tidy(euler[0]),
             labels[1], tidy(euler[1]), labels[2], tidy(euler[2]));
}

const bool registered = register_command(10, [](CLI::App& app) {
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
