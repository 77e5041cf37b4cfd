/// `robcal compensate`: corrected targets for the controller from wanted world poses and a
/// calibrated model; `robcal compensate-program`: the same applied to every point of a robot
/// program (docs/method/10-compensation.md, 02-frames.md §7). Parse, call
/// compensate_targets / compensate_program, print.

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/compensate/compensate_targets.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/robot_pulses.hpp"
#include "robcal/programs/program_compensation.hpp"

namespace robcal::cli {
namespace {

struct ModelOptions {
  std::string robot;
  std::string model;
  std::string tool;
  std::string payload_mass;
  std::string payload_cog;
  std::string payload_name;
  std::string method = "newton";
  std::string approach = "++++++";
  std::string temperature;
  std::string warmup_time;
  bool warm = false;
  bool json = false;
};

CompensationSetup parse_setup(const ModelOptions& o) {
  CompensationSetup setup;
  setup.robot = load_calibrated_robot(o.model);
  setup.model_file = o.model;
  if (!o.robot.empty()) {
    setup.expected_robot = load_robot(o.robot).name;
    setup.pulses_per_degree = robot_pulses_per_degree(o.robot);
  }
  if (!o.tool.empty()) setup.tool = load_tool(o.tool);
  if (o.payload_mass.empty() != o.payload_cog.empty())
    throw InputError({"", 0, 0, o.payload_mass.empty() ? "--payload-mass-kg" : "--payload-cog-mm"},
                     "give both --payload-mass-kg and --payload-cog-mm");
  if (!o.payload_mass.empty()) {
    const auto cog = parse_numbers(o.payload_cog, 3, "--payload-cog-mm");
    setup.payload = PointMass{parse_numbers(o.payload_mass, 1, "--payload-mass-kg")[0],
                              Eigen::Vector3d(cog[0], cog[1], cog[2])};
  }
  setup.approach = parse_approach(o.approach, {"", 0, 0, "--approach"});
  setup.payload_name = o.payload_name;
  if (!o.temperature.empty())
    setup.temperature_c = parse_numbers(o.temperature, 1, "--temperature-c")[0];
  if (!o.warmup_time.empty())
    setup.warmup_time_s = parse_numbers(o.warmup_time, 1, "--warmup-time-s")[0];
  setup.warm = o.warm;
  return setup;
}

void run_compensate(const ModelOptions& o, const std::string& targets, const std::string& out,
                    const std::string& check_truth) {
  CompensateTargetsRequest request;
  request.setup = parse_setup(o);
  request.method = ik_method_from_name(o.method);
  request.targets = read_pose_list(targets);
  request.targets_file = targets;
  if (!check_truth.empty()) request.truth = load_truth(check_truth);
  request.out = out;
  const CompensateTargetsResult r = compensate_targets(request);
  if (o.json) {
    print_json(nlohmann::json(r));
    return;
  }
  fmt::print("{} targets corrected for {} ({}), written to {}\n", r.rows.size(), r.robot,
             ik_method_name(r.method), r.out);
  if (r.conditions > 1)
    fmt::print("  each under its own approach, temperature, warm-up and payload: {} conditions\n",
               r.conditions);
  fmt::print("  calibrated-model residual ≤ {:.2g} mm, ≤ {} iterations; payload {} kg\n",
             r.max_residual_mm, r.max_iterations, r.payload_kg);
  if (r.max_confidence95_mm)
    fmt::print("  95% position confidence radius ≤ {:.4f} mm\n", *r.max_confidence95_mm);
  if (r.closed_loop) {
    const auto line = [](const char* what, const ToolErrorStats& s) {
      fmt::print(
          "  {:<14} mean {:.4f} mm  RMS {:.4f} mm  max {:.4f} mm  max {:.4f} deg  ({} targets)\n",
          what, s.mean_mm, s.rms_mm, s.max_mm, s.max_deg, s.count);
    };
    fmt::print("closed loop on the true robot ({}):\n", check_truth);
    line("compensated", r.closed_loop->compensated);
    line("uncompensated", r.closed_loop->uncompensated);
  }
}

struct ProgramFilterFlags {
  std::string in, out, frames, confidence_out;
  bool joints = false;
  bool keep_going = false;
};

void run_compensate_program(const ModelOptions& options, const ProgramFilterFlags& f) {
  ProgramCompensationRequest request;
  ModelOptions o = options;
  request.approach_from_motion = o.approach == "motion";
  if (request.approach_from_motion) o.approach = ModelOptions{}.approach;
  request.setup = parse_setup(o);
  request.in = f.in;
  request.out = f.out;
  request.confidence_out = f.confidence_out;
  request.frames_file = f.frames;
  request.options.joints = f.joints;
  request.options.keep_going = f.keep_going;
  const ProgramCompensationResult r = compensate_program(request);
  if (o.json) {
    print_json(nlohmann::json(r));
    return;
  }
  const ProgramFilterResult& result = r.filter;
  fmt::print("{}: {} Cartesian point{} and {} joint target{} corrected, written to {}\n", r.in,
             result.cartesian_points, result.cartesian_points == 1 ? "" : "s", result.joint_points,
             result.joint_points == 1 ? "" : "s", r.out);
  if (!r.out_companion.empty())
    fmt::print("KUKA module: its {} read and corrected with it, written to {}\n",
               krl_companion_path(r.in), r.out_companion);
  if (!result.assumed.empty()) {
    fmt::print(
        "{} point{} corrected for the default tool (--tool) in the base frame, which "
        "the program does not confirm; check:\n",
        result.assumed.size(), result.assumed.size() == 1 ? "" : "s");
    for (const UncorrectedPoint& u : result.assumed) fmt::print("  {}: {}\n", u.where, u.reason);
  }
  if (!result.uncorrected.empty()) {
    fmt::print("{} point{} left as written (not corrected):\n", result.uncorrected.size(),
               result.uncorrected.size() == 1 ? "" : "s");
    for (const UncorrectedPoint& u : result.uncorrected)
      fmt::print("  {}: {}\n", u.where, u.reason);
  }
}

void add_model_options(CLI::App* cmd, ModelOptions& o) {
  cmd->add_option("--model", o.model, "Calibrated model file (what `robcal calibrate` writes)")
      ->required();
  cmd->add_option("--robot", o.robot,
                  "Built-in robot name or robot file (checked against the model; Yaskawa: its "
                  "pulses_per_degree)");
  cmd->add_option("--tool", o.tool, "Tool file: its TCP and payload replace the model's");
  cmd->add_option("--payload-mass-kg", o.payload_mass,
                  "Payload carried now, if not the tool's (the compliance re-compensates)");
  cmd->add_option("--payload-cog-mm", o.payload_cog,
                  "Its centre of gravity x,y,z in the flange frame");
  cmd->add_option("--approach", o.approach,
                  "Side each joint reaches the targets from, one of + (below, as the measurement "
                  "programs do), - (above), 0 (unknown) per joint: the backlash group's sign; "
                  "compensate-program also 'motion': each point from its move from the previous "
                  "one (the first from below)")
      ->capture_default_str();
  cmd->add_option("--payload", o.payload_name,
                  "Payload carried now by name, one of the tool's 'payloads:' (the compliance "
                  "re-compensates)");
  cmd->add_option("--temperature-c", o.temperature,
                  "The arm's temperature (°C) at the targets, for the thermal group (default: "
                  "the robot's reference temperature, 20 °C)");
  cmd->add_option("--warmup-time-s", o.warmup_time,
                  "How long the arm has worked (s) at the targets, for the warm-up group "
                  "(default: cold)");
  cmd->add_flag("--warm", o.warm, "The arm is fully warm at the targets (warm-up group)");
  cmd->add_flag("--json", o.json, "Machine-readable summary on stdout");
}

const bool compensate_registered = register_command(70, [](CLI::App& app) {
  auto* cmd =
      app.add_subcommand("compensate",
                         "Corrected targets: the joints and nominal poses that make the controller "
                         "reach wanted world poses");
  auto o = std::make_shared<ModelOptions>();
  auto targets = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto truth = std::make_shared<std::string>();
  add_model_options(cmd, *o);
  cmd->add_option("--targets", *targets,
                  "CSV name,x,y,z,qw,qx,qy,qz[,config][,approach][,temperature][,time_s]"
                  "[,payload]: wanted TCP poses in the world (mm), a row's approach, temperature "
                  "(°C), warm-up time (s, or warm) and payload replacing --approach, "
                  "--temperature-c, --warmup-time-s/--warm and --payload for it")
      ->required();
  cmd->add_option("--out", *out,
                  "Output CSV name,config,j1..j6 (deg),x,y,z,qw,qx,qy,qz (nominal target in the "
                  "base frame),A/B/C or W/P/R,iterations,residual_mm,confidence95_mm[,approach,"
                  "temperature,payload[,time_s]: each row's condition, when the targets give "
                  "any]")
      ->required();
  cmd->add_option("--method", o->method, "newton (default) or pose-shift");
  cmd->add_option("--check-truth", *truth,
                  "Truth file of a simulation: command the corrected joints on the true robot "
                  "and report the error at the tool, beside the uncompensated error");
  cmd->callback([=] { run_compensate(*o, *targets, *out, *truth); });

  auto* prog = app.add_subcommand(
      "compensate-program",
      "Rewrite every target of a RAPID, KRL, Fanuc LS, Yaskawa JBI or URScript program with "
      "corrected "
      "values for the tool and frame active at it, leaving every other byte as it was");
  auto po = std::make_shared<ModelOptions>();
  auto pf = std::make_shared<ProgramFilterFlags>();
  add_model_options(prog, *po);
  prog->add_option("--in", pf->in,
                   "Program: .mod/.modx/.prg/.sys (RAPID), .src/.dat (KRL), .ls (Fanuc), "
                   ".jbi (Yaskawa), .script (URScript)")
      ->required();
  prog->add_option("--out", pf->out, "Corrected program (a new file; the input is kept)")
      ->required();
  prog->add_flag("--joints", pf->joints,
                 "Also correct joint targets (MoveAbsJ, E6AXIS/AXIS, Fanuc J1..J6, Yaskawa "
                 "pulse positions)");
  prog->add_option("--frames", pf->frames,
                   "Frames file kind,name,x,y,z,qw,qx,qy,qz: tools and work objects/bases the "
                   "program uses but does not define");
  prog->add_flag("--keep-going", pf->keep_going,
                 "Leave a target that cannot be corrected as written (listed at the end) "
                 "instead of refusing the program");
  prog->add_option("--confidence-out", pf->confidence_out,
                   "CSV of the 95% confidence radius of each corrected target "
                   "(line,column,name,confidence95_mm)");
  prog->callback([=] { run_compensate_program(*po, *pf); });
});

}  // namespace
}  // namespace robcal::cli
