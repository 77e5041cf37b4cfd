/// `robcal report`: one self-contained HTML page (and the same content as JSON) for a
/// calibrated model validated on measurement files.

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <numeric>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/pose_list_file.hpp"
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
  std::string instrument;  ///< instrument.yaml (name and σ)
  std::string seed;
  std::string iso9283_poses, iso9283_measurements;
  int iso9283_min_cycles = kIso9283Cycles;
  std::string ballbar;
  bool json = false;
};

MeasurementSet read_set(const std::string& path, const Tool& tool,
                        std::initializer_list<MeasurementKind> kinds) {
  MeasurementFile file = read_measurements_csv(path, tool, kinds);
  for (const std::string& warning : file.warnings) fmt::print(stderr, "warning: {}\n", warning);
  return std::move(file.measurements);
}

MeasurementSet read_positions(const std::string& path, const Tool& tool) {
  return read_set(path, tool, {MeasurementKind::Points, MeasurementKind::Poses});
}

/// The instrument file's name and σ (the mean of sigma_mm when it lists one per axis).
void read_instrument(const std::string& path, Provenance& provenance) {
  const yaml::Node root = yaml::load_file(path);
  provenance.instrument = root.at("instrument").as_string();
  if (root.has("sigma_mm")) {
    const yaml::Node sigma = root.at("sigma_mm");
    const std::vector<double> values =
        sigma.node.IsSequence() ? sigma.as_doubles() : std::vector<double>{sigma.as_double()};
    if (!values.empty())
      provenance.instrument_sigma_mm =
          std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  }
}

void run_report(const ReportOptions& o) {
  const std::filesystem::path html_path(o.out);
  if (html_path.extension() != ".html")
    throw InputError({"", 0, 0, "--out"}, "expected a file name ending in .html");
  if (o.iso9283_poses.empty() != o.iso9283_measurements.empty())
    throw InputError({"", 0, 0, "--iso9283-poses"},
                     "give both --iso9283-poses and --iso9283-measurements");
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
  data.provenance = start_provenance_of_process();
  data.provenance.robot = model.model.name;
  data.provenance.level = model.level;
  if (!o.seed.empty()) data.provenance.seed = std::stoull(o.seed);
  data.provenance.files.push_back(provenance_file("model", o.model));
  data.sources.push_back("model " + o.model);
  for (const std::string& path : o.measurements) {
    data.sources.push_back("validation " + path);
    data.provenance.files.push_back(provenance_file("validation", path));
  }
  if (!o.instrument.empty()) {
    read_instrument(o.instrument, data.provenance);
    data.provenance.files.push_back(provenance_file("instrument", o.instrument));
  }
  std::optional<Eigen::Matrix3Xd> calibration;
  if (!o.calibration.empty()) {
    data.sources.push_back("calibration " + o.calibration);
    data.provenance.files.push_back(provenance_file("calibration", o.calibration));
    const MeasurementSet set = read_positions(o.calibration, model.tool);
    calibration = measured_positions(set);
    data.distance_to_calibration_mm = distance_to_calibration(validation, set);
  } else {
    data.notes.push_back(
        "No --calibration file: distances to the calibration region are not "
        "shown.");
  }
  CalibratedRobot before;
  std::string before_label;
  if (o.before.empty()) {
    // The nominal robot placed by a rigid fit to the first validation file: the best a
    // nominal model does once its base frame is known.
    before = fit_base(CalibratedRobot::nominal(model.model, model.tool), validation.front());
    before_label = "nominal (rigid base fit)";
  } else {
    before = load_calibrated_robot(o.before);
    before_label = "before: " + o.before;
    data.provenance.files.push_back(provenance_file("before", o.before));
  }
  const std::string after_label = model.level.empty() ? "calibrated" : model.level;
  data.models.push_back(model_errors(before_label, before, validation, calibration));
  data.models.push_back(model_errors(after_label, model, validation, calibration));
  if (!o.iso9283_poses.empty()) {
    data.iso9283 = iso9283_analyse(
        read_iso9283_request(o.iso9283_poses, o.iso9283_measurements, o.iso9283_min_cycles));
    data.provenance.files.push_back(provenance_file("ISO 9283 poses", o.iso9283_poses));
    data.provenance.files.push_back(provenance_file("ISO 9283 cycles", o.iso9283_measurements));
  }
  if (!o.ballbar.empty()) {
    const MeasurementSet set = read_set(o.ballbar, model.tool, {MeasurementKind::Distances});
    // The centre is identified for each model: no world frame is needed.
    data.ballbar.emplace_back(before_label, ballbar_errors(before, set, std::nullopt));
    data.ballbar.emplace_back(after_label, ballbar_errors(model, set, std::nullopt));
    data.provenance.files.push_back(provenance_file("ballbar", o.ballbar));
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
  cmd->add_option("--instrument", o->instrument,
                  "Instrument file (instrument.yaml: name and sigma_mm) for the provenance");
  cmd->add_option("--seed", o->seed, "Seed of the plan or simulation, for the provenance")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--iso9283-poses", o->iso9283_poses,
                  "ISO 9283 commanded poses (from `robcal iso9283 plan`)");
  cmd->add_option("--iso9283-measurements", o->iso9283_measurements,
                  "ISO 9283 measured cycles (pose,cycle,x,y,z[,qw,qx,qy,qz][,direction])");
  cmd->add_option("--iso9283-min-cycles", o->iso9283_min_cycles,
                  "Fewest cycles accepted per pose (the standard: 30)")
      ->capture_default_str();
  cmd->add_option("--ballbar", o->ballbar,
                  "Ballbar (distances) file: length errors of both models");
  cmd->add_option("--title", o->title, "Page title")->capture_default_str();
  cmd->add_option("--out", o->out, "Output .html (the JSON goes beside it)")->required();
  cmd->add_flag("--json", o->json, "Print the report's JSON");
  cmd->callback([o] { run_report(*o); });
});

}  // namespace
}  // namespace robcal::cli
