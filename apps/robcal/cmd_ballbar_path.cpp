/// `robcal ballbar-path`: the ballbar test path around a taught centre, its joint targets and the
/// checks made before anything moves (validate/ballbar_path.hpp).

#include <fmt/format.h>

#include <algorithm>
#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/validate/ballbar_path.hpp"

namespace robcal::cli {
namespace {

struct Options {
  std::string robot, tool, model, reading_model, target, centre,
      axis = "0,0,1", elevations = "0", orientation = "0,0,1,0", config = "front-up-noflip", out;
  double length = 0, range = 1.0;
  int points = 12;
  bool json = false;
};

CalibratedRobot load_model_of(const std::string& path, const RobotModel& model, const Tool& tool) {
  CalibratedRobot robot = load_calibrated_robot(path);
  if (robot.model.name != model.name)
    throw InputError({path, 0, 0, ""}, fmt::format("this is a model of the {}, not of the {}",
                                                   robot.model.name, model.name));
  if (robot.tool.targets.empty()) robot.tool = tool;
  return robot;
}

void run(const Options& o) {
  const RobotModel model = load_robot(o.robot);
  const Tool tool = load_tool(o.tool);
  BallbarPathRequest request;
  request.robot =
      o.model.empty() ? CalibratedRobot::nominal(model, tool) : load_model_of(o.model, model, tool);
  if (!o.reading_model.empty()) request.reading_model = load_model_of(o.reading_model, model, tool);
  request.target = request.robot.tool.target_index(o.target);
  if (request.target < 0)
    throw InputError({o.tool, 0, 0, "--target"},
                     fmt::format("no target '{}' in the tool", o.target));
  const std::vector<double> c = parse_numbers(o.centre, 3, "--centre");
  request.centre_mm = Eigen::Vector3d(c[0], c[1], c[2]);
  const std::vector<double> a = parse_numbers(o.axis, 3, "--axis");
  request.axis = Eigen::Vector3d(a[0], a[1], a[2]);
  request.length_mm = o.length;
  request.range_mm = o.range;
  const size_t rings =
      static_cast<size_t>(std::count(o.elevations.begin(), o.elevations.end(), ',')) + 1;
  request.elevations_deg = parse_numbers(o.elevations, static_cast<int>(rings), "--elevations");
  request.points_per_ring = o.points;
  request.world_R_tcp = parse_orientation(o.orientation, "--orientation");
  request.config = parse_config(o.config);
  const BallbarPath path = ballbar_path(request);
  if (path.problems() > 0) {
    std::string list;
    for (const BallbarPathPoint& p : path.points)
      if (!p.problem.empty())
        list += fmt::format("\n  elevation {:g}°, azimuth {:g}° at ({:.3f}, {:.3f}, {:.3f}) mm: {}",
                            p.elevation_deg, p.azimuth_deg, p.position_mm.x(), p.position_mm.y(),
                            p.position_mm.z(), p.problem);
    throw InputError({"", 0, 0, "--centre"},
                     fmt::format("{} of {} path points fail the checks (nothing written):{}",
                                 path.problems(), path.points.size(), list));
  }
  write_file_atomically(o.out, ballbar_path_csv(path, o.target));
  double worst = 0;
  for (const BallbarPathPoint& p : path.points)
    worst = std::max(worst, std::abs(p.predicted_offset_mm));
  if (o.json) {
    print_json(
        {{"points", path.points.size()}, {"largest_predicted_offset_mm", worst}, {"out", o.out}});
    return;
  }
  fmt::print(
      "ballbar path: {} points on {} ring(s) of radius {:g} mm around ({:.3f}, {:.3f}, {:.3f}) "
      "mm, all reachable in {}\n",
      path.points.size(), request.elevations_deg.size(), o.length, c[0], c[1], c[2],
      request.config.label());
  fmt::print(
      "predicted readings within {:.4f} mm of the length ({}; the bar reads ±{:g} mm)\nwrote {}\n",
      worst, o.reading_model.empty() ? "the commanding model itself" : o.reading_model, o.range,
      o.out);
}

const bool registered = register_command(67, [](CLI::App& app) {
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "ballbar-path",
      "Ballbar test path around a taught centre: joint targets, reachability and "
      "the bar's range checked before anything moves");
  cmd->add_option("--robot", o->robot, "Built-in robot name or robot file")->required();
  cmd->add_option("--tool", o->tool, "Tool file (the ball is one of its targets)")->required();
  cmd->add_option("--target", o->target, "The tool's target that carries the ball")->required();
  cmd->add_option("--model", o->model, "Model that commands the path (default: nominal)");
  cmd->add_option("--reading-model", o->reading_model,
                  "Model that predicts the readings (e.g. a calibrated one; default: --model)");
  cmd->add_option("--centre", o->centre, "Taught centre X,Y,Z (mm, world)")->required();
  cmd->add_option("--length", o->length, "The bar's length (mm)")->required();
  cmd->add_option("--range", o->range, "The bar reads length ± range (mm)")->capture_default_str();
  cmd->add_option("--axis", o->axis, "Circle normal / sphere pole")->capture_default_str();
  cmd->add_option("--elevations", o->elevations, "Ring elevations (deg), comma separated")
      ->capture_default_str();
  cmd->add_option("--points", o->points, "Points per ring")->capture_default_str();
  cmd->add_option("--orientation", o->orientation, "TCP orientation qw,qx,qy,qz")
      ->capture_default_str();
  cmd->add_option("--config", o->config, "Arm configuration")->capture_default_str();
  cmd->add_option("--out", o->out, "Configurations CSV (config,target,j1..j6)")->required();
  cmd->add_flag("--json", o->json, "Machine-readable output");
  cmd->callback([o] { run(*o); });
});

}  // namespace
}  // namespace robcal::cli
