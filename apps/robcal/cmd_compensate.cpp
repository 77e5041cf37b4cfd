/// `robcal compensate`: corrected targets for the controller from wanted world poses and a
/// calibrated model; `robcal compensate-program`: the same applied to every point of an ABB
/// RAPID module or a KUKA KRL file (docs/method/10-compensation.md, 02-frames.md §7).

#include <fmt/format.h>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/compensate/closed_loop.hpp"
#include "robcal/compensate/corrected_targets.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/programs/frames_file.hpp"
#include "robcal/programs/program_filter.hpp"

namespace robcal::cli {
namespace {

struct ModelOptions {
  std::string robot;
  std::string model;
  std::string tool;
  std::string payload_mass;
  std::string payload_cog;
  std::string method = "newton";
  bool json = false;
};

/// The calibrated robot with the tool file's TCP and payload, and the payload override.
CalibratedRobot load_model(const ModelOptions& o, std::optional<PointMass>& payload) {
  CalibratedRobot robot = load_calibrated_robot(o.model);
  if (!o.robot.empty() && load_robot(o.robot).name != robot.model.name)
    throw InputError({o.model, 0, 0, "--robot"},
                     fmt::format("the model is a calibrated {}, not a {}", robot.model.name,
                                 load_robot(o.robot).name));
  if (!o.tool.empty()) {
    const Tool tool = load_tool(o.tool);
    robot.tool.flange_T_tcp = tool.flange_T_tcp;
    robot.tool.payload = tool.payload;
  }
  if (o.payload_mass.empty() != o.payload_cog.empty())
    throw InputError({"", 0, 0, o.payload_mass.empty() ? "--payload-mass-kg" : "--payload-cog-mm"},
                     "give both --payload-mass-kg and --payload-cog-mm");
  if (!o.payload_mass.empty()) {
    const double mass = parse_numbers(o.payload_mass, 1, "--payload-mass-kg")[0];
    if (!(mass >= 0 && mass < 1e4))
      throw InputError({"", 0, 0, "--payload-mass-kg"}, "expected a mass in kg, 0 or more");
    const auto cog = parse_numbers(o.payload_cog, 3, "--payload-cog-mm");
    payload = PointMass{mass, Eigen::Vector3d(cog[0], cog[1], cog[2])};
  }
  return robot;
}

IkMethod parse_method(const std::string& text) {
  if (text == "newton") return IkMethod::Newton;
  if (text == "pose-shift") return IkMethod::PoseShift;
  throw InputError({"", 0, 0, "--method"}, "expected newton or pose-shift, found '" + text + "'");
}

nlohmann::json stats_json(const ToolErrorStats& s) {
  return {{"count", s.count},
          {"mean_mm", tidy(s.mean_mm, 6)},
          {"rms_mm", tidy(s.rms_mm, 6)},
          {"max_mm", tidy(s.max_mm, 6)},
          {"mean_deg", tidy(s.mean_deg, 6)},
          {"max_deg", tidy(s.max_deg, 6)}};
}

void run_compensate(const ModelOptions& o, const std::string& targets, const std::string& out,
                    const std::string& check_truth) {
  std::optional<PointMass> payload;
  const CalibratedRobot robot = load_model(o, payload);
  const IkMethod method = parse_method(o.method);
  const Compensator comp = make_compensator(robot, payload);
  const std::vector<WantedTarget> wanted = read_pose_list(targets);
  const std::vector<CorrectedTarget> rows = correct_targets(comp, robot, wanted, targets, method);
  std::optional<ClosedLoopReport> loop;
  if (!check_truth.empty()) loop = closed_loop_check(comp, load_truth(check_truth), wanted, rows);
  write_file_atomically(out, corrected_targets_csv(rows, robot.model));

  int max_iterations = 0;
  double worst_mm = 0, worst_ci = 0;
  bool has_ci = false;
  for (const CorrectedTarget& r : rows) {
    max_iterations = std::max(max_iterations, r.ik.iterations);
    worst_mm = std::max(worst_mm, r.ik.position_error_mm);
    if (r.confidence95_mm) {
      has_ci = true;
      worst_ci = std::max(worst_ci, *r.confidence95_mm);
    }
  }
  if (o.json) {
    nlohmann::json j;
    j["robot"] = robot.model.name;
    j["targets"] = rows.size();
    j["out"] = out;
    j["method"] = o.method;
    j["payload_kg"] = comp.payload.mass_kg;
    j["max_iterations"] = max_iterations;
    j["max_residual_mm"] = worst_mm;
    j["max_confidence95_mm"] = has_ci ? nlohmann::json(tidy(worst_ci, 6)) : nlohmann::json();
    if (loop) {
      j["closed_loop"]["compensated"] = stats_json(loop->compensated);
      j["closed_loop"]["uncompensated"] = stats_json(loop->uncompensated);
    }
    print_json(j);
    return;
  }
  fmt::print("{} targets corrected for {} ({}), written to {}\n", rows.size(), robot.model.name,
             o.method, out);
  fmt::print("  calibrated-model residual ≤ {:.2g} mm, ≤ {} iterations; payload {} kg\n", worst_mm,
             max_iterations, comp.payload.mass_kg);
  if (has_ci) fmt::print("  95% position confidence radius ≤ {:.4f} mm\n", worst_ci);
  if (loop) {
    const auto line = [](const char* what, const ToolErrorStats& s) {
      fmt::print(
          "  {:<14} mean {:.4f} mm  RMS {:.4f} mm  max {:.4f} mm  max {:.4f} deg  ({} targets)\n",
          what, s.mean_mm, s.rms_mm, s.max_mm, s.max_deg, s.count);
    };
    fmt::print("closed loop on the true robot ({}):\n", check_truth);
    line("compensated", loop->compensated);
    line("uncompensated", loop->uncompensated);
  }
}

struct ProgramFilterFlags {
  std::string in, out, frames, confidence_out;
  bool joints = false;
  bool keep_going = false;
};

void run_compensate_program(const ModelOptions& o, const ProgramFilterFlags& f) {
  std::optional<PointMass> payload;
  const CalibratedRobot robot = load_model(o, payload);
  const Compensator comp = make_compensator(robot, payload);
  const ProgramLanguage language = program_language_from_path(f.in);
  ProgramFilterOptions options;
  options.joints = f.joints;
  options.keep_going = f.keep_going;
  if (!f.frames.empty()) {
    FramesFile frames = read_frames_file(f.frames);
    options.tools = std::move(frames.tools);
    options.frames = std::move(frames.frames);
  }
  const ProgramFilterResult result = filter_program_file(
      f.in, f.out, options, make_program_corrector(comp, language, &robot), f.confidence_out);
  if (o.json) {
    nlohmann::json uncorrected = nlohmann::json::array();
    for (const UncorrectedPoint& u : result.uncorrected)
      uncorrected.push_back({{"where", u.where}, {"reason", u.reason}});
    print_json({{"in", f.in},
                {"out", f.out},
                {"language", program_language_name(language)},
                {"cartesian_points", result.cartesian_points},
                {"joint_points", result.joint_points},
                {"uncorrected", uncorrected},
                {"assumed_default_tool_and_frame", result.assumed.size()}});
    return;
  }
  fmt::print("{}: {} Cartesian point{} and {} joint target{} corrected, written to {}\n", f.in,
             result.cartesian_points, result.cartesian_points == 1 ? "" : "s", result.joint_points,
             result.joint_points == 1 ? "" : "s", f.out);
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
                  "Built-in robot name or robot file (checked against the model)");
  cmd->add_option("--tool", o.tool, "Tool file: its TCP and payload replace the model's");
  cmd->add_option("--payload-mass-kg", o.payload_mass,
                  "Payload carried now, if not the tool's (the compliance re-compensates)");
  cmd->add_option("--payload-cog-mm", o.payload_cog,
                  "Its centre of gravity x,y,z in the flange frame");
  cmd->add_flag("--json", o.json, "Machine-readable summary on stdout");
}

const bool registered = register_command(70, [](CLI::App& app) {
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
                  "CSV name,x,y,z,qw,qx,qy,qz[,config]: wanted TCP poses in the world (mm)")
      ->required();
  cmd->add_option("--out", *out,
                  "Output CSV name,config,j1..j6 (deg),x,y,z,qw,qx,qy,qz (nominal target in the "
                  "base frame),A/B/C or W/P/R,iterations,residual_mm,confidence95_mm")
      ->required();
  cmd->add_option("--method", o->method, "newton (default) or pose-shift");
  cmd->add_option("--check-truth", *truth,
                  "Truth file of a simulation: command the corrected joints on the true robot "
                  "and report the error at the tool, beside the uncompensated error");
  cmd->callback([=] { run_compensate(*o, *targets, *out, *truth); });

  auto* prog = app.add_subcommand(
      "compensate-program",
      "Rewrite every target of a RAPID, KRL, Fanuc LS or URScript program with corrected "
      "values for the tool and frame active at it, leaving every other byte as it was");
  auto po = std::make_shared<ModelOptions>();
  auto pf = std::make_shared<ProgramFilterFlags>();
  add_model_options(prog, *po);
  prog->add_option("--in", pf->in,
                   "Program: .mod/.modx/.prg/.sys (RAPID), .src/.dat (KRL), .ls (Fanuc), "
                   ".script (URScript)")
      ->required();
  prog->add_option("--out", pf->out, "Corrected program (a new file; the input is kept)")
      ->required();
  prog->add_flag("--joints", pf->joints,
                 "Also correct joint targets (MoveAbsJ, E6AXIS/AXIS, Fanuc J1..J6)");
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
