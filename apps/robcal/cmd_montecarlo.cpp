/// `robcal montecarlo`: the spread of the calibrated robot's accuracy over repeated simulated
/// calibrations, against the Cramér–Rao prediction.

#include <fmt/format.h>

#include <chrono>
#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/sim/monte_carlo_study.hpp"

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

void run_montecarlo(const McOptions& o) {
  const MonteCarloStudyRequest request =
      monte_carlo_study_request(o.mc, o.noise_mm, o.level, o.plan, o.validation_model);
  const auto started = std::chrono::steady_clock::now();
  const MonteCarloStudy study = run_monte_carlo_study(request);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const MonteCarloOptions& mc = request.options;
  const MonteCarloResult& result = study.result;
  if (o.json) {
    nlohmann::json j = monte_carlo_study_json(study);
    j["seconds"] = seconds;
    print_json(j);
    return;
  }
  fmt::print(
      "Monte Carlo: {} calibrations of the published IRB 120 ({} poses, {} parameters "
      "identified, σ {} mm/axis), {} validation configurations each, seed {}\n",
      mc.runs, study.poses, study.identified, o.noise_mm, mc.validation, mc.seed);
  fmt::print("  validation: {}\n",
             mc.validation_model == ValidationModel::Exact
                 ? "exact (forward kinematics of each calibrated model against the truth)"
                 : "first-order (J_v·δp + model-error bias at the truth; exact to second order in "
                   "the parameter error; --validation-model exact for full kinematics)");
  fmt::print("  error against the truth      observed      Cramér–Rao prediction\n");
  fmt::print("  RMS                          {:.5f} mm    {:.5f} mm\n", result.observed_rms_mm,
             study.predicted.rms_mm);
  fmt::print("  mean                         {:.5f} mm    {:.5f} mm\n", result.observed_mean_mm,
             study.predicted.mean_mm);
  fmt::print("  per-run mean, 5–95 %         {:.5f} – {:.5f} mm\n", study.run_mean_p05_mm,
             study.run_mean_p95_mm);
  fmt::print("  ratio observed/predicted RMS {:.4f} (1.00 for an efficient estimator)\n",
             result.ratio);
  if (result.failed > 0) fmt::print("  {} runs did not converge (left out)\n", result.failed);
  fmt::print("  {:.3f} s on {} thread(s)\n", seconds, mc.threads);
}

const bool montecarlo_registered = register_command(95, [](CLI::App& app) {
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
