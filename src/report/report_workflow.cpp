#include "robcal/report/report_workflow.hpp"

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include <cstdint>
#include <numeric>
#include <string_view>

#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/yaml_support.hpp"
#include "robcal/report/provenance.hpp"
#include "robcal/validate/ballbar_error.hpp"
#include "robcal/validate/base_fit.hpp"
#include "robcal/validate/iso9283.hpp"

namespace robcal {
namespace {

MeasurementSet read_set(const std::string& path, const Tool& tool,
                        std::initializer_list<MeasurementKind> kinds,
                        std::vector<std::string>& warnings) {
  MeasurementFile file = read_measurements_csv(path, tool, kinds);
  warnings.insert(warnings.end(), file.warnings.begin(), file.warnings.end());
  return std::move(file.measurements);
}

MeasurementSet read_positions(const std::string& path, const Tool& tool,
                              std::vector<std::string>& warnings) {
  return read_set(path, tool, {MeasurementKind::Points, MeasurementKind::Poses}, warnings);
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

/// Length in bytes of the UTF-8 sequence at `at` of `text`; 0 when it is not one (a stray
/// continuation byte, a truncated or overlong sequence, a surrogate, beyond U+10FFFF).
size_t utf8_sequence_length(std::string_view text, size_t at) {
  const auto byte = [&](size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(at);
  if (lead < 0x80) return 1;
  const size_t length = lead >= 0xF0 ? 4 : lead >= 0xE0 ? 3 : lead >= 0xC0 ? 2 : 0;
  if (length == 0 || at + length > text.size() || lead > 0xF4) return 0;
  uint32_t code = lead & (0x7F >> length);
  for (size_t i = 1; i < length; ++i) {
    if ((byte(at + i) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(at + i) & 0x3F);
  }
  constexpr uint32_t kShortest[] = {0, 0, 0x80, 0x800, 0x10000};
  if (code < kShortest[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return length;
}

/// --title heads the page and names it in a browser's tab: one line of printable UTF-8 text.
void check_title(std::string_view title) {
  constexpr size_t kMaxTitle = 200;
  const auto refuse = [](const std::string& why) {
    throw InputError({"", 0, 0, "--title"}, why + ": expected one line of printable UTF-8 text");
  };
  if (title.find_first_not_of(' ') == std::string_view::npos) refuse("the title is empty");
  if (title.size() > kMaxTitle)
    refuse(fmt::format("the title has {} bytes, more than {}", title.size(), kMaxTitle));
  for (size_t at = 0; at < title.size();) {
    const auto c = static_cast<unsigned char>(title[at]);
    if (c < 0x20 || c == 0x7F)
      refuse(fmt::format("control character 0x{:02X} at byte {}", c, at + 1));
    const size_t length = utf8_sequence_length(title, at);
    if (length == 0) refuse(fmt::format("byte 0x{:02X} at byte {} is not UTF-8", c, at + 1));
    at += length;
  }
}

}  // namespace

ReportBuild build_report(const ReportRequest& o) {
  check_title(o.title);
  if (o.measurements.empty())
    throw InputError({"", 0, 0, "--measurements"}, "expected at least one validation file");
  if (o.iso9283_poses.empty() != o.iso9283_measurements.empty())
    throw InputError({"", 0, 0, "--iso9283-poses"},
                     "give both --iso9283-poses and --iso9283-measurements");
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
  data.provenance = start_provenance_of_process();
  data.provenance.robot = model.model.name;
  data.provenance.level = model.level;
  data.provenance.seed = o.seed;
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
  std::optional<MeasurementSet> calibration_set;
  if (!o.calibration.empty()) {
    data.sources.push_back("calibration " + o.calibration);
    data.provenance.files.push_back(provenance_file("calibration", o.calibration));
    calibration_set = read_positions(o.calibration, model.tool, out.warnings);
    calibration = measured_positions(*calibration_set);
    data.distance_to_calibration_mm = distance_to_calibration(validation, *calibration_set);
  } else {
    data.notes.push_back(
        "No --calibration file: distances to the calibration region are not "
        "shown.");
  }
  CalibratedRobot before;
  std::string before_label;
  if (o.before.empty()) {
    // The nominal robot placed by a rigid fit to the calibration data, as the published tables
    // and `robcal demo` place it: validation rows never enter a model they rate. Without a
    // calibration file only the validation rows can place it, which the label says.
    const CalibratedRobot nominal = CalibratedRobot::nominal(model.model, model.tool);
    before = fit_base(nominal, calibration_set ? *calibration_set : validation.front());
    before_label = calibration_set ? "nominal (base fitted on the calibration data)"
                                   : "nominal (base fitted on the validation data)";
  } else {
    before = load_calibrated_robot(o.before);
    before_label = "before: " + o.before;
    data.provenance.files.push_back(provenance_file("before", o.before));
  }
  const std::string after_label = model.level.empty() ? "calibrated" : model.level;
  data.models.push_back(model_errors(before_label, before, validation, calibration));
  for (const std::string& path : o.between) {
    const CalibratedRobot other = load_calibrated_robot(path);
    data.models.push_back(
        model_errors(other.level.empty() ? path : other.level, other, validation, calibration));
    data.provenance.files.push_back(provenance_file("model", path));
  }
  data.models.push_back(model_errors(after_label, model, validation, calibration));
  if (!o.iso9283_poses.empty()) {
    data.iso9283 = iso9283_analyse(
        read_iso9283_request(o.iso9283_poses, o.iso9283_measurements, o.iso9283_min_cycles));
    data.provenance.files.push_back(provenance_file("ISO 9283 poses", o.iso9283_poses));
    data.provenance.files.push_back(provenance_file("ISO 9283 cycles", o.iso9283_measurements));
  }
  if (!o.ballbar.empty()) {
    const MeasurementSet set =
        read_set(o.ballbar, model.tool, {MeasurementKind::Distances}, out.warnings);
    data.ballbar_range = check_ballbar_readings(set, o.ballbar_length_mm, o.ballbar_range_mm);
    // The centre is identified for each model: no world frame is needed.
    data.ballbar.emplace_back(before_label, ballbar_errors(before, set, std::nullopt));
    data.ballbar.emplace_back(after_label, ballbar_errors(model, set, std::nullopt));
    data.provenance.files.push_back(provenance_file("ballbar", o.ballbar));
  }
  data.parameters = report_parameters(model);
  data.groups = group_significance(model);
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
  // The sources and the command line hold file names, which need not be UTF-8: U+FFFD for
  // their stray bytes (as in report_html).
  write_file_atomically(json_path,
                        report.dump(1, ' ', false, nlohmann::json::error_handler_t::replace));
  write_file_atomically(html_path, html);
}

nlohmann::json make_report(const ReportRequest& request, const std::filesystem::path& html_path,
                           std::vector<std::string>& warnings) {
  if (!html_path.empty()) {
    check_report_path(html_path);
    (void)load_chartjs();
  }
  ReportBuild build = build_report(request);
  warnings.insert(warnings.end(), build.warnings.begin(), build.warnings.end());
  nlohmann::json report = report_json(build.data);
  if (!html_path.empty()) write_report(report, html_path);
  return report;
}

}  // namespace robcal
