/// `robcal program`: the measurement program that visits planned configurations, in the
/// controller's language (ABB RAPID, KUKA KRL, Fanuc LS, Yaskawa JBI, URScript).

#include <fmt/chrono.h>
#include <fmt/format.h>

#include <algorithm>
#include <ctime>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/programs/measurement_program.hpp"

namespace robcal::cli {
namespace {

struct ProgramOptions {
  std::string language;
  std::string configs;
  std::string out;
  std::string robot;
  std::string tool;
  std::string hook = "wait";
  std::string pulses;
  bool json = false;
};

void run_program(const ProgramOptions& o, const MeasurementProgramRequest& program) {
  MeasurementProgramFilesRequest request;
  request.program = program;
  request.program.language = program_language_from_name(o.language, "--lang");
  request.program.hook = measurement_hook_from_name(o.hook);
  if (!o.pulses.empty()) {
    const std::vector<double> p = parse_numbers(o.pulses, kJointCount, "--pulses-per-degree");
    request.program.pulses_per_degree.emplace();
    std::copy(p.begin(), p.end(), request.program.pulses_per_degree->begin());
  }
  request.program.date = fmt::format("{:%Y/%m/%d %H:%M}", fmt::gmtime(std::time(nullptr)));
  request.configs = o.configs;
  request.robot = o.robot;
  request.tool = o.tool;
  request.out_dir = o.out;
  const MeasurementProgramFilesResult r = write_measurement_program_from_files(request);
  const std::vector<std::string>& paths = r.paths;
  if (o.json) {
    print_json({{"language", program_language_name(r.program.language)},
                {"configurations", r.program.joints.size()},
                {"files", paths}});
    return;
  }
  const auto above =
      std::count_if(r.program.visits.begin(), r.program.visits.end(),
                    [](const ConfigurationVisit& v) { return (v.side.array() < 0).any(); });
  fmt::print("{} configurations, each approached from q - {:g} deg{}, in {} {} program{}:\n",
             r.program.joints.size(), r.program.approach_deg,
             above == 0 ? ""
                        : fmt::format(" (q + {:g} deg on some joints of {}, as planned)",
                                      r.program.approach_deg, above),
             paths.size(), program_language_name(r.program.language), paths.size() == 1 ? "" : "s");
  for (const std::string& p : paths) fmt::print("  {}\n", p);
}

const bool program_registered = register_command(65, [](CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "program",
      "Measurement program in the controller's language: joint moves to each planned "
      "configuration, approached from q - 5 deg on every joint, a settle wait and a hook");
  auto o = std::make_shared<ProgramOptions>();
  auto r = std::make_shared<MeasurementProgramRequest>();
  cmd->add_option("--lang", o->language, "rapid, krl, ls (Fanuc), jbi (Yaskawa) or urscript")
      ->required();
  cmd->add_option("--configs", o->configs,
                  "Configurations CSV config,target,j1..j6 (degrees; what `robcal plan` writes)")
      ->required();
  cmd->add_option("--out", o->out, "Folder for the program file(s)")->required();
  cmd->add_option("--robot", o->robot,
                  "Built-in robot name or robot file: check each configuration and its approach "
                  "against the joint limits");
  cmd->add_option("--tool", o->tool, "Tool file (needed when the CSV names targets)");
  cmd->add_option("--name", r->name, "Program name, at most 6 characters (default RCMEAS)");
  cmd->add_option("--hook", o->hook,
                  "At each configuration: wait (for an input), pulse (an output) or log (a "
                  "message with the name and joints; RAPID, LS, URScript)");
  cmd->add_option("--signal", r->signal, "Input/output number for the hook (default 1)");
  cmd->add_option("--rapid-signal", r->rapid_signal,
                  "RAPID signal name (default diRobcalMeasured / doRobcalMeasure)");
  cmd->add_option("--settle-s", r->settle_s, "Wait after reaching each configuration (s)");
  cmd->add_option(
      "--approach-deg", r->approach_deg,
      "Approach offset on every joint (deg, docs/method/05-observability.md §4; default 5)");
  cmd->add_option("--speed-percent", r->joint_speed_percent, "Joint speed, % (default 10)");
  cmd->add_option("--max-configs-per-file", r->max_configs_per_file,
                  "Split into programs of at most this many configurations (default: the "
                  "controller's limit: RAPID/KRL 500, LS 250, JBI 400, URScript 1000)");
  cmd->add_option("--tool-number", r->tool_number, "Tool number stored with LS/JBI points");
  cmd->add_option("--pulses-per-degree", o->pulses,
                  "Yaskawa: encoder pulses per degree of the six axes, comma-separated (default: "
                  "the --robot file's pulses_per_degree)");
  cmd->add_flag("--json", o->json, "Machine-readable summary on stdout");
  cmd->callback([=] { run_program(*o, *r); });
});

}  // namespace
}  // namespace robcal::cli
