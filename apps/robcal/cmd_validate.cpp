/// `robcal validate`: absolute position errors and all-pairs distance errors of a model against
/// measurements it was not fitted to (METHOD §9).

#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/validate/base_fit.hpp"
#include "robcal/validate/validation.hpp"

namespace robcal::cli {
namespace {

struct ValidateOptions {
  std::string robot;
  std::string tool;
  std::string model;
  std::string measurements;
  bool fit_base = false;
  bool json = false;
  int threads = 2;
};

nlohmann::json statistics_json(const ErrorStatistics& s) {
  return {{"mean", s.mean},
          {"std", s.std},
          {"mean_plus_3std", s.mean_plus_3std()},
          {"min", s.min},
          {"max", s.max}};
}

nlohmann::json histogram_json(const Histogram& h) {
  return {{"lower", h.lower}, {"upper", h.upper}, {"counts", h.counts}};
}

void print_statistics_row(const std::string& label, const ErrorStatistics& s) {
  fmt::print("  {:<10} {:>8} {:>10.4f} {:>10.4f} {:>10.4f} {:>10.4f}\n", label, s.count, s.mean,
             s.std, s.mean_plus_3std(), s.max);
}

void run_validate(const ValidateOptions& options) {
  const RobotModel model = load_robot(options.robot);
  const Tool tool = load_tool(options.tool);
  CalibratedRobot robot = CalibratedRobot::nominal(model, tool);
  if (!options.model.empty()) {
    robot = load_calibrated_robot(options.model);
    if (robot.model.name != model.name)
      throw InputError({options.model, 0, 0, "--model"},
                       fmt::format("this is a model of the {}, not of the {} (--robot {})",
                                   robot.model.name, model.name, options.robot));
    // The model's tool holds the identified target coordinates; an older file may have none.
    if (robot.tool.targets.empty()) robot.tool = tool;
  }
  MeasurementFile file = read_measurements_csv(options.measurements, robot.tool,
                                               {MeasurementKind::Points, MeasurementKind::Poses});
  for (const std::string& warning : file.warnings) std::cerr << "warning: " << warning << "\n";
  const MeasurementSet& set = file.measurements;
  std::string frame = "the model's world frame";
  if (!robot.base_fitted) {
    if (!options.fit_base)
      throw InputError(
          {options.measurements, 0, 0, "--fit-base"},
          fmt::format("the {} model of {} has no world frame (its base was never fitted), so its "
                      "positions cannot be compared with measured ones. Calibrate at least the "
                      "base: `robcal calibrate --robot {} --tool {} --measurements CAL.csv --level "
                      "base --out model.yaml`, then validate with --model model.yaml; or pass "
                      "--fit-base to place it by a rigid best fit to these measurements",
                      robot.level, model.name, options.robot, options.tool));
    robot = fit_base(robot, set);
    frame = "base fitted to these measurements (6 parameters, rigid best fit)";
  }

  const ValidationReport report = validate_model(robot, set, options.threads);
  const PositionErrors& positions = report.positions;
  const PairwiseDistanceErrors& distances = report.distances;

  if (options.json) {
    nlohmann::json out;
    out["points"] = set.size();
    out["position_error_mm"] = statistics_json(positions.position_mm);
    out["distance_error_mm"] = statistics_json(distances.stats);
    out["distance_error_mm"]["pairs"] = distances.stats.count;
    out["distance_error_mm"]["histogram"] = histogram_json(distances.histogram);
    out["position_histogram_mm"] = histogram_json(report.position_histogram);
    out["per_target"] = nlohmann::json::array();
    for (const TargetErrorStatistics& t : positions.per_target) {
      nlohmann::json entry = statistics_json(t.position_mm);
      entry["target"] = t.target;
      entry["rows"] = t.position_mm.count;
      out["per_target"].push_back(entry);
    }
    if (set.kind == MeasurementKind::Poses)
      out["orientation_error_deg"] = statistics_json(positions.orientation_deg);
    out["kind"] = measurement_kind_name(set.kind);
    out["robot"] = model.name;
    out["level"] = robot.level;
    out["base_fitted_to_measurements"] = options.fit_base;
    out["measurements"] = options.measurements;
    out["threads"] = options.threads;
    print_json(out);
    return;
  }

  fmt::print("validation of {} ({} model; {}) against {}: {} {}\n\n", model.name, robot.level,
             frame, options.measurements, set.size(), measurement_kind_name(set.kind));
  fmt::print("absolute position error (mm)\n");
  fmt::print("  {:<10} {:>8} {:>10} {:>10} {:>10} {:>10}\n", "target", "rows", "mean", "std",
             "mean+3std", "max");
  if (positions.per_target.size() > 1)
    for (const TargetErrorStatistics& t : positions.per_target)
      print_statistics_row(t.target, t.position_mm);
  print_statistics_row(set.kind == MeasurementKind::Poses ? "TCP" : "all", positions.position_mm);
  if (set.kind == MeasurementKind::Poses) {
    fmt::print("\norientation error (deg)\n");
    print_statistics_row("TCP", positions.orientation_deg);
  }
  fmt::print("\nposition error histogram\n{}", histogram_text(report.position_histogram, "mm"));
  fmt::print("\ndistance error over all {} pairs of rows (mm): | |m_i − m_j| − |p_i − p_j| |\n",
             distances.stats.count);
  fmt::print("  mean {:.4f}  std {:.4f}  mean+3std {:.4f}  min {:.4f}  max {:.4f}\n",
             distances.stats.mean, distances.stats.std, distances.stats.mean_plus_3std(),
             distances.stats.min, distances.stats.max);
  if (distances.stats.count > 0)
    fmt::print("distance error histogram ({} bins over [0, {:.4f}) mm, shown by 8)\n{}",
               distances.histogram.counts.size(), distances.histogram.upper,
               histogram_text(merge_bins(distances.histogram, 8), "mm"));
}

const bool registered = register_command(60, [](CLI::App& app) {
  auto options = std::make_shared<ValidateOptions>();
  auto* cmd = app.add_subcommand(
      "validate",
      "Absolute position error (mean, std, mean+3std, max, per target, histogram) and distance "
      "error over every pair of rows, of a model against measurements");
  cmd->add_option("--robot", options->robot, "Built-in robot name or robot file")->required();
  cmd->add_option("--tool", options->tool, "Tool file (payload, targets, tcp)")->required();
  cmd->add_option("--model", options->model,
                  "Calibrated model written by `robcal calibrate` (default: the nominal robot)");
  cmd->add_option("--measurements", options->measurements,
                  "Validation measurements: points or poses CSV (mm, degrees)")
      ->required();
  cmd->add_flag("--fit-base", options->fit_base,
                "For a model without a world frame (the nominal robot): first fit its 6 base "
                "parameters to these measurements (rigid best fit)");
  cmd->add_option("--threads", options->threads,
                  "Threads for the all-pairs distance errors (results do not depend on it)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  cmd->add_flag("--json", options->json, "Machine-readable output");
  cmd->callback([options] { run_validate(*options); });
});

}  // namespace
}  // namespace robcal::cli
