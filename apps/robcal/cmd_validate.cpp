/// `robcal validate`: absolute position errors and all-pairs distance errors of a model against
/// measurements it was not fitted to (docs/method/09-validation.md).

#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/validate/validate_workflow.hpp"

namespace robcal::cli {
namespace {

struct ValidateFlags {
  ValidateRequest request;
  std::string ballbar_centre;  ///< X,Y,Z mm; empty: identified from the rows
  bool json = false;
};

void print_statistics_row(const std::string& label, const ErrorStatistics& s, int width = 10) {
  if (s.count == 0) {
    fmt::print("  {:<{}} {:>8} {:>10}\n", label, width, 0, "no data");
    return;
  }
  fmt::print("  {:<{}} {:>8} {:>10.4f} {:>10.4f} {:>10.4f} {:>10.4f}\n", label, width, s.count,
             s.mean, s.std, s.mean_plus_3std(), s.max);
}

/// Distance errors over the pairs of rows inside each configuration class.
void print_class_pairs(const std::vector<ClassTable>& tables) {
  fmt::print("\ndistance error by class (mm), over the pairs of rows both in the class\n");
  for (const ClassTable& t : tables) {
    if (t.rows.empty() || !t.rows.front().pairs) continue;
    fmt::print("  {:<12} {:>10} {:>10} {:>10} {:>10} {:>12} {:>10}\n", t.name, "pairs", "mean",
               "std", "max", "signed mean", "positive");
    for (const ClassRow& r : t.rows) {
      const PairwiseDistanceErrors& p = *r.pairs;
      if (p.stats.count == 0)
        fmt::print("  {:<12} {:>10} {:>10}\n", r.label, 0, "no data");
      else
        fmt::print("  {:<12} {:>10} {:>10.4f} {:>10.4f} {:>10.4f} {:>+12.4f} {:>9.1f}%\n", r.label,
                   p.stats.count, p.stats.mean, p.stats.std, p.stats.max, p.signed_mean,
                   100 * p.positive_share());
    }
  }
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
  print_class_pairs(tables);
}

void print_ballbar(const ValidateResult& result) {
  const BallbarErrors& errors = *result.ballbar;
  const std::string centre_text =
      errors.centre_fitted ? "identified from these rows (3 parameters fitted)" : "given";
  fmt::print("ballbar validation of {} ({} model) against {}: {} distances\n", result.robot,
             result.level, result.measurements, result.rows);
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
  fmt::print("every reading within the bar's range {:g} ± {:g} mm (nominal length {})\n",
             result.ballbar_range.nominal_length_mm, result.ballbar_range.range_mm,
             result.ballbar_range.length_given ? "given" : "the median reading");
  fmt::print("\nlength error by class (mm); configuration classes of the rows' joints\n");
  for (const ClassTable& t : errors.classes) {
    fmt::print("  {:<12} {:>8} {:>10} {:>10} {:>10} {:>10}\n", t.name, "rows", "mean", "std",
               "mean+3std", "max");
    for (const ClassRow& r : t.rows) print_statistics_row(r.label, r.position_mm, 12);
  }
  fmt::print("\nlength error histogram\n{}", histogram_text(result.ballbar_histogram, "mm"));
}

const char* frame_text(ValidationFrame frame) {
  if (frame == ValidationFrame::Refitted)
    return "the model's base re-registered to these measurements (6 parameters, rigid fit)";
  if (frame == ValidationFrame::Fitted)
    return "base fitted to these measurements (6 parameters, rigid best fit)";
  return "the model's world frame";
}

void print_validation(const ValidateResult& result) {
  const ValidationReport& report = *result.report;
  const PositionErrors& positions = report.positions;
  const PairwiseDistanceErrors& distances = report.distances;
  const bool poses = result.kind == MeasurementKind::Poses;
  fmt::print("validation of {} ({} model; {}) against {}: {} {}\n\n", result.robot, result.level,
             frame_text(result.frame), result.measurements, result.rows,
             measurement_kind_name(result.kind));
  fmt::print("absolute position error (mm)\n");
  fmt::print("  {:<10} {:>8} {:>10} {:>10} {:>10} {:>10}\n", "target", "rows", "mean", "std",
             "mean+3std", "max");
  if (positions.per_target.size() > 1)
    for (const TargetErrorStatistics& t : positions.per_target)
      print_statistics_row(t.target, t.position_mm);
  print_statistics_row(poses ? "TCP" : "all", positions.position_mm);
  if (poses) {
    fmt::print("\norientation error (deg)\n");
    print_statistics_row("TCP", positions.orientation_deg);
    fmt::print(
        "\npose error (mm): √(position² + ({:g} mm/rad × orientation)²), weighted as "
        "calibrate weighs them (--orientation-weight)\n",
        positions.orientation_weight_mm);
    print_statistics_row("TCP", positions.pose_mm);
  }
  print_class_tables(report.classes, poses);
  if (!result.region_classes)
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

void run_validate(ValidateFlags flags) {
  if (!flags.ballbar_centre.empty()) {
    const std::vector<double> c = parse_numbers(flags.ballbar_centre, 3, "--ballbar-centre");
    flags.request.options.ballbar_centre_mm = Eigen::Vector3d(c[0], c[1], c[2]);
  }
  const ValidateResult result = validate(flags.request);
  for (const std::string& note : result.notes) std::cerr << "note: " << note << "\n";
  for (const std::string& warning : result.warnings) std::cerr << "warning: " << warning << "\n";
  if (flags.json)
    print_json(validate_json(result));
  else if (result.ballbar)
    print_ballbar(result);
  else
    print_validation(result);
}

const bool validate_registered = register_command(60, [](CLI::App& app) {
  auto flags = std::make_shared<ValidateFlags>();
  ValidateRequest& r = flags->request;
  auto* cmd = app.add_subcommand(
      "validate",
      "Absolute position error (mean, std, mean+3std, max, per target, histogram) and distance "
      "error over every pair of rows, of a model against measurements");
  cmd->add_option("--robot", r.robot, "Built-in robot name or robot file")->required();
  cmd->add_option("--tool", r.tool, "Tool file (payload, targets, tcp)")->required();
  cmd->add_option("--model", r.model,
                  "Calibrated model written by `robcal calibrate` (default: the nominal robot)");
  cmd->add_option("--measurements", r.measurements,
                  "Validation measurements: points, poses or distances (ballbar) CSV (mm, "
                  "degrees)")
      ->required();
  cmd->add_option("--units", r.units,
                  "Units of the measurement files when they do not declare them ('# units: m, "
                  "rad'): a length unit mm or m and/or an angle unit deg or rad (as calibrate)");
  cmd->add_option("--euler", r.euler,
                  "Rotation order of rx,ry,rz columns when the file does not declare it "
                  "('# euler: intrinsic ZYX'): intrinsic or extrinsic and an order of X, Y, Z");
  cmd->add_option("--orientation-weight", r.options.orientation_weight_mm,
                  "Poses files: mm per rad of orientation error in the combined pose error "
                  "(as calibrate --orientation-weight)")
      ->capture_default_str();
  cmd->add_option("--ballbar-centre", flags->ballbar_centre,
                  "Distances (ballbar) files: the fixed centre X,Y,Z in mm in the model's frame "
                  "(default: identified from the rows)");
  cmd->add_option("--ballbar-length", r.options.ballbar_length_mm,
                  "Distances (ballbar) files: the bar's nominal length in mm (default: the median "
                  "reading); a reading outside length ± range is refused");
  cmd->add_option("--ballbar-range", r.options.ballbar_range_mm,
                  fmt::format("Distances (ballbar) files: the bar reads length ± range (mm; "
                              "default {:g})",
                              kDefaultBallbarRangeMm));
  cmd->add_option("--calibration", r.calibration,
                  "The calibration measurements (points or poses): adds the error tables by "
                  "region, the distance to the nearest calibration position");
  cmd->add_flag("--fit-base", r.options.fit_base,
                "First fit the 6 base parameters to these measurements (rigid best fit): places "
                "a model without a world frame, re-registers a calibrated one (moved robot or "
                "instrument)");
  cmd->add_option("--threads", r.options.threads,
                  "Threads for the all-pairs distance errors (results do not depend on it)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  cmd->add_flag("--json", flags->json, "Machine-readable output");
  cmd->callback([flags] { run_validate(*flags); });
});

}  // namespace
}  // namespace robcal::cli
