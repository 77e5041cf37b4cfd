/// `robcal calibrate`: identify a robot's parameters from measurements
/// (docs/method/04-identification.md) and write the calibrated model.

#include <fmt/format.h>

#include <iostream>
#include <optional>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/identify/calibrate_workflow.hpp"
#include "robcal/identify/calibration_output.hpp"
#include "robcal/io/measurement_file.hpp"

namespace robcal::cli {
namespace {

struct CalibrateArgs {
  std::string robot, tool, model, measurements, level, loss = "none", out, units, euler, folds,
                                                       warmup_tau;
  std::vector<std::string> identify, fix;
  double huber_scale = 0;
  double orientation_weight = kDefaultOrientationWeightMm;
  double sigma = 0;
  int kfold = 0;
  uint64_t seed = 1;
  bool json = false, keep_near_dependent = false, force = false;
};

void print_report(const CalibrationRun& run, const std::string& out, bool refused) {
  const IdentificationResult& r = run.result;
  const CrossValidation* cv = run.cross_validation ? &*run.cross_validation : nullptr;
  if (r.reidentification)
    fmt::print("re-identified {} on the calibrated {} (level {}) from {} rows of {} ({})\n",
               r.reidentification->what, r.robot.model.name, r.robot.level, run.rows,
               measurement_kind_name(run.kind), run.file);
  else
    fmt::print("calibrated {} at level {} from {} rows of {} ({})\n", r.robot.model.name,
               r.robot.level, run.rows, measurement_kind_name(run.kind), run.file);
  fmt::print("solver: {} after {} iterations ({})\n",
             r.status.converged ? "converged" : "DID NOT CONVERGE", r.status.iterations,
             r.status.message);
  const char* what = run.kind == MeasurementKind::Distances ? "|length error|"
                     : run.kind == MeasurementKind::Poses   ? "TCP position error"
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
  if (run.kind == MeasurementKind::Poses)
    fmt::print("orientation residuals weighted {:g} mm per rad (--orientation-weight)\n",
               run.options.orientation_weight_mm);
  for (const auto& t : r.by_target)
    fmt::print("  target {:<8} {:>4} rows  rms {:.4f}  max {:.4f} mm\n", t.target, t.rows, t.rms_mm,
               t.max_mm);
  fmt::print("\nparameters (value ± 1σ; nominal):\n");
  int fixed = 0, opt_in = 0;
  for (const auto& u : r.unknowns) {
    if (u.status == ParameterStatus::Fixed) {
      ++(u.opt_in_not_asked ? opt_in : fixed);
      continue;
    }
    if (r.reidentification && u.status == ParameterStatus::Identified)
      continue;  // listed below with the values they replace
    if (u.status == ParameterStatus::Dropped) {
      fmt::print("  {:<22} dropped, {}\n", u.name, u.reason);
      continue;
    }
    fmt::print("  {:<22} {:>16.6g} ± {:<10.3g} {:<9} (nominal {:.6g})\n", u.name, u.value,
               u.std_dev, u.unit, u.nominal);
  }
  fmt::print("  ({} parameters held at their {} values{})\n", fixed,
             r.reidentification ? "calibrated" : "nominal",
             opt_in > 0 ? fmt::format("; {} opt-in terms not asked for", opt_in) : "");
  if (r.reidentification) {
    fmt::print("re-identified ({}) on the calibrated model, the rest kept:\n",
               r.reidentification->what);
    for (const ReidentifiedValue& v : r.reidentification->values)
      fmt::print("  {:<22} {:>16.6g} ± {:<10.3g} {:<9} (was {:.6g})\n", v.name, v.value, v.std_dev,
                 v.unit, v.before);
  }
  for (const GroupSignificance& g : group_significance(r.robot))
    if (g.enabled && g.identified == 0)
      fmt::print("group {}: NOT identified by these measurements (the warning above says why)\n",
                 g.group);
    else if (g.enabled)
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
      p.configurations, run.options.seed, p.mean_mm, p.rms_mm, p.max_mm, p.mean_vs_measurements_mm,
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
  if (!refused) fmt::print("written {}\n", out);
}

void run_calibrate(const CalibrateArgs& args) {
  CalibrateFilesRequest request{args.robot, args.model, args.tool, args.measurements, args.units,
                                args.euler, args.level, args.loss, args.folds,        {}};
  IdentifyOptions& options = request.request.options;
  options.identify = args.identify;
  options.fix = args.fix;
  options.huber_scale_mm = args.huber_scale;
  options.orientation_weight_mm = args.orientation_weight;
  options.seed = args.seed;
  options.instrument_sigma_mm = args.sigma;
  options.resolve_near_dependencies = !args.keep_near_dependent;
  if (!args.warmup_tau.empty())
    options.warmup_time_constant_s = parse_numbers(args.warmup_tau, 1, "--warmup-tau-s")[0];
  request.request.kfold = args.kfold;
  if (!args.json && stdout_is_terminal()) fmt::print("calibrating…\n");
  const CalibrationRun run = calibrate_files(request);
  for (const std::string& w : run.warnings) std::cerr << "warning: " << w << "\n";
  const Provenance provenance =
      calibration_provenance(run, {args.model, args.tool, args.measurements});
  const std::optional<std::string> refusal =
      write_calibration(run, args.out, args.force, &provenance);
  if (args.json)
    print_json(calibration_run_json(run, refusal ? "" : args.out));
  else
    print_report(run, args.out, refusal.has_value());
  if (refusal) throw std::runtime_error(*refusal);
}

const bool calibrate_registered = register_command(30, [](CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "calibrate",
      "Identify the robot's parameters from measurements and write the calibrated model");
  auto args = std::make_shared<CalibrateArgs>();
  cmd->add_option("--robot", args->robot, "Built-in robot name or robot file");
  cmd->add_option("--model", args->model,
                  "A calibrated model file to start from instead of --robot: only what --level "
                  "tool, --level base or --identify asks is re-identified, the rest is kept");
  cmd->add_option("--tool", args->tool,
                  "Tool file (payload, targets, tcp); with --model: the new tool (--level tool), "
                  "else the model's tool is used");
  cmd->add_option("--measurements", args->measurements,
                  "Measurement CSV (points, poses or distances)")
      ->required();
  cmd->add_option("--units", args->units,
                  "Units of the measurement file when it does not declare them ('# units: m, "
                  "rad'): a length unit mm or m and/or an angle unit deg or rad");
  cmd->add_option("--euler", args->euler,
                  "Rotation order of rx,ry,rz columns when the file does not declare it "
                  "('# euler: intrinsic ZYX'): intrinsic or extrinsic and an order of X, Y, Z");
  cmd->add_option("--level", args->level,
                  "base, joints, kinematic or full (default full); with --model also tool (a new "
                  "tool's points or TCP frame) and no default (say what to re-identify)");
  cmd->add_option(
      "--identify", args->identify,
      "Also identify the parameters matching this glob (repeatable), e.g. "
      "'joint*.scale', or an opt-in group by name: periodic, backlash, mounting, "
      "thermal, warmup, motor_periodic (joints with a gear_ratio), gravity (its direction), "
      "groups (all of them)");
  cmd->add_option("--warmup-tau-s", args->warmup_tau,
                  "Time constant (s) of the warm-up 1 - exp(-t/tau) for the warmup group, rows "
                  "with a time_s column (default: the robot file's warmup_time_constant_s, 1800)");
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
