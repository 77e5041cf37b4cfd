/// `robcal report`: one self-contained HTML page (and the same content as JSON) for a
/// calibrated model validated on measurement files.

#include <fmt/format.h>

#include <filesystem>
#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/yaml_support.hpp"
#include "robcal/report/report.hpp"
#include "robcal/validate/base_fit.hpp"

namespace robcal::cli {
namespace {

struct ReportOptions {
  std::string model;
  std::vector<std::string> measurements;
  std::string calibration;
  std::string before;
  std::string title = "robcal calibration report";
  std::string out;
  bool json = false;
};

MeasurementSet read_positions(const std::string& path, const Tool& tool) {
  MeasurementFile file =
      read_measurements_csv(path, tool, {MeasurementKind::Points, MeasurementKind::Poses});
  for (const std::string& warning : file.warnings) fmt::print(stderr, "warning: {}\n", warning);
  return std::move(file.measurements);
}

void run_report(const ReportOptions& o) {
  const std::filesystem::path html_path(o.out);
  if (html_path.extension() != ".html")
    throw InputError({"", 0, 0, "--out"}, "expected a file name ending in .html");
  const std::string chartjs = load_chartjs();
  const CalibratedRobot model = load_calibrated_robot(o.model);
  if (!model.base_fitted)
    throw InputError({o.model, 0, 0, "--model"},
                     "this model has no world frame (its base was never fitted): calibrate at "
                     "least with --level base");
  std::vector<MeasurementSet> validation;
  for (const std::string& path : o.measurements)
    validation.push_back(read_positions(path, model.tool));

  ReportData data;
  data.title = o.title;
  data.robot = model.model.name;
  data.sources.push_back("model " + o.model);
  for (const std::string& path : o.measurements) data.sources.push_back("validation " + path);
  if (o.before.empty()) {
    // The nominal robot placed by a rigid fit to the first validation file: the best a
    // nominal model does once its base frame is known.
    const CalibratedRobot nominal =
        fit_base(CalibratedRobot::nominal(model.model, model.tool), validation.front());
    data.models.push_back(model_errors("nominal (rigid base fit)", nominal, validation));
  } else {
    data.models.push_back(
        model_errors("before: " + o.before, load_calibrated_robot(o.before), validation));
  }
  data.models.push_back(
      model_errors(model.level.empty() ? "calibrated" : model.level, model, validation));
  if (!o.calibration.empty()) {
    data.sources.push_back("calibration " + o.calibration);
    data.distance_to_calibration_mm =
        distance_to_calibration(validation, read_positions(o.calibration, model.tool));
  } else {
    data.notes.push_back(
        "No --calibration file: distances to the calibration region are not "
        "shown.");
  }
  data.parameters = report_parameters(model);
  const yaml::Node root = yaml::load_file(o.model);
  if (root.has("statistics"))
    data.diagnostics = yaml_to_json(YAML::Dump(root.at("statistics").node));

  const nlohmann::json report = report_json(data);
  std::filesystem::path json_path = html_path;
  json_path.replace_extension(".json");
  const std::string html = report_html(report, chartjs);
  write_file_atomically(json_path, report.dump(1));
  write_file_atomically(html_path, html);
  if (o.json) {
    print_json(report);
    return;
  }
  fmt::print("{}", report_table_text(report));
  fmt::print("wrote {} and {}\n", html_path.string(), json_path.string());
}

const bool registered = register_command(85, [](CLI::App& app) {
  auto o = std::make_shared<ReportOptions>();
  auto* cmd = app.add_subcommand(
      "report", "Self-contained HTML report (and JSON) of a calibrated model's validation");
  cmd->add_option("--model", o->model, "Calibrated model file (from calibrate)")->required();
  cmd->add_option("--measurements", o->measurements,
                  "Validation measurement files (points or poses), one or more")
      ->required();
  cmd->add_option("--calibration", o->calibration,
                  "The calibration measurements (for the error against distance to them)");
  cmd->add_option("--before", o->before,
                  "Model to compare with (default: the nominal robot, rigid base fit)");
  cmd->add_option("--title", o->title, "Page title")->capture_default_str();
  cmd->add_option("--out", o->out, "Output .html (the JSON goes beside it)")->required();
  cmd->add_flag("--json", o->json, "Print the report's JSON");
  cmd->callback([o] { run_report(*o); });
});

}  // namespace
}  // namespace robcal::cli
