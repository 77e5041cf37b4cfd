/// `robcal hexapod calibrate | export-poses | replan | simulate-readings`: from measurement
/// sessions of the ballbar hexapod to a calibrated model (docs/method/07-hexapod.md, published
/// procedure), the two-stage way: calibrate on what was measurable, re-plan the configurations that
/// were out of the ballbar's range on that preliminary model, measure them, calibrate on
/// everything.

#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/hexapod/measurement.hpp"
#include "robcal/hexapod/plan_file.hpp"
#include "robcal/hexapod/replan.hpp"
#include "robcal/hexapod/session_calibration.hpp"
#include "robcal/hexapod/session_data.hpp"
#include "robcal/hexapod/simulated_readings.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal::cli {
namespace {

using namespace robcal::hexapod;

/// The sessions to read: directories (plan.json + journal.jsonl) or one journal with --plan.
struct SessionOptions {
  std::vector<std::string> sessions;
  std::string plan;
  std::string tool;  ///< payload source

  /// `with_tool`: the command takes the payload from --tool (replan takes it from the model).
  void add_to(CLI::App* cmd, bool with_tool = true) {
    cmd->add_option("--session", sessions,
                    "Session directory (plan.json + journal.jsonl) or journal file; repeat for the "
                    "first pass and the re-measurement of its retries (calibrate: and for the "
                    "sessions of other base-fixture placements)")
        ->required();
    cmd->add_option("--plan", plan, "Plan of a journal file given as --session");
    if (with_tool)
      cmd->add_option("--tool", tool,
                      "Tool file whose payload (mass, CoG) the robot carried (default: none); its "
                      "targets are replaced by the tool fixture's cups");
  }
  [[nodiscard]] SessionData load() const { return load_sessions(sessions, plan); }
  [[nodiscard]] PointMass payload() const {
    return tool.empty() ? PointMass{} : load_tool(tool).payload;
  }
};

void print_session_summary(const SessionData& data, const WorldFrameFit& world) {
  fmt::print(
      "sessions {}: {} configurations measured, {} to retry, {} not reached; world frame from the "
      "base cups rms {:.4f} mm\n",
      data.source, data.readings.size(), data.retry.size(), data.pending, world.rms_mm);
}

/// The files a command writes, all rendered before any is written: an error on the way (a
/// configuration without a direct-kinematics solution, say) leaves no file behind.
class OutputFiles {
 public:
  void add(const std::string& path, std::string text) {
    if (!path.empty()) files_.emplace_back(path, std::move(text));
  }
  void add(const RenderedFiles& files) {
    for (const auto& [path, text] : files) add(path, text);
  }
  void write() const {
    for (const auto& [path, text] : files_) write_file_atomically(path, text);
  }

 private:
  std::vector<std::pair<std::string, std::string>> files_;
};

// ---- calibrate -------------------------------------------------------------------------------

struct CalibrateOptions {
  SessionOptions session;
  std::string robot = "fanuc-lrmate200ic";
  std::string level = "full";
  std::vector<std::string> identify;
  std::string fit = "poses";
  bool relative = false;
  double orientation_weight = kDefaultOrientationWeightMm;
  uint64_t seed = 1;
  std::string out, poses_out, legs_out, tool_out;
  bool json = false;
};

void run_calibrate(const CalibrateOptions& o) {
  SessionCalibrationRequest request;
  request.fit = parse_session_fit(o.fit);
  request.level = parse_calibration_level(o.level);
  request.identify = o.identify;
  check_identify_patterns(request.level, request.identify);
  request.relative = o.relative;
  request.orientation_weight_mm = o.orientation_weight;
  request.seed = o.seed;
  const RobotModel model = load_robot(o.robot);
  request.exports = {o.poses_out, o.legs_out, o.tool_out};
  // The small files first: a bad --tool is named before the sessions are read.
  const PointMass payload = o.session.payload();
  const std::vector<SessionData> placements = load_placements(o.session.sessions, o.session.plan);
  const SessionData& data = placements.front();
  if (request.fit == SessionFit::Poses && !o.json && stdout_is_terminal())
    fmt::print("calibrating ({} poses)…\n", data.readings.size());
  const SessionCalibration c = calibrate_sessions(placements, model, payload, request);
  OutputFiles files;
  files.add(o.out, c.model_file);
  files.add(c.exports);
  files.write();
  if (o.json) {
    print_json(session_calibration_json(placements, model, c, o.out));
    return;
  }
  size_t measured = 0;
  for (size_t p = 0; p < placements.size(); ++p) {
    if (placements.size() > 1) fmt::print("placement {}: ", p + 1);
    print_session_summary(placements[p], c.placement_worlds[p]);
    measured += placements[p].readings.size();
  }
  if (c.legs) {
    const LegFitResult& fit = *c.legs;
    fmt::print(
        "calibrated {} at level {} from the raw legs of {} configurations ({} distances): {} "
        "after {} iterations, rms {:.5f} mm (start {:.4f}); ballbar offset {:+.5f} mm; {} model "
        "parameters identified\nwritten {}\n",
        model.name, c.robot.level, measured, fit.residuals,
        fit.converged ? "converged" : "DID NOT CONVERGE", fit.iterations, fit.rms_mm,
        fit.initial_rms_mm, fit.length_offset_mm, fit.identified.size(), o.out);
    for (const std::string& h : fit.held) fmt::print("  held {}\n", h);
    return;
  }
  const IdentificationResult& r = *c.identification;
  fmt::print(
      "calibrated {} at level {}{} from {} poses: {} after {} iterations, {} unknowns "
      "identified\n"
      "TCP error per pose, mm: mean {:.4f} rms {:.4f} max {:.4f} (nominal at the start: mean "
      "{:.4f} rms {:.4f} max {:.4f})\nwritten {}\n",
      model.name, r.robot.level, o.relative ? " (relative: base held)" : "", c.poses.size(),
      r.status.converged ? "converged" : "DID NOT CONVERGE", r.status.iterations,
      r.identified_count, r.mean_mm, r.rms_mm, r.max_mm, r.start_mean_mm, r.start_rms_mm,
      r.start_max_mm, o.out);
  if (!data.retry.empty())
    fmt::print(
        "{} configurations were out of the ballbar's range: re-plan them on this model with "
        "`robcal hexapod replan --session … --model {} --out PLAN`, measure them in a new session "
        "and calibrate on all sessions\n",
        data.retry.size(), o.out);
}

// ---- export-poses ----------------------------------------------------------------------------

void run_export(const SessionOptions& s, const SessionExportPaths& paths, bool json) {
  const PointMass payload = s.payload();  // a bad --tool named before the session is read
  const SessionData data = s.load();
  const SessionExport exported = export_session(data, payload, paths);
  OutputFiles files;
  files.add(exported.files);
  files.write();
  if (json) {
    print_json(session_export_json(data, exported, paths));
    return;
  }
  print_session_summary(data, exported.world);
  fmt::print("written {}{}{}\n", paths.poses, paths.legs.empty() ? "" : ", " + paths.legs,
             paths.tool.empty() ? "" : ", " + paths.tool);
}

// ---- replan ----------------------------------------------------------------------------------

void run_replan(const SessionOptions& s, const std::string& model_path, const std::string& out,
                bool json) {
  const CalibratedRobot model = load_calibrated_robot(model_path);  // named before the session
  const Replan r = replan_retries(s.load(), model, model_path);
  write_hexapod_plan(out, r.plan);
  if (json) {
    print_json(replan_json(r, out));
    return;
  }
  fmt::print("{} of {} configurations to retry re-planned on {}; plan written to {}\n",
             r.plan.session.configurations.size(), r.retry, model_path, out);
  for (const ReplanFailure& f : r.failed) fmt::print("  {}: {}\n", f.config, f.why);
}

// ---- simulate-readings -----------------------------------------------------------------------

struct SimulateReadingsOptions {
  std::string plan, robot = "fanuc-lrmate200ic", out, validation_out, tool_out, payload;
  uint64_t seed = 1;
  int validation = 1000;
  bool json = false;
};

void run_simulate_readings(const SimulateReadingsOptions& o) {
  SimulatedReadingsRequest request{
      o.plan, std::nullopt, o.seed,
      o.validation_out.empty() ? std::min(o.validation, 0) : o.validation};
  if (!o.payload.empty()) request.payload = load_tool(o.payload).payload;
  const SimulatedReadings r =
      simulate_readings(read_hexapod_plan(o.plan), load_robot(o.robot), request);
  OutputFiles files;
  files.add(o.out, readings_text(r));
  files.add(o.tool_out, tool_to_yaml(r.tool));
  if (!r.validation.points.empty()) files.add(o.validation_out, validation_csv(r));
  files.write();
  if (o.json) {
    print_json(simulated_readings_json(r, o.out, o.tool_out, o.validation_out));
    return;
  }
  fmt::print("{} readings ({} legs out of range) for {} written to {} (seed {})\n",
             r.readings.size(), r.out_of_range, o.plan, o.out, o.seed);
}

const bool hexapod_calibrate_registered = register_command(61, [](CLI::App& app) {
  CLI::App* hex = app.get_subcommand("hexapod");
  {
    auto* cmd = hex->add_subcommand(
        "calibrate",
        "Calibrate from measurement sessions: tool fixture poses by the direct kinematics, world "
        "frame from the base cups, identification (`robcal calibrate`)");
    auto o = std::make_shared<CalibrateOptions>();
    o->session.add_to(cmd);
    cmd->add_option("--robot", o->robot, "Built-in robot name or robot file")
        ->capture_default_str();
    cmd->add_option("--level", o->level, "base, joints, kinematic or full")->capture_default_str();
    cmd->add_option("--identify", o->identify,
                    "Also identify the parameters matching this glob or opt-in group (repeatable), "
                    "as calibrate --identify takes them, e.g. periodic");
    cmd->add_option("--fit", o->fit,
                    "poses: identification (`robcal calibrate`) on the tool fixture poses; legs: "
                    "straight from the raw leg lengths, with the cups and the ballbar offset")
        ->capture_default_str();
    cmd->add_flag("--relative", o->relative,
                  "Hold the base parameters (the published relative model): keeps the error of "
                  "the world frame the uncalibrated robot gave the base cups");
    cmd->add_option("--orientation-weight", o->orientation_weight,
                    "Poses fit: mm per rad of orientation residual (as calibrate "
                    "--orientation-weight)")
        ->capture_default_str();
    cmd->add_option("--seed", o->seed, "Seed of the predicted-accuracy samples")
        ->capture_default_str();
    cmd->add_option("--out", o->out, "Calibrated model file to write (YAML)")->required();
    cmd->add_option("--poses-out", o->poses_out, "Also write the poses measurement CSV");
    cmd->add_option("--legs-out", o->legs_out, "Also write the raw legs CSV");
    cmd->add_option("--tool-out", o->tool_out, "Also write the tool file (fixture cups, TCP)");
    cmd->add_flag("--json", o->json, "Machine-readable summary");
    cmd->callback([o] { run_calibrate(*o); });
  }
  {
    auto* cmd = hex->add_subcommand(
        "export-poses",
        "Write a session's readings as a poses measurement CSV (for `robcal calibrate`), the raw "
        "legs CSV and the tool file");
    auto s = std::make_shared<SessionOptions>();
    auto paths = std::make_shared<SessionExportPaths>();
    auto json = std::make_shared<bool>(false);
    s->add_to(cmd);
    cmd->add_option("--out", paths->poses, "Poses CSV: config,j1..j6,x,y,z,qw,qx,qy,qz")
        ->required();
    cmd->add_option("--legs-out", paths->legs, "Raw legs CSV");
    cmd->add_option("--tool-out", paths->tool,
                    "Tool file: payload, cups T1..T3, TCP = tool fixture");
    cmd->add_flag("--json", *json, "Machine-readable summary");
    cmd->callback([=] { run_export(*s, *paths, *json); });
  }
  {
    auto* cmd = hex->add_subcommand(
        "replan",
        "Re-plan the configurations that were out of the ballbar's range on a preliminary model "
        "(the plan of the second session)");
    auto s = std::make_shared<SessionOptions>();
    auto model = std::make_shared<std::string>();
    auto out = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    s->add_to(cmd, false);
    cmd->add_option("--model", *model, "Preliminary model from `robcal hexapod calibrate`")
        ->required();
    cmd->add_option("--out", *out, "Plan file to write (JSON)")->required();
    cmd->add_flag("--json", *json, "Machine-readable summary");
    cmd->callback([=] { run_replan(*s, *model, *out, *json); });
  }
  {
    auto* cmd = hex->add_subcommand(
        "simulate-readings",
        "The readings a session over a plan would get in a simulated cell (random true robot and "
        "fixtures from --seed), one per line for `robcal hexapod session`");
    auto o = std::make_shared<SimulateReadingsOptions>();
    cmd->add_option("--plan", o->plan, "Plan file (from `robcal hexapod plan` or `replan`)")
        ->required();
    cmd->add_option("--robot", o->robot, "Built-in robot name or robot file")
        ->capture_default_str();
    cmd->add_option("--seed", o->seed, "Seed of the true robot, the fixtures and the readings")
        ->capture_default_str();
    cmd->add_option("--payload", o->payload,
                    "Tool file whose payload the true robot carries (default 2.6 kg at "
                    "(50, 25, 100) mm)");
    cmd->add_option("--out", o->out, "Readings file to write")->required();
    cmd->add_option("--tool-out", o->tool_out, "Write the tool file (payload, cups, TCP)");
    cmd->add_option("--validation-out", o->validation_out,
                    "Write laser-tracker validation points (robot frame of the base cups' world)");
    cmd->add_option("--validation", o->validation, "Validation configurations")
        ->capture_default_str();
    cmd->add_flag("--json", o->json, "Machine-readable summary");
    cmd->callback([o] { run_simulate_readings(*o); });
  }
});

}  // namespace
}  // namespace robcal::cli
