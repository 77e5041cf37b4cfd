/// `robcal ballbar-path`: the ballbar test path around a taught centre, its joint targets and the
/// checks made before anything moves (validate/ballbar_path.hpp).

#include <fmt/format.h>

#include <algorithm>
#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/validate/test_workflows.hpp"

namespace robcal::cli {
namespace {

struct Options {
  BallbarPathFilesRequest request;
  std::string centre, axis = "0,0,1", elevations = "0", orientation = "0,0,1,0",
                      config = "front-up-noflip";
  bool json = false;
};

void run(Options o) {
  BallbarPathRequest& request = o.request.path;
  const std::vector<double> c = parse_numbers(o.centre, 3, "--centre");
  request.centre_mm = Eigen::Vector3d(c[0], c[1], c[2]);
  const std::vector<double> a = parse_numbers(o.axis, 3, "--axis");
  request.axis = Eigen::Vector3d(a[0], a[1], a[2]);
  const size_t rings =
      static_cast<size_t>(std::count(o.elevations.begin(), o.elevations.end(), ',')) + 1;
  request.elevations_deg = parse_numbers(o.elevations, static_cast<int>(rings), "--elevations");
  request.world_R_tcp = parse_orientation(o.orientation, "--orientation");
  request.config = parse_config(o.config);
  const BallbarPathFiles result = ballbar_path_files(o.request);
  for (const std::string& note : result.notes) fmt::print(stderr, "note: {}\n", note);
  if (o.json) {
    print_json(ballbar_path_json(result));
    return;
  }
  fmt::print(
      "ballbar path: {} points on {} ring(s) of radius {:g} mm around ({:.3f}, {:.3f}, {:.3f}) "
      "mm, all reachable in {}\n",
      result.path.points.size(), request.elevations_deg.size(), request.length_mm, c[0], c[1], c[2],
      request.config.label());
  fmt::print(
      "predicted readings within {:.4f} mm of the length ({}; the bar reads ±{:g} mm)\nwrote {}\n",
      result.largest_offset_mm,
      o.request.reading_model.empty() ? "the commanding model itself" : o.request.reading_model,
      request.range_mm, result.out);
}

const bool ballbar_path_registered = register_command(67, [](CLI::App& app) {
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "ballbar-path",
      "Ballbar test path around a taught centre: joint targets, reachability and "
      "the bar's range checked before anything moves");
  cmd->add_option("--robot", o->request.robot, "Built-in robot name or robot file")->required();
  cmd->add_option("--tool", o->request.tool, "Tool file (the ball is one of its targets)")
      ->required();
  cmd->add_option("--target", o->request.target, "The tool's target that carries the ball")
      ->required();
  cmd->add_option("--model", o->request.model, "Model that commands the path (default: nominal)");
  cmd->add_option("--reading-model", o->request.reading_model,
                  "Model that predicts the readings (e.g. a calibrated one; default: --model)");
  cmd->add_option("--centre", o->centre, "Taught centre X,Y,Z (mm, world)")->required();
  cmd->add_option("--length", o->request.path.length_mm, "The bar's length (mm)")->required();
  cmd->add_option("--range", o->request.path.range_mm, "The bar reads length ± range (mm)")
      ->capture_default_str();
  cmd->add_option("--axis", o->axis, "Circle normal / sphere pole")->capture_default_str();
  cmd->add_option("--elevations", o->elevations, "Ring elevations (deg), comma separated")
      ->capture_default_str();
  cmd->add_option("--points", o->request.path.points_per_ring, "Points per ring")
      ->capture_default_str();
  cmd->add_option("--orientation", o->orientation, "TCP orientation qw,qx,qy,qz")
      ->capture_default_str();
  cmd->add_option("--config", o->config, "Arm configuration")->capture_default_str();
  cmd->add_option("--out", o->request.out, "Configurations CSV (config,target,j1..j6)")->required();
  cmd->add_flag("--json", o->json, "Machine-readable output");
  cmd->callback([o] { run(*o); });
});

}  // namespace
}  // namespace robcal::cli
