/// `robcal calibrate`: identify a robot's parameters from measurements
/// (docs/method/04-identification.md) and write the calibrated model.

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <iostream>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/identify/calibration_run.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/report/provenance.hpp"

namespace robcal::cli {
namespace {

struct CalibrateArgs {
  std::string robot, tool, measurements, level = "full", loss = "none", out, units, euler, folds;
  std::vector<std::string> identify, fix;
  double huber_scale = 0;
  double orientation_weight = kDefaultOrientationWeightMm;
  double sigma = 0;
  int kfold = 0;
  uint64_t seed = 1;
  bool json = false, keep_near_dependent = false, force = false;
};

const char* status_text(ParameterStatus s) {
  return s == ParameterStatus::Identified ? "identified"
         : s == ParameterStatus::Dropped  ? "dropped"
                                          : "fixed";
}

nlohmann::json per_fold_json(const CrossValidation& cv) {
  nlohmann::json out = nlohmann::json::array();
  for (const FoldErrors& f : cv.per_fold)
    out.push_back({{"rows", f.rows},
                   {"mean", tidy(f.mean_mm)},
                   {"std", tidy(f.std_mm)},
                   {"max", tidy(f.max_mm)}});
  return out;
}

nlohmann::json to_json(const CalibrationRun& run, const CalibrateArgs& args, size_t rows,
                       MeasurementKind kind, bool written) {
  const IdentificationResult& r = run.result;
  const CrossValidation* cv = run.cross_validation ? &*run.cross_validation : nullptr;
  nlohmann::json out;
  out["robot"] = r.robot.model.name;
  out["level"] = r.robot.level;
  out["rows"] = rows;
  out["converged"] = r.status.converged;
  out["iterations"] = r.status.iterations;
  out["solver_message"] = r.status.message;
  out["residuals"] = r.residual_count;
  out["identified"] = r.identified_count;
  if (kind == MeasurementKind::Poses)
    out["orientation_weight_mm_per_rad"] = args.orientation_weight;
  out["warnings"] = r.warnings;
  out["residual_per_row_mm"] = {
      {"mean", tidy(r.mean_mm)}, {"rms", tidy(r.rms_mm)}, {"max", tidy(r.max_mm)}};
  out["start_residual_per_row_mm"] = {{"mean", tidy(r.start_mean_mm)},
                                      {"rms", tidy(r.start_rms_mm)},
                                      {"max", tidy(r.start_max_mm)}};
  out["rms_mm"] = tidy(r.rms_mm);
  out["max_mm"] = tidy(r.max_mm);
  if (r.noise_test.tested)
    out["noise_test"] = {{"instrument_sigma_mm", r.noise_test.instrument_sigma_mm},
                         {"chi_square", tidy(r.noise_test.chi_square)},
                         {"dof", r.noise_test.dof},
                         {"p_value", r.noise_test.p_value},
                         {"consistent", r.noise_test.consistent}};
  out["sigma_mm"] = tidy(r.sigma_mm);
  out["condition_number"] = r.condition_number;
  if (r.huber_scale_mm > 0) out["huber_scale_mm"] = tidy(r.huber_scale_mm);
  out["by_target"] = nlohmann::json::array();
  for (const auto& t : r.by_target)
    out["by_target"].push_back({{"target", t.target},
                                {"rows", t.rows},
                                {"rms_mm", tidy(t.rms_mm)},
                                {"max_mm", tidy(t.max_mm)}});
  out["parameters"] = nlohmann::json::array();
  for (const auto& u : r.unknowns) {
    nlohmann::json p = {{"name", u.name},
                        {"unit", u.unit},
                        {"nominal", tidy(u.nominal, 12)},
                        {"value", tidy(u.value, 12)},
                        {"std", u.std_dev},
                        {"status", status_text(u.status)}};
    if (!u.reason.empty()) p["reason"] = u.reason;
    out["parameters"].push_back(p);
  }
  out["groups"] = nlohmann::json::array();
  for (const GroupSignificance& g : group_significance(r.robot))
    if (g.enabled)
      out["groups"].push_back({{"name", g.group},
                               {"identified", g.identified},
                               {"wald", tidy(g.wald)},
                               {"p_value", g.p_value},
                               {"significant", g.significant}});
  out["correlations"] = nlohmann::json::array();
  for (const auto& c : r.correlations)
    out["correlations"].push_back(
        {{"first", c.first}, {"second", c.second}, {"rho", tidy(c.rho, 6)}});
  out["suspected_outliers"] = nlohmann::json::array();
  for (const auto& o : r.outliers)
    out["suspected_outliers"].push_back(
        {{"config", o.config}, {"line", o.line}, {"residual_mm", tidy(o.residual_mm)}});
  const PredictedAccuracy& p = r.predicted;
  out["predicted_position_error_mm"] = {
      {"configurations", p.configurations},
      {"seed", args.seed},
      {"against_truth",
       {{"mean", tidy(p.mean_mm)}, {"rms", tidy(p.rms_mm)}, {"max", tidy(p.max_mm)}}},
      {"against_new_measurements",
       {{"mean", tidy(p.mean_vs_measurements_mm)}, {"rms", tidy(p.rms_vs_measurements_mm)}}}};
  if (cv)
    out["cross_validation"] = {{"folds", cv->folds},
                               {"run_because_of_misfit", run.cross_validation_for_misfit},
                               {"user_folds", cv->user_folds},
                               {"per_fold", per_fold_json(*cv)},
                               {"seed", cv->seed},
                               {"rows", cv->errors_mm.size()},
                               {"error_mm",
                                {{"mean", tidy(cv->mean_mm)},
                                 {"std", tidy(cv->std_mm)},
                                 {"mean_plus_3std", tidy(cv->mean_plus_3std_mm())},
                                 {"max", tidy(cv->max_mm)}}}};
  out["problems"] = run.problems;
  out["output"] = written ? nlohmann::json(args.out) : nlohmann::json(nullptr);
  return out;
}

void print_report(const CalibrationRun& run, const CalibrateArgs& args,
                  const MeasurementSet& data) {
  const IdentificationResult& r = run.result;
  const CrossValidation* cv = run.cross_validation ? &*run.cross_validation : nullptr;
  fmt::print("calibrated {} at level {} from {} rows of {} ({})\n", r.robot.model.name,
             r.robot.level, data.size(), measurement_kind_name(data.kind), data.file);
  fmt::print("solver: {} after {} iterations ({})\n",
             r.status.converged ? "converged" : "DID NOT CONVERGE", r.status.iterations,
             r.status.message);
  const char* what = data.kind == MeasurementKind::Distances ? "|length error|"
                     : data.kind == MeasurementKind::Poses   ? "TCP position error"
                                                             : "3D position error";
  fmt::print("residual per row ({}), training data:\n", what);
  fmt::print("  calibrated:               mean {:.4f}  rms {:.4f}  max {:.4f} mm\n", r.mean_mm,
             r.rms_mm, r.max_mm);
  fmt::print("  nominal (rigid fit only): mean {:.4f}  rms {:.4f}  max {:.4f} mm\n",
             r.start_mean_mm, r.start_rms_mm, r.start_max_mm);
  fmt::print("σ {:.4f} mm per residual component ({} residuals, {} unknowns)\n", r.sigma_mm,
             r.residual_count, r.identified_count);
  if (r.noise_test.tested)
    fmt::print(
        "noise test against the instrument's σ {:g} mm: χ² {:.1f} for {} degrees of freedom, "
        "p = {:.2g}: {}\n",
        r.noise_test.instrument_sigma_mm, r.noise_test.chi_square, r.noise_test.dof,
        r.noise_test.p_value,
        r.noise_test.consistent ? "the residuals are the instrument's noise"
                                : "the residuals EXCEED what the instrument's noise explains: "
                                  "the model misses systematic effects (or σ is understated)");
  if (data.kind == MeasurementKind::Poses)
    fmt::print("orientation residuals weighted {:g} mm per rad (--orientation-weight)\n",
               args.orientation_weight);
  for (const auto& t : r.by_target)
    fmt::print("  target {:<8} {:>4} rows  rms {:.4f}  max {:.4f} mm\n", t.target, t.rows, t.rms_mm,
               t.max_mm);
  fmt::print("\nparameters (value ± 1σ; nominal):\n");
  int fixed = 0;
  for (const auto& u : r.unknowns) {
    if (u.status == ParameterStatus::Fixed) {
      ++fixed;
      continue;
    }
    if (u.status == ParameterStatus::Dropped) {
      fmt::print("  {:<22} dropped, {}\n", u.name, u.reason);
      continue;
    }
    fmt::print("  {:<22} {:>16.6g} ± {:<10.3g} {:<9} (nominal {:.6g})\n", u.name, u.value,
               u.std_dev, u.unit, u.nominal);
  }
  fmt::print("  ({} parameters held at their nominal values)\n", fixed);
  for (const GroupSignificance& g : group_significance(r.robot))
    if (g.enabled)
      fmt::print("group {}: Wald {:.1f} for {} parameters, p = {:.2g}: {}\n", g.group, g.wald,
                 g.identified, g.p_value,
                 g.significant ? "significant"
                               : "NOT significant: the data do not show this effect, the group "
                                 "can be left out");
  if (!r.correlations.empty()) {
    fmt::print("strongest correlations:");
    for (size_t i = 0; i < r.correlations.size() && i < 5; ++i)
      fmt::print("{} {}~{} {:+.3f}", i ? "," : "", r.correlations[i].first,
                 r.correlations[i].second, r.correlations[i].rho);
    fmt::print("\n");
  }
  if (!r.outliers.empty()) {
    fmt::print("suspected outliers (residual beyond 4 robust σ):\n");
    for (const auto& o : r.outliers)
      fmt::print("  config {} (line {}): {:.4f} mm\n", o.config, o.line, o.residual_mm);
  }
  const PredictedAccuracy& p = r.predicted;
  if (!r.noise_test.consistent)
    fmt::print(
        "the covariance-based prediction below counts the misfit as random noise: trust the "
        "cross-validated error{}\n",
        cv ? "" : " (--kfold; too few configurations to run it by default)");
  fmt::print(
      "predicted position error (from the covariance) over {} configurations in the measured joint "
      "ranges "
      "(seed {}):\n  against the true robot:    mean {:.4f}  rms {:.4f}  max {:.4f} mm\n"
      "  against new measurements:  mean {:.4f}  rms {:.4f} mm (adds σ = {:.4f} mm per "
      "axis of instrument noise)\n",
      p.configurations, args.seed, p.mean_mm, p.rms_mm, p.max_mm, p.mean_vs_measurements_mm,
      p.rms_vs_measurements_mm, p.measurement_sigma_mm);
  if (cv)
    fmt::print(
        "cross-validation ({} folds, {}{}), held-out error over {} rows: mean {:.4f}  "
        "std {:.4f}  mean+3std {:.4f}  max {:.4f} mm\n",
        cv->folds, cv->user_folds ? "from the folds file" : fmt::format("seed {}", cv->seed),
        run.cross_validation_for_misfit ? ", run because of the misfit" : "", cv->errors_mm.size(),
        cv->mean_mm, cv->std_mm, cv->mean_plus_3std_mm(), cv->max_mm);
  if (cv)
    for (size_t f = 0; f < cv->per_fold.size(); ++f)
      fmt::print("  fold {:<3} {:>4} rows  mean {:.4f}  std {:.4f}  max {:.4f} mm\n", f + 1,
                 cv->per_fold[f].rows, cv->per_fold[f].mean_mm, cv->per_fold[f].std_mm,
                 cv->per_fold[f].max_mm);
  for (const std::string& problem : run.problems) fmt::print("PROBLEM: {}\n", problem);
  if (run.problems.empty() || args.force) fmt::print("written {}\n", args.out);
}

void run_calibrate(const CalibrateArgs& args) {
  check_orientation_weight(args.orientation_weight);
  const RobotModel model = load_robot(args.robot);
  const Tool tool = load_tool(args.tool);
  MeasurementFormat format;
  if (!args.units.empty()) parse_units(args.units, {"", 0, 0, "--units"}, format);
  if (!args.euler.empty()) format.euler = parse_euler_order(args.euler, {"", 0, 0, "--euler"});
  const MeasurementFile file = read_measurements_csv(args.measurements, tool, {}, format);
  for (const std::string& w : file.warnings) std::cerr << "warning: " << w << "\n";
  if (args.loss != "none" && args.loss != "huber")
    throw InputError({"", 0, 0, "--loss"},
                     fmt::format("unknown loss '{}': expected none or huber", args.loss));
  IdentifyOptions options;
  options.level = parse_calibration_level(args.level);
  options.identify = args.identify;
  options.fix = args.fix;
  options.huber = args.loss == "huber";
  options.huber_scale_mm = args.huber_scale;
  options.orientation_weight_mm = args.orientation_weight;
  options.seed = args.seed;
  options.instrument_sigma_mm = args.sigma;
  options.resolve_near_dependencies = !args.keep_near_dependent;
  CalibrationRequest request{options, args.kfold, {}};
  if (!args.folds.empty()) request.folds = read_folds_csv(args.folds);
  const bool progress = !args.json && stdout_is_terminal();
  if (progress) fmt::print("calibrating ({} rows)…\n", file.measurements.size());
  const CalibrationRun run = run_calibration(model, tool, file.measurements, request);
  const IdentificationResult& result = run.result;
  for (const std::string& w : result.warnings) std::cerr << "warning: " << w << "\n";
  YAML::Node statistics = YAML::Load(statistics_yaml(result));
  if (run.cross_validation) {
    const CrossValidation& cv = *run.cross_validation;
    statistics["cross_validation"]["folds"] = cv.folds;
    statistics["cross_validation"]["seed"] = cv.seed;
    statistics["cross_validation"]["mean_mm"] = cv.mean_mm;
    statistics["cross_validation"]["std_mm"] = cv.std_mm;
    statistics["cross_validation"]["max_mm"] = cv.max_mm;
  }
  // Where the model came from; `robcal report` shows it with the fit's statistics.
  Provenance provenance = start_provenance_of_process();
  provenance.robot = model.name;
  provenance.level = args.level;
  provenance.seed = args.seed;
  provenance.files = {provenance_file("tool", args.tool),
                      provenance_file("measurements", args.measurements)};
  statistics["provenance"] = YAML::Load(provenance_yaml(provenance));
  if (!run.problems.empty()) statistics["problems"] = run.problems;
  YAML::Emitter emitter;
  emitter.SetDoublePrecision(9);
  emitter << statistics;
  const bool write = run.problems.empty() || args.force;
  if (write)
    write_file_atomically(args.out, calibrated_robot_to_yaml(result.robot, emitter.c_str()));
  if (args.json)
    print_json(to_json(run, args, file.measurements.size(), file.measurements.kind, write));
  else
    print_report(run, args, file.measurements);
  if (!write)
    throw std::runtime_error(fmt::format(
        "{} not written: the fit is not trustworthy ({} problem{} above); fix the cause, or "
        "write it anyway with --force",
        args.out, run.problems.size(), run.problems.size() > 1 ? "s" : ""));
}

const bool registered = register_command(30, [](CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "calibrate",
      "Identify the robot's parameters from measurements and write the calibrated model");
  auto args = std::make_shared<CalibrateArgs>();
  cmd->add_option("--robot", args->robot, "Built-in robot name or robot file")->required();
  cmd->add_option("--tool", args->tool, "Tool file (payload, targets, tcp)")->required();
  cmd->add_option("--measurements", args->measurements,
                  "Measurement CSV (points, poses or distances)")
      ->required();
  cmd->add_option("--units", args->units,
                  "Units of the measurement file when it does not declare them ('# units: m, "
                  "rad'): a length unit mm or m and/or an angle unit deg or rad");
  cmd->add_option("--euler", args->euler,
                  "Rotation order of rx,ry,rz columns when the file does not declare it "
                  "('# euler: intrinsic ZYX'): intrinsic or extrinsic and an order of X, Y, Z");
  cmd->add_option("--level", args->level, "base, joints, kinematic or full (default full)");
  cmd->add_option("--identify", args->identify,
                  "Also identify the parameters matching this glob (repeatable), e.g. "
                  "'joint*.scale'");
  cmd->add_option("--fix", args->fix,
                  "Hold the parameters matching this glob at nominal (repeatable), e.g. 'link6.*'");
  cmd->add_option("--loss", args->loss, "none (least squares) or huber (robust; lists outliers)");
  cmd->add_option("--huber-scale", args->huber_scale,
                  "Huber threshold in mm (default: 3 × the robust σ of a least-squares pass)");
  cmd->add_option("--orientation-weight", args->orientation_weight,
                  "Poses files: mm per rad of orientation residual, the instrument's ratio of "
                  "position to orientation noise (validate takes the same option)")
      ->capture_default_str();
  cmd->add_option("--sigma", args->sigma,
                  "The instrument's stated noise σ per axis in mm: the residuals are tested "
                  "against it (χ²); a misfit is reported and cross-validated");
  cmd->add_flag("--keep-near-dependent", args->keep_near_dependent,
                "Fit near-dependent parameter groups anyway (default: hold the latest of each at "
                "nominal, warned)");
  cmd->add_flag("--force", args->force,
                "Write the model even when the fit did not converge or looks implausible");
  cmd->add_option("--kfold", args->kfold, "Estimate accuracy by K-fold cross-validation");
  cmd->add_option("--folds", args->folds,
                  "Cross-validate with these folds instead of seeded ones: CSV config,fold "
                  "(fold 1..K)");
  cmd->add_option("--seed", args->seed,
                  "Seed of the cross-validation folds and predicted-accuracy samples (default 1)");
  cmd->add_flag("--json", args->json, "Machine-readable summary on stdout");
  cmd->add_option("--out", args->out, "Calibrated model file to write (YAML)")->required();
  cmd->callback([args] { run_calibrate(*args); });
});

}  // namespace
}  // namespace robcal::cli
