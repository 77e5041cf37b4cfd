#include "robcal/validate/validate_workflow.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "robcal/core/error.hpp"
#include "robcal/io/format_options.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/measure/tcp_warning.hpp"
#include "robcal/validate/base_fit.hpp"
#include "robcal/validate/error_statistics_json.hpp"

namespace robcal {
namespace {

/// The calibrated model of `request` (or the nominal robot), checked against the robot and the
/// tool it is validated with; `notes` gets the targets whose calibrated coordinates are used.
CalibratedRobot load_model(const ValidateRequest& request, std::vector<std::string>& notes) {
  const RobotModel model = load_robot(request.robot);
  const Tool tool = load_tool(request.tool);
  if (request.model.empty()) return CalibratedRobot::nominal(model, tool);
  CalibratedRobot robot = load_calibrated_robot(request.model);
  if (robot.model.name != model.name)
    throw InputError({request.model, 0, 0, "--model"},
                     fmt::format("this is a model of the {}, not of the {} (--robot {})",
                                 robot.model.name, model.name, request.robot));
  // The model's tool holds the identified target coordinates; an older file may have none.
  if (robot.tool.targets.empty()) robot.tool = tool;
  check_tool_against_model(robot, tool, request.tool);
  for (const Target& t : tool.targets) {
    const Target& m = robot.tool.targets[static_cast<size_t>(robot.tool.target_index(t.name))];
    const double moved = (m.position_mm - t.position_mm).norm();
    if (t.known && moved > 1e-3)
      notes.push_back(fmt::format(
          "target '{}': the model's calibrated coordinates are used, {:.4f} mm from the tool "
          "file's",
          t.name, moved));
  }
  return robot;
}

nlohmann::json per_target_json(const std::vector<TargetErrorStatistics>& targets) {
  nlohmann::json out = nlohmann::json::array();
  for (const TargetErrorStatistics& t : targets) {
    nlohmann::json entry = error_statistics_json(t.position_mm, "mm");
    entry["target"] = t.target;
    entry["rows"] = t.position_mm.count;
    out.push_back(entry);
  }
  return out;
}

nlohmann::json histogram_json(const Histogram& h) {
  return {{"lower", h.lower}, {"upper", h.upper}, {"counts", h.counts}};
}

/// A class's statistics in `unit`; a class without rows is {"rows": 0, "status": "no data"}.
nlohmann::json class_statistics_json(const ErrorStatistics& s, std::string_view unit) {
  if (s.count == 0) return {{"rows", 0}, {"status", "no data"}};
  nlohmann::json out = error_statistics_json(s, unit);
  out["rows"] = s.count;
  return out;
}

/// Pair distance errors inside a class; fewer than two rows: {"pairs": 0, "status": "no data"}.
nlohmann::json class_pairs_json(const PairwiseDistanceErrors& pairs) {
  if (pairs.stats.count == 0) return {{"pairs", 0}, {"status", "no data"}};
  nlohmann::json out = error_statistics_json(pairs.stats, "mm");
  out["pairs"] = pairs.stats.count;
  out["signed_mean_mm"] = pairs.signed_mean;
  out["positive_share"] = pairs.positive_share();
  return out;
}

nlohmann::json classes_json(const std::vector<ClassTable>& tables, bool poses,
                            const char* error_key = "position_error_mm") {
  nlohmann::json out = nlohmann::json::array();
  for (const ClassTable& t : tables) {
    nlohmann::json rows = nlohmann::json::array();
    for (const ClassRow& r : t.rows) {
      nlohmann::json row = {{"class", r.label},
                            {error_key, class_statistics_json(r.position_mm, "mm")}};
      if (poses) row["orientation_error_deg"] = class_statistics_json(r.orientation_deg, "deg");
      if (r.pairs) row["distance_error_mm"] = class_pairs_json(*r.pairs);
      rows.push_back(row);
    }
    out.push_back({{"table", t.name}, {"rows", rows}});
  }
  return out;
}

nlohmann::json ballbar_json(const ValidateResult& result) {
  const BallbarErrors& errors = *result.ballbar;
  nlohmann::json out;
  out["rows"] = result.rows;
  out["kind"] = measurement_kind_name(result.kind);
  out["length_error_mm"] = error_statistics_json(errors.absolute_mm, "mm");
  out["length_error_mm"]["signed_mean_mm"] = errors.signed_mean_mm;
  out["length_error_mm"]["signed_std_mm"] = errors.signed_std_mm;
  out["length_error_mm"]["positive_share"] = errors.positive_share;
  out["length_error_histogram_mm"] = histogram_json(result.ballbar_histogram);
  out["ballbar_centre_mm"] = {errors.centre_mm.x(), errors.centre_mm.y(), errors.centre_mm.z()};
  out["ballbar_centre"] = errors.centre_fitted ? "identified" : "given";
  out["ballbar_length_mm"] = result.ballbar_range.nominal_length_mm;
  out["ballbar_range_mm"] = result.ballbar_range.range_mm;
  out["ballbar_length"] = result.ballbar_range.length_given ? "given" : "median of the readings";
  out["per_target"] = per_target_json(errors.per_target);
  out["classes"] = classes_json(errors.classes, false, "length_error_mm");
  out["robot"] = result.robot;
  out["level"] = result.level;
  out["measurements"] = result.measurements;
  return out;
}

/// The robot and tool as the refusal's suggested command names them.
struct Sources {
  std::string robot = "ROBOT";
  std::string tool = "TOOL";
};

ValidateResult validate_set(CalibratedRobot robot, const MeasurementSet& set,
                            const ValidateOptions& options, const std::string& measurements,
                            const Sources& sources) {
  check_orientation_weight(options.orientation_weight_mm);
  if (options.threads < 1 || options.threads > 256)
    throw InputError({"", 0, 0, "--threads"},
                     fmt::format("expected 1 to 256 threads, got {}", options.threads));
  ValidateResult result;
  result.robot = robot.model.name;
  result.measurements = measurements;
  result.kind = set.kind;
  result.rows = set.size();
  result.fit_base = options.fit_base;
  result.threads = options.threads;
  result.region_classes = options.calibration_mm.has_value();
  if (const auto warning = poses_without_tcp_warning(robot.tool, set))
    result.warnings.push_back(*warning);
  for (const auto& [given, flag] :
       {std::pair{options.ballbar_centre_mm.has_value(), "--ballbar-centre"},
        std::pair{options.ballbar_length_mm.has_value(), "--ballbar-length"},
        std::pair{options.ballbar_range_mm.has_value(), "--ballbar-range"}})
    if (given && set.kind != MeasurementKind::Distances)
      throw InputError({measurements, 0, 0, flag},
                       fmt::format("{} is for distances (ballbar) files; this is a {} file", flag,
                                   measurement_kind_name(set.kind)));
  if (set.kind == MeasurementKind::Distances) {
    if (options.fit_base)
      throw InputError({measurements, 0, 0, "--fit-base"},
                       "a distances (ballbar) file has no positions to fit a world frame to; "
                       "without --ballbar-centre the centre is identified, so no frame is needed");
    result.level = robot.level;
    result.ballbar_range =
        check_ballbar_readings(set, options.ballbar_length_mm, options.ballbar_range_mm);
    result.ballbar = ballbar_errors(robot, set, options.ballbar_centre_mm);
    std::vector<double> absolute;
    for (double e : result.ballbar->length_error_mm) absolute.push_back(std::abs(e));
    // The top edge sits just above the largest error so that it falls inside the last bin.
    const double top = std::max(result.ballbar->absolute_mm.max * (1 + 1e-9), 1e-9);
    result.ballbar_histogram = make_histogram(absolute, kPositionHistogramBins, 0.0, top);
    return result;
  }
  if (!robot.base_fitted && !options.fit_base)
    throw InputError(
        {measurements, 0, 0, "--fit-base"},
        fmt::format("the {} model of {} has no world frame (its base was never fitted), so its "
                    "positions cannot be compared with measured ones. Calibrate at least the "
                    "base: `robcal calibrate --robot {} --tool {} --measurements CAL.csv "
                    "--level base --out model.yaml`, then validate with --model model.yaml; or "
                    "pass --fit-base (Python: fit_base=True) to place it by a rigid best fit to "
                    "these measurements",
                    robot.level, robot.model.name, sources.robot, sources.tool));
  if (options.fit_base) {
    result.frame = robot.base_fitted ? ValidationFrame::Refitted : ValidationFrame::Fitted;
    robot = fit_base(robot, set);
  }
  result.level = robot.level;
  result.report = validate_model(robot, set, options.threads, options.orientation_weight_mm,
                                 options.calibration_mm);
  return result;
}

}  // namespace

ValidateResult validate(CalibratedRobot robot, const MeasurementSet& set,
                        const ValidateOptions& options, const std::string& measurements) {
  return validate_set(std::move(robot), set, options, measurements, {});
}

ValidateResult validate(const ValidateRequest& request) {
  std::vector<std::string> notes;
  const CalibratedRobot robot = load_model(request, notes);
  const MeasurementFormat format = declared_format(request.units, request.euler);
  MeasurementFile file = read_measurements_csv(
      request.measurements, robot.tool,
      {MeasurementKind::Points, MeasurementKind::Poses, MeasurementKind::Distances}, format);
  ValidateOptions options = request.options;
  if (!request.calibration.empty()) {
    const MeasurementFile calibration = read_measurements_csv(
        request.calibration, robot.tool, {MeasurementKind::Points, MeasurementKind::Poses}, format);
    options.calibration_mm = measured_positions(calibration.measurements);
  }
  ValidateResult result = validate_set(robot, file.measurements, options, request.measurements,
                                       {request.robot, request.tool});
  result.warnings.insert(result.warnings.begin(), file.warnings.begin(), file.warnings.end());
  result.notes = std::move(notes);
  return result;
}

nlohmann::json validate_json(const ValidateResult& result) {
  if (result.ballbar) return ballbar_json(result);
  const ValidationReport& report = *result.report;
  const PositionErrors& positions = report.positions;
  const PairwiseDistanceErrors& distances = report.distances;
  const bool poses = result.kind == MeasurementKind::Poses;
  nlohmann::json out;
  out["points"] = result.rows;
  out["position_error_mm"] = error_statistics_json(positions.position_mm, "mm");
  out["distance_error_mm"] = error_statistics_json(distances.stats, "mm");
  out["distance_error_mm"]["pairs"] = distances.stats.count;
  out["distance_error_mm"]["histogram"] = histogram_json(distances.histogram);
  out["position_histogram_mm"] = histogram_json(report.position_histogram);
  out["distance_error_mm"]["signed_mean_mm"] = distances.signed_mean;
  out["distance_error_mm"]["positive_share"] = distances.positive_share();
  out["per_target"] = per_target_json(positions.per_target);
  out["classes"] = classes_json(report.classes, poses);
  if (poses) {
    out["orientation_error_deg"] = error_statistics_json(positions.orientation_deg, "deg");
    out["pose_error_mm"] = error_statistics_json(positions.pose_mm, "mm");
    out["orientation_weight_mm_per_rad"] = positions.orientation_weight_mm;
  }
  out.update({{"kind", measurement_kind_name(result.kind)},
              {"robot", result.robot},
              {"level", result.level},
              {"base_fitted_to_measurements", result.fit_base},
              {"measurements", result.measurements},
              {"threads", result.threads}});
  return out;
}

}  // namespace robcal
