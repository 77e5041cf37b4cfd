#include "robcal/report/report_workflow.hpp"

#include <nlohmann/json.hpp>

#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/yaml_support.hpp"
#include "robcal/validate/base_fit.hpp"

namespace robcal {
namespace {

MeasurementSet read_positions(const std::string& path, const Tool& tool,
                              std::vector<std::string>& warnings) {
  MeasurementFile file =
      read_measurements_csv(path, tool, {MeasurementKind::Points, MeasurementKind::Poses});
  warnings.insert(warnings.end(), file.warnings.begin(), file.warnings.end());
  return std::move(file.measurements);
}

}  // namespace

ReportBuild build_report(const ReportRequest& o) {
  if (o.measurements.empty())
    throw InputError({"", 0, 0, "--measurements"}, "expected at least one validation file");
  const CalibratedRobot model = load_calibrated_robot(o.model);
  if (!model.base_fitted)
    throw InputError({o.model, 0, 0, "--model"},
                     "this model has no world frame (its base was never fitted): calibrate at "
                     "least with --level base");
  ReportBuild out;
  std::vector<MeasurementSet> validation;
  for (const std::string& path : o.measurements)
    validation.push_back(read_positions(path, model.tool, out.warnings));

  ReportData& data = out.data;
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
    data.distance_to_calibration_mm = distance_to_calibration(
        validation, read_positions(o.calibration, model.tool, out.warnings));
  } else {
    data.notes.push_back(
        "No --calibration file: distances to the calibration region are not "
        "shown.");
  }
  data.parameters = report_parameters(model);
  const yaml::Node root = yaml::load_file(o.model);
  if (root.has("statistics"))
    data.diagnostics = yaml_to_json(YAML::Dump(root.at("statistics").node));
  return out;
}

void check_report_path(const std::filesystem::path& html_path) {
  if (html_path.extension() != ".html")
    throw InputError({"", 0, 0, "--out"}, "expected a file name ending in .html");
}

void write_report(const nlohmann::json& report, const std::filesystem::path& html_path) {
  check_report_path(html_path);
  const std::string html = report_html(report, load_chartjs());
  std::filesystem::path json_path = html_path;
  json_path.replace_extension(".json");
  write_file_atomically(json_path, report.dump(1));
  write_file_atomically(html_path, html);
}

}  // namespace robcal
