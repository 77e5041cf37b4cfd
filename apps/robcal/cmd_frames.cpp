/// `robcal frames base|tool|world`: frames set up as the published method does, from
/// single-joint sweeps and table nests (campaign/frames.hpp), written with their σ.

#include <fmt/format.h>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/campaign/frames_workflow.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal::cli {
namespace {

struct FramesOptions {
  std::string robot, first, second, target = "1", cell, tool, out;
  std::string measured, nominal;
  double sigma_mm = 0;
  bool json = false;

  [[nodiscard]] campaign::TargetFrameRequest target_request() const {
    return {robot, first, second, cell, target, tool, sigma_mm};
  }
};

void print_frame(const std::string& what, const campaign::FrameEstimate& f) {
  fmt::print("{} (value ± 1σ; noise σ {:.4f} mm, fit rms {:.4f} mm)\n", what, f.sigma_mm, f.rms_mm);
  const char* names[] = {"x", "y", "z", "alpha", "beta", "gamma"};
  for (int i = 0; i < 6; ++i)
    fmt::print("  {:<6} {:>14.4f} ± {:.4f} {}\n", names[i],
               i < 3 ? f.values[i] : rad2deg(f.values[i]), i < 3 ? f.sigma[i] : rad2deg(f.sigma[i]),
               i < 3 ? "mm" : "deg");
}

void run_base(const FramesOptions& o) {
  const campaign::BaseFrameResult result =
      campaign::frames_base({o.robot, o.first, o.second, o.target, o.cell, o.sigma_mm});
  write_file_atomically(o.out, result.text);
  if (o.json) {
    print_json({{"base", campaign::frame_estimate_json(result.base)}, {"out", o.out}});
    return;
  }
  print_frame(fmt::format("base of {} in the instrument frame", result.robot), result.base);
  fmt::print("wrote {}{}\n", o.out,
             o.cell.empty() ? " (a robot_base block for the cell file)" : "");
}

void print_target(const FramesOptions& o, const campaign::TargetFrameResult& result) {
  write_file_atomically(o.out, result.text);
  if (o.json) {
    nlohmann::json out = campaign::target_estimate_json(result.target, result.point);
    out["out"] = o.out;
    print_json(out);
    return;
  }
  const campaign::PointEstimate& t = result.point;
  fmt::print("target {} in the flange frame of {} (value ± 1σ; noise σ {:.4f} mm)\n", result.target,
             result.robot, t.sigma_mm);
  for (int k = 0; k < 3; ++k)
    fmt::print("  {} {:>12.4f} ± {:.4f} mm\n", static_cast<char>('x' + k), t.position_mm[k],
               t.sigma[k]);
  fmt::print("wrote {}\n", o.out);
}

void run_world(const FramesOptions& o) {
  const campaign::NestFrameResult result =
      campaign::frames_world({o.measured, o.nominal, o.sigma_mm});
  write_file_atomically(o.out, result.text);
  if (o.json) {
    nlohmann::json out = campaign::nest_frame_json(result);
    out["out"] = o.out;
    print_json(out);
    return;
  }
  print_frame("frame of the nests in the instrument frame", result.frame);
  const Eigen::Vector3d& i = result.instrument_mm;
  fmt::print("instrument in that frame: {:.4f} {:.4f} {:.4f} mm\nwrote {}\n", i.x(), i.y(), i.z(),
             o.out);
}

const bool frames_registered = register_command(76, [](CLI::App& app) {
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
  tool->callback(
      [tool_o] { print_target(*tool_o, campaign::frames_tool(tool_o->target_request())); });

  auto point_o = std::make_shared<FramesOptions>();
  auto* point = frames->add_subcommand(
      "point", "Target in the flange frame from ≥ 4 measured configurations, base from a cell");
  point->add_option("--robot", point_o->robot, "Built-in robot name or robot file")->required();
  point->add_option("--cell", point_o->cell, "Cell file giving the robot's base")->required();
  point->add_option("--measurements", point_o->first, "Points file of one target")->required();
  point->add_option("--target", point_o->target, "Target measured")->capture_default_str();
  point->add_option("--tool", point_o->tool, "Tool file to update (default: a new tool)");
  common(point, *point_o);
  point->callback(
      [point_o] { print_target(*point_o, campaign::frames_point(point_o->target_request())); });

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
