/// `robcal frames base|tool|world`: frames set up as the published method does, from
/// single-joint sweeps and table nests (campaign/frames.hpp), written with their σ.

#include <fmt/format.h>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/campaign/cell.hpp"
#include "robcal/campaign/frames_file.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal::cli {
namespace {

struct FramesOptions {
  std::string robot, first, second, target = "1", cell, tool, out;
  std::string measured, nominal;
  double sigma_mm = 0;
  bool json = false;
};

campaign::JointSweep read_sweep(const std::string& path, const std::string& target, int joint,
                                const RobotModel& model) {
  Tool tool;
  tool.targets.push_back({target, Eigen::Vector3d::Zero(), false});
  return campaign::sweep_from_measurements(
      read_measurements_csv(path, tool, {MeasurementKind::Points}).measurements, joint, model);
}

nlohmann::json frame_json(const campaign::FrameEstimate& f) {
  return {{"position_mm", {f.values[0], f.values[1], f.values[2]}},
          {"rotation_xyz_deg", {rad2deg(f.values[3]), rad2deg(f.values[4]), rad2deg(f.values[5])}},
          {"sigma_position_mm", {f.sigma[0], f.sigma[1], f.sigma[2]}},
          {"sigma_rotation_deg", {rad2deg(f.sigma[3]), rad2deg(f.sigma[4]), rad2deg(f.sigma[5])}},
          {"sigma_noise_mm", f.sigma_mm},
          {"rms_mm", f.rms_mm}};
}

void print_frame(const char* what, const campaign::FrameEstimate& f) {
  fmt::print("{} (value ± 1σ; noise σ {:.4f} mm, fit rms {:.4f} mm)\n", what, f.sigma_mm, f.rms_mm);
  const char* names[] = {"x", "y", "z", "alpha", "beta", "gamma"};
  for (int i = 0; i < 6; ++i)
    fmt::print("  {:<6} {:>14.4f} ± {:.4f} {}\n", names[i],
               i < 3 ? f.values[i] : rad2deg(f.values[i]), i < 3 ? f.sigma[i] : rad2deg(f.sigma[i]),
               i < 3 ? "mm" : "deg");
}

void run_base(const FramesOptions& o) {
  const RobotModel model = load_robot(o.robot);
  const campaign::JointSweep s1 = read_sweep(o.first, o.target, 1, model);
  const campaign::JointSweep s2 = read_sweep(o.second, o.target, 2, model);
  const campaign::FrameEstimate base = campaign::base_from_sweeps(model, s1, s2, o.sigma_mm);
  const std::string comment = fmt::format(
      "robot base of {} from circle fits of the joint-1 sweep {} ({} readings) and the joint-2 "
      "sweep {} ({} readings) of target {} (robcal frames base)",
      model.name, o.first, s1.points_mm.size(), o.second, s2.points_mm.size(), o.target);
  const std::string text =
      o.cell.empty() ? "# " + comment + "\n" + campaign::robot_base_block(base)
                     : campaign::cell_with_base(read_text_file(o.cell), o.cell, base, comment);
  write_file_atomically(o.out, text);
  if (o.json) {
    print_json({{"base", frame_json(base)}, {"out", o.out}});
    return;
  }
  print_frame(fmt::format("base of {} in the instrument frame", model.name).c_str(), base);
  fmt::print("wrote {}{}\n", o.out,
             o.cell.empty() ? " (a robot_base block for the cell file)" : "");
}

/// Writes the tool (o.tool's, or a new one) with the target at `t`, and prints it.
void write_target(const FramesOptions& o, const RobotModel& model, const campaign::PointEstimate& t,
                  const std::string& source) {
  Tool tool;
  if (!o.tool.empty()) tool = load_tool(o.tool);
  int index = tool.target_index(o.target);
  if (index < 0) {
    tool.targets.push_back({o.target, Eigen::Vector3d::Zero(), true});
    index = static_cast<int>(tool.targets.size()) - 1;
  }
  tool.targets[static_cast<size_t>(index)] = {o.target, t.position_mm, true};
  const std::string text = fmt::format(
      "# target {} from {}: [{:.4f}, {:.4f}, {:.4f}] ± [{:.4f}, {:.4f}, {:.4f}] mm (1σ), noise σ "
      "{:.4f} mm\n{}",
      o.target, source, t.position_mm.x(), t.position_mm.y(), t.position_mm.z(), t.sigma.x(),
      t.sigma.y(), t.sigma.z(), t.sigma_mm, tool_to_yaml(tool));
  write_file_atomically(o.out, text);
  if (o.json) {
    print_json({{"target", o.target},
                {"position_mm", {t.position_mm.x(), t.position_mm.y(), t.position_mm.z()}},
                {"sigma_mm", {t.sigma.x(), t.sigma.y(), t.sigma.z()}},
                {"sigma_noise_mm", t.sigma_mm},
                {"out", o.out}});
    return;
  }
  fmt::print("target {} in the flange frame of {} (value ± 1σ; noise σ {:.4f} mm)\n", o.target,
             model.name, t.sigma_mm);
  for (int k = 0; k < 3; ++k)
    fmt::print("  {} {:>12.4f} ± {:.4f} mm\n", static_cast<char>('x' + k), t.position_mm[k],
               t.sigma[k]);
  fmt::print("wrote {}\n", o.out);
}

void run_tool(const FramesOptions& o) {
  const RobotModel model = load_robot(o.robot);
  const campaign::JointSweep s5 = read_sweep(o.first, o.target, 5, model);
  const campaign::JointSweep s6 = read_sweep(o.second, o.target, 6, model);
  write_target(o, model, campaign::tool_from_sweeps(model, s5, s6, o.sigma_mm),
               fmt::format("circle fits of the joint-5 sweep {} and the joint-6 sweep {} (robcal "
                           "frames tool)",
                           o.first, o.second));
}

void run_point(const FramesOptions& o) {
  const RobotModel model = load_robot(o.robot);
  const campaign::Cell cell = campaign::load_cell(o.cell);
  Tool names;
  names.targets.push_back({o.target, Eigen::Vector3d::Zero(), false});
  const MeasurementSet set =
      read_measurements_csv(o.first, names, {MeasurementKind::Points}).measurements;
  write_target(
      o, model,
      campaign::tool_point_from_measurements(model, cell.robot_params(model), set, o.sigma_mm),
      fmt::format("{} rows of {} with the nominal robot at the base of {} (robcal "
                  "frames point)",
                  set.points.size(), o.first, o.cell));
}

void run_world(const FramesOptions& o) {
  const campaign::FrameEstimate frame = campaign::frame_from_named_nests(
      {o.measured, read_text_file(o.measured)}, {o.nominal, read_text_file(o.nominal)}, o.sigma_mm);
  const Eigen::Vector3d instrument = frame.pose.inverse().p;
  const std::string text =
      campaign::frame_yaml("frame", frame,
                           fmt::format("the frame of {} (nest coordinates) in the instrument's "
                                       "frame, fitted to the nests measured in {} (robcal frames "
                                       "world)",
                                       o.nominal, o.measured)) +
      fmt::format("instrument_position_mm: [{}, {}, {}]  # the instrument in that frame\n",
                  instrument.x(), instrument.y(), instrument.z());
  write_file_atomically(o.out, text);
  if (o.json) {
    print_json({{"frame", frame_json(frame)},
                {"instrument_position_mm", {instrument.x(), instrument.y(), instrument.z()}},
                {"out", o.out}});
    return;
  }
  print_frame("frame of the nests in the instrument frame", frame);
  fmt::print("instrument in that frame: {:.4f} {:.4f} {:.4f} mm\nwrote {}\n", instrument.x(),
             instrument.y(), instrument.z(), o.out);
}

const bool registered = register_command(76, [](CLI::App& app) {
  auto* frames = app.add_subcommand(
      "frames", "Set up the base, tool and world frames from joint sweeps and nests, with σ");
  frames->require_subcommand(1);
  const auto common = [](CLI::App* cmd, FramesOptions& o) {
    cmd->add_option("--sigma-mm", o.sigma_mm,
                    "Instrument noise per axis, mm (default: estimated from the fit residuals)");
    cmd->add_option("--out", o.out, "File to write")->required();
    cmd->add_flag("--json", o.json, "Machine-readable output");
  };

  auto base_o = std::make_shared<FramesOptions>();
  auto* base = frames->add_subcommand(
      "base", "Robot base from circle fits of a joint-1 and a joint-2 sweep (points files)");
  base->add_option("--robot", base_o->robot, "Built-in robot name or robot file")->required();
  base->add_option("--joint1", base_o->first, "Points file of the joint-1 sweep")->required();
  base->add_option("--joint2", base_o->second, "Points file of the joint-2 sweep")->required();
  base->add_option("--target", base_o->target, "Target measured in the sweeps")
      ->capture_default_str();
  base->add_option("--cell", base_o->cell, "Cell file whose robot_base block is replaced in --out");
  common(base, *base_o);
  base->callback([base_o] { run_base(*base_o); });

  auto tool_o = std::make_shared<FramesOptions>();
  auto* tool = frames->add_subcommand(
      "tool", "Target in the flange frame from circle fits of a joint-5 and a joint-6 sweep");
  tool->add_option("--robot", tool_o->robot, "Built-in robot name or robot file")->required();
  tool->add_option("--joint5", tool_o->first, "Points file of the joint-5 sweep")->required();
  tool->add_option("--joint6", tool_o->second, "Points file of the joint-6 sweep")->required();
  tool->add_option("--target", tool_o->target, "Target measured in the sweeps")
      ->capture_default_str();
  tool->add_option("--tool", tool_o->tool, "Tool file to update (default: a new tool)");
  common(tool, *tool_o);
  tool->callback([tool_o] { run_tool(*tool_o); });

  auto point_o = std::make_shared<FramesOptions>();
  auto* point = frames->add_subcommand(
      "point", "Target in the flange frame from ≥ 4 measured configurations, base from a cell");
  point->add_option("--robot", point_o->robot, "Built-in robot name or robot file")->required();
  point->add_option("--cell", point_o->cell, "Cell file giving the robot's base")->required();
  point->add_option("--measurements", point_o->first, "Points file of one target")->required();
  point->add_option("--target", point_o->target, "Target measured")->capture_default_str();
  point->add_option("--tool", point_o->tool, "Tool file to update (default: a new tool)");
  common(point, *point_o);
  point->callback([point_o] { run_point(*point_o); });

  auto world_o = std::make_shared<FramesOptions>();
  auto* world = frames->add_subcommand(
      "world", "A frame (table, world) from ≥ 3 nests measured against their coordinates");
  world->add_option("--measured", world_o->measured, "Nests as measured: name,x,y,z (mm)")
      ->required();
  world->add_option("--nominal", world_o->nominal, "Nests in the frame to set up: name,x,y,z (mm)")
      ->required();
  common(world, *world_o);
  world->callback([world_o] { run_world(*world_o); });
});

}  // namespace
}  // namespace robcal::cli
