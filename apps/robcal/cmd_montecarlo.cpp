/// `robcal montecarlo`: the spread of the calibrated robot's accuracy over repeated simulated
/// calibrations, against the Cramér–Rao prediction.

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/monte_carlo.hpp"

namespace robcal::cli {
namespace {

struct McOptions {
  MonteCarloOptions mc;
  double noise_mm = 0.022;
  std::string level = "full";
  std::string plan = "optimal";
  std::string validation_model = "first-order";
  bool json = false;
};

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const double position = p * static_cast<double>(values.size() - 1);
  const size_t below = static_cast<size_t>(position);
  const size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (position - static_cast<double>(below)) * (values[above] - values[below]);
}

void run_montecarlo(McOptions o) {
  if (o.plan != "optimal" && o.plan != "random")
    throw InputError({"", 0, 0, "--plan"}, "expected 'optimal' or 'random'");
  if (!(o.noise_mm > 0)) throw InputError({"", 0, 0, "--noise-mm"}, "must be positive");
  o.mc.level = parse_calibration_level(o.level);
  o.mc.optimal_plan = o.plan == "optimal";
  o.mc.validation_model = parse_validation_model(o.validation_model);
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  const TrueRobot truth = published_irb120_truth(model, tool);
  const VirtualInstrument tracker =
      standard_instrument(InstrumentKind::LaserTracker, truth, o.noise_mm);
  const MonteCarloSetup setup = prepare_monte_carlo(truth, tracker, model, tool, o.mc);
  const auto started = std::chrono::steady_clock::now();
  const MonteCarloResult result = run_monte_carlo(setup, o.mc);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  std::vector<double> means, maxima;
  for (const MonteCarloRun& run : result.runs)
    if (run.converged) {
      means.push_back(run.mean_mm);
      maxima.push_back(run.max_mm);
    }
  const int identified = static_cast<int>(setup.identification.free.size());
  if (o.json) {
    nlohmann::json j;
    j["seed"] = o.mc.seed;
    j["runs"] = o.mc.runs;
    j["failed"] = result.failed;
    j["poses"] = setup.template_set.size();
    j["validation"] = o.mc.validation;
    j["validation_model"] = validation_model_name(o.mc.validation_model);
    j["identified_parameters"] = identified;
    j["noise_mm"] = o.noise_mm;
    j["threads"] = o.mc.threads;
    j["observed"] = {{"rms_mm", result.observed_rms_mm},
                     {"mean_mm", result.observed_mean_mm},
                     {"run_mean_p05_mm", percentile(means, 0.05)},
                     {"run_mean_p95_mm", percentile(means, 0.95)},
                     {"run_max_p95_mm", percentile(maxima, 0.95)}};
    j["predicted"] = {{"rms_mm", setup.predicted.rms_mm},
                      {"mean_mm", setup.predicted.mean_mm},
                      {"max_mm", setup.predicted.max_mm}};
    j["ratio"] = result.ratio;
    j["seconds"] = seconds;
    print_json(j);
    return;
  }
  fmt::print(
      "Monte Carlo: {} calibrations of the published IRB 120 ({} poses, {} parameters "
      "identified, σ {} mm/axis), {} validation configurations each, seed {}\n",
      o.mc.runs, setup.template_set.size(), identified, o.noise_mm, o.mc.validation, o.mc.seed);
  fmt::print("  validation: {}\n",
             o.mc.validation_model == ValidationModel::Exact
                 ? "exact (forward kinematics of each calibrated model against the truth)"
                 : "first-order (J_v·δp + model-error bias at the truth; exact to second order in "
                   "the parameter error; --validation-model exact for full kinematics)");
  fmt::print("  error against the truth      observed      Cramér–Rao prediction\n");
  fmt::print("  RMS                          {:.5f} mm    {:.5f} mm\n", result.observed_rms_mm,
             setup.predicted.rms_mm);
  fmt::print("  mean                         {:.5f} mm    {:.5f} mm\n", result.observed_mean_mm,
             setup.predicted.mean_mm);
  fmt::print("  per-run mean, 5–95 %         {:.5f} – {:.5f} mm\n", percentile(means, 0.05),
             percentile(means, 0.95));
  fmt::print("  ratio observed/predicted RMS {:.4f} (1.00 for an efficient estimator)\n",
             result.ratio);
  if (result.failed > 0) fmt::print("  {} runs did not converge (left out)\n", result.failed);
  fmt::print("  {:.3f} s on {} thread(s)\n", seconds, o.mc.threads);
}

const bool registered = register_command(95, [](CLI::App& app) {
  auto o = std::make_shared<McOptions>();
  auto* cmd = app.add_subcommand(
      "montecarlo", "Repeated simulated calibrations: accuracy spread against Cramér–Rao");
  cmd->add_option("--runs", o->mc.runs, "Calibrations")->capture_default_str();
  cmd->add_option("--poses", o->mc.poses, "Calibration configurations")->capture_default_str();
  cmd->add_option("--validation", o->mc.validation, "Validation configurations")
      ->capture_default_str();
  cmd->add_option("--threads", o->mc.threads, "Threads (results do not depend on it)")
      ->capture_default_str();
  cmd->add_option("--seed", o->mc.seed, "Seed of every random draw")->capture_default_str();
  cmd->add_option("--noise-mm", o->noise_mm, "Tracker σ per axis, mm")->capture_default_str();
  cmd->add_option("--level", o->level, "Calibration level: base, joints, kinematic, full")
      ->capture_default_str();
  cmd->add_option("--plan", o->plan, "optimal (D-optimal of 5000) or random configurations")
      ->capture_default_str();
  cmd->add_option("--validation-model", o->validation_model,
                  "first-order (J_v·δp at the truth, one matrix-vector product per run) or exact "
                  "(forward kinematics at every validation configuration)")
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Machine-readable output");
  cmd->callback([o] { run_montecarlo(*o); });
});

}  // namespace
}  // namespace robcal::cli
