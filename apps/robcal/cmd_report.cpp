/// `robcal report`: one self-contained HTML page (and the same content as JSON) for a
/// calibrated model validated on measurement files.

#include <fmt/format.h>

#include <filesystem>
#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/report/report_workflow.hpp"

namespace robcal::cli {
namespace {

struct ReportOptions {
  ReportRequest request;
  std::string out;
  bool json = false;
};

void run_report(const ReportOptions& o) {
  const std::filesystem::path html_path(o.out);
  std::vector<std::string> warnings;
  const nlohmann::json report = make_report(o.request, html_path, warnings);
  for (const std::string& warning : warnings) fmt::print(stderr, "warning: {}\n", warning);
  if (o.json) {
    print_json(report);
    return;
  }
  fmt::print("{}", report_table_text(report));
  std::filesystem::path json_path = html_path;
  json_path.replace_extension(".json");
  fmt::print("wrote {} and {}\n", html_path.string(), json_path.string());
}

const bool report_registered = register_command(85, [](CLI::App& app) {
  auto o = std::make_shared<ReportOptions>();
  auto* cmd = app.add_subcommand(
      "report", "Self-contained HTML report (and JSON) of a calibrated model's validation");
  cmd->add_option("--model", o->request.model, "Calibrated model file (from calibrate)")
      ->required();
  cmd->add_option("--measurements", o->request.measurements,
                  "Validation measurement files (points or poses), one or more")
      ->required();
  cmd->add_option("--calibration", o->request.calibration,
                  "The calibration measurements (for the error against distance to them)");
  cmd->add_option(
      "--before", o->request.before,
      "Model to compare with (default: the nominal robot, rigid base fit to --calibration, "
      "else to the first validation file)");
  cmd->add_option("--between", o->request.between,
                  "Further calibrated models shown between --before and --model, in this order "
                  "(e.g. the lower levels), each labelled by its level");
  cmd->add_option("--instrument", o->request.instrument,
                  "Instrument file (instrument.yaml: name and sigma_mm) for the provenance");
  cmd->add_option("--seed", o->request.seed, "Seed of the plan or simulation, for the provenance");
  cmd->add_option("--iso9283-poses", o->request.iso9283_poses,
                  "ISO 9283 commanded poses (from `robcal iso9283 plan`)");
  cmd->add_option("--iso9283-measurements", o->request.iso9283_measurements,
                  "ISO 9283 measured cycles (pose,cycle,x,y,z[,qw,qx,qy,qz][,direction])");
  cmd->add_option("--iso9283-min-cycles", o->request.iso9283_min_cycles,
                  "Fewest cycles accepted per pose (the standard: 30)")
      ->capture_default_str();
  cmd->add_option("--ballbar", o->request.ballbar,
                  "Ballbar (distances) file: length errors of both models");
  cmd->add_option("--ballbar-length", o->request.ballbar_length_mm,
                  "The bar's nominal length in mm (default: the median reading); a reading "
                  "outside length ± range is refused");
  cmd->add_option(
      "--ballbar-range", o->request.ballbar_range_mm,
      fmt::format("The bar reads length ± range (mm; default {:g})", kDefaultBallbarRangeMm));
  cmd->add_option("--title", o->request.title, "Page title")->capture_default_str();
  cmd->add_option("--out", o->out, "Output .html (the JSON goes beside it)")->required();
  cmd->add_flag("--json", o->json, "Print the report's JSON");
  cmd->callback([o] { run_report(*o); });
});

}  // namespace
}  // namespace robcal::cli
