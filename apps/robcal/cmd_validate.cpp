/// `robcal validate`: absolute position errors and all-pairs distance errors of a model against
/// measurements it was not fitted to (docs/method/09-validation.md).

#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/validate/ballbar_error.hpp"
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
  double orientation_weight = kDefaultOrientationWeightMm;
  std::string ballbar_centre;  ///< X,Y,Z mm; empty: identified from the rows
  std::string calibration;     ///< calibration measurements, for the region classes
};

nlohmann::json statistics_json(const ErrorStatistics& s) {
  return {{"mean", s.mean},
          {"std", s.std},
          {"mean_plus_3std", s.mean_plus_3std()},
          {"min", s.min},
          {"max", s.max}};
}

nlohmann::json per_target_json(const std::vector<TargetErrorStatistics>& targets) {
  nlohmann::json out = nlohmann::json::array();
  for (const TargetErrorStatistics& t : targets) {
    nlohmann::json entry = statistics_json(t.position_mm);
    entry["target"] = t.target;
    entry["rows"] = t.position_mm.count;
    out.push_back(entry);
  }
  return out;
}

nlohmann::json histogram_json(const Histogram& h) {
  return {{"lower", h.lower}, {"upper", h.upper}, {"counts", h.counts}};
}

void print_statistics_row(const std::string& label, const ErrorStatistics& s, int width = 10) {
  if (s.count == 0) {
    fmt::print("  {:<{}} {:>8} {:>10}\n", label, width, 0, "no data");
    return;
  }
  fmt::print("  {:<{}} {:>8} {:>10.4f} {:>10.4f} {:>10.4f} {:>10.4f}\n", label, width, s.count,
             s.mean, s.std, s.mean_plus_3std(), s.max);
}

/// A class's statistics; a class without rows is {"rows": 0, "status": "no data"}.
nlohmann::json class_statistics_json(const ErrorStatistics& s) {
  if (s.count == 0) return {{"rows", 0}, {"status", "no data"}};
  nlohmann::json out = statistics_json(s);
  out["rows"] = s.count;
  return out;
}

nlohmann::json classes_json(const std::vector<ClassTable>& tables, bool poses) {
  nlohmann::json out = nlohmann::json::array();
  for (const ClassTable& t : tables) {
    nlohmann::json rows = nlohmann::json::array();
    for (const ClassRow& r : t.rows) {
      nlohmann::json row = {{"class", r.label},
                            {"position_error_mm", class_statistics_json(r.position_mm)}};
      if (poses) row["orientation_error_deg"] = class_statistics_json(r.orientation_deg);
      rows.push_back(row);
    }
    out.push_back({{"table", t.name}, {"rows", rows}});
  }
  return out;
}

void print_class_tables(const std::vector<ClassTable>& tables, bool poses) {
  const auto print = [&](const char* title, auto statistics_of) {
    fmt::print("\n{}\n", title);
    for (const ClassTable& t : tables) {
      // Points: the per-target table is printed above.
      if (t.name == "target" && !poses) continue;
      fmt::print("  {:<12} {:>8} {:>10} {:>10} {:>10} {:>10}\n", t.name, "rows", "mean", "std",
                 "mean+3std", "max");
      for (const ClassRow& r : t.rows) print_statistics_row(r.label, statistics_of(r), 12);
    }
  };
  print("absolute position error by class (mm); configuration classes of the rows' joints",
        [](const ClassRow& r) { return r.position_mm; });
  if (poses)
    print("orientation error by class (deg)", [](const ClassRow& r) { return r.orientation_deg; });
}

/// Ballbar rows (docs/method/09-validation.md): length errors against a given or identified centre;
/// distances need no world frame when the centre is identified.
void run_ballbar_validation(const ValidateOptions& options, const RobotModel& model,
                            const CalibratedRobot& robot, const MeasurementSet& set) {
  std::optional<Eigen::Vector3d> centre;
  if (!options.ballbar_centre.empty()) {
    const std::vector<double> c = parse_numbers(options.ballbar_centre, 3, "--ballbar-centre");
    centre = Eigen::Vector3d(c[0], c[1], c[2]);
  }
  const BallbarErrors errors = ballbar_errors(robot, set, centre);
  std::vector<double> absolute;
  for (double e : errors.length_error_mm) absolute.push_back(std::abs(e));
  const double top = std::max(errors.absolute_mm.max * (1 + 1e-9), 1e-9);
  const Histogram histogram = make_histogram(absolute, kPositionHistogramBins, 0.0, top);
  const std::string centre_text =
      errors.centre_fitted ? "identified from these rows (3 parameters fitted)" : "given";
  if (options.json) {
    nlohmann::json out;
    out["rows"] = set.size();
    out["kind"] = measurement_kind_name(set.kind);
    out["length_error_mm"] = statistics_json(errors.absolute_mm);
    out["length_error_mm"]["signed_mean"] = errors.signed_mean_mm;
    out["length_error_mm"]["signed_std"] = errors.signed_std_mm;
    out["length_error_mm"]["positive_share"] = errors.positive_share;
    out["length_error_histogram_mm"] = histogram_json(histogram);
    out["ballbar_centre_mm"] = {errors.centre_mm.x(), errors.centre_mm.y(), errors.centre_mm.z()};
    out["ballbar_centre"] = errors.centre_fitted ? "identified" : "given";
    out["per_target"] = per_target_json(errors.per_target);
    out["robot"] = model.name;
    out["level"] = robot.level;
    out["measurements"] = options.measurements;
    print_json(out);
    return;
  }
  fmt::print("ballbar validation of {} ({} model) against {}: {} distances\n", model.name,
             robot.level, options.measurements, set.size());
  fmt::print("centre {} at ({:.4f}, {:.4f}, {:.4f}) mm in the model's frame\n\n", centre_text,
             errors.centre_mm.x(), errors.centre_mm.y(), errors.centre_mm.z());
  fmt::print("length error (mm): |measured − modelled length|\n");
  fmt::print("  {:<10} {:>8} {:>10} {:>10} {:>10} {:>10}\n", "target", "rows", "mean", "std",
             "mean+3std", "max");
  if (errors.per_target.size() > 1)
    for (const TargetErrorStatistics& t : errors.per_target)
      print_statistics_row(t.target, t.position_mm);
  print_statistics_row("all", errors.absolute_mm);
  fmt::print("signed (measured − modelled): mean {:+.4f}  std {:.4f} mm; {:.1f}% positive\n",
             errors.signed_mean_mm, errors.signed_std_mm, 100 * errors.positive_share);
  fmt::print("\nlength error histogram\n{}", histogram_text(histogram, "mm"));
}

void run_validate(const ValidateOptions& options) {
  check_orientation_weight(options.orientation_weight);
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
    check_tool_against_model(robot, tool, options.tool);
    for (const Target& t : tool.targets) {
      const Target& m = robot.tool.targets[static_cast<size_t>(robot.tool.target_index(t.name))];
      if (t.known && (m.position_mm - t.position_mm).norm() > 1e-3)
        std::cerr << fmt::format(
            "note: target '{}': the model's calibrated coordinates are used, "
            "{:.4f} mm from the tool file's\n",
            t.name, (m.position_mm - t.position_mm).norm());
    }
  }
  MeasurementFile file = read_measurements_csv(
      options.measurements, robot.tool,
      {MeasurementKind::Points, MeasurementKind::Poses, MeasurementKind::Distances});
  for (const std::string& warning : file.warnings) std::cerr << "warning: " << warning << "\n";
  const MeasurementSet& set = file.measurements;
  if (!options.ballbar_centre.empty() && set.kind != MeasurementKind::Distances)
    throw InputError({options.measurements, 0, 0, "--ballbar-centre"},
                     fmt::format("--ballbar-centre is for distances (ballbar) files; this is a "
                                 "{} file",
                                 measurement_kind_name(set.kind)));
  if (set.kind == MeasurementKind::Distances) {
    if (options.fit_base)
      throw InputError({options.measurements, 0, 0, "--fit-base"},
                       "a distances (ballbar) file has no positions to fit a world frame to; "
                       "without --ballbar-centre the centre is identified, so no frame is needed");
    run_ballbar_validation(options, model, robot, set);
    return;
  }
  std::string frame = "the model's world frame";
  if (options.fit_base && robot.base_fitted) {
    // A moved instrument or robot: the calibrated model is re-registered, not re-identified.
    robot = fit_base(robot, set);
    frame = "the model's base re-registered to these measurements (6 parameters, rigid fit)";
  } else if (!robot.base_fitted) {
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

  std::optional<Eigen::Matrix3Xd> calibration;
  if (!options.calibration.empty()) {
    const MeasurementFile file = read_measurements_csv(
        options.calibration, robot.tool, {MeasurementKind::Points, MeasurementKind::Poses});
    calibration = measured_positions(file.measurements);
  }
  const ValidationReport report =
      validate_model(robot, set, options.threads, options.orientation_weight, calibration);
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
    out["distance_error_mm"]["signed_mean"] = distances.signed_mean;
    out["distance_error_mm"]["positive_share"] = distances.positive_share();
    out["per_target"] = per_target_json(positions.per_target);
    out["classes"] = classes_json(report.classes, set.kind == MeasurementKind::Poses);
    if (set.kind == MeasurementKind::Poses) {
      out["orientation_error_deg"] = statistics_json(positions.orientation_deg);
      out["pose_error_mm"] = statistics_json(positions.pose_mm);
      out["orientation_weight_mm_per_rad"] = positions.orientation_weight_mm;
    }
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
    fmt::print(
        "\npose error (mm): √(position² + ({:g} mm/rad × orientation)²), weighted as "
        "calibrate weighs them (--orientation-weight)\n",
        positions.orientation_weight_mm);
    print_statistics_row("TCP", positions.pose_mm);
  }
  print_class_tables(report.classes, set.kind == MeasurementKind::Poses);
  if (options.calibration.empty())
    fmt::print("(no --calibration file: the region classes are not shown)\n");
  fmt::print("\nposition error histogram\n{}", histogram_text(report.position_histogram, "mm"));
  fmt::print("\ndistance error over all {} pairs of rows (mm): | |m_i − m_j| − |p_i − p_j| |\n",
             distances.stats.count);
  fmt::print("  mean {:.4f}  std {:.4f}  mean+3std {:.4f}  min {:.4f}  max {:.4f}\n",
             distances.stats.mean, distances.stats.std, distances.stats.mean_plus_3std(),
             distances.stats.min, distances.stats.max);
  if (distances.stats.count > 0)
    fmt::print(
        "signed |m_i − m_j| − |p_i − p_j|: mean {:+.4f} mm; {:.1f}% positive (measured distance "
        "the longer)\n",
        distances.signed_mean, 100 * distances.positive_share());
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
                  "Validation measurements: points, poses or distances (ballbar) CSV (mm, "
                  "degrees)")
      ->required();
  cmd->add_option("--orientation-weight", options->orientation_weight,
                  "Poses files: mm per rad of orientation error in the combined pose error "
                  "(as calibrate --orientation-weight)")
      ->capture_default_str();
  cmd->add_option("--ballbar-centre", options->ballbar_centre,
                  "Distances (ballbar) files: the fixed centre X,Y,Z in mm in the model's frame "
                  "(default: identified from the rows)");
  cmd->add_option("--calibration", options->calibration,
                  "The calibration measurements (points or poses): adds the error tables by "
                  "region, the distance to the nearest calibration position");
  cmd->add_flag("--fit-base", options->fit_base,
                "First fit the 6 base parameters to these measurements (rigid best fit): places "
                "a model without a world frame, re-registers a calibrated one (moved robot or "
                "instrument)");
  cmd->add_option("--threads", options->threads,
                  "Threads for the all-pairs distance errors (results do not depend on it)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  cmd->add_flag("--json", options->json, "Machine-readable output");
  cmd->callback([options] { run_validate(*options); });
});

}  // namespace
}  // namespace robcal::cli
