#include "robcal/sim/monte_carlo_study.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "robcal/core/error.hpp"
#include "robcal/identify/fit_error_json.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal {

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const double position = p * static_cast<double>(values.size() - 1);
  const size_t below = static_cast<size_t>(position);
  const size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (position - static_cast<double>(below)) * (values[above] - values[below]);
}

MonteCarloStudy run_monte_carlo_study(const MonteCarloStudyRequest& request) {
  if (!(request.noise_mm > 0)) throw InputError({"", 0, 0, "--noise-mm"}, "must be positive");
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  const TrueRobot truth = published_irb120_truth(model, tool);
  const VirtualInstrument tracker =
      standard_instrument(InstrumentKind::LaserTracker, truth, request.noise_mm);
  const MonteCarloSetup setup = prepare_monte_carlo(truth, tracker, model, tool, request.options);
  MonteCarloStudy study;
  study.request = request;
  study.poses = static_cast<int>(setup.template_set.size());
  study.identified = static_cast<int>(setup.identification.free.size());
  study.predicted = setup.predicted;
  study.result = run_monte_carlo(setup, request.options);
  std::vector<double> means, maxima;
  for (const MonteCarloRun& run : study.result.runs)
    if (run.converged) {
      means.push_back(run.mean_mm);
      maxima.push_back(run.max_mm);
    }
  study.run_mean_p05_mm = percentile(means, 0.05);
  study.run_mean_p95_mm = percentile(means, 0.95);
  study.run_max_p95_mm = percentile(maxima, 0.95);
  return study;
}

MonteCarloStudyRequest monte_carlo_study_request(MonteCarloOptions options, double noise_mm,
                                                 const std::string& level, const std::string& plan,
                                                 const std::string& validation_model) {
  if (plan != "optimal" && plan != "random")
    throw InputError({"", 0, 0, "--plan"}, "expected 'optimal' or 'random'");
  options.level = parse_calibration_level(level);
  options.optimal_plan = plan == "optimal";
  options.validation_model = parse_validation_model(validation_model);
  return {options, noise_mm};
}

nlohmann::json monte_carlo_study_json(const MonteCarloStudy& s) {
  const MonteCarloOptions& o = s.request.options;
  nlohmann::json j;
  j["seed"] = o.seed;
  j["runs"] = o.runs;
  j["failed"] = s.result.failed;
  j["poses"] = s.poses;
  j["validation"] = o.validation;
  j["validation_model"] = validation_model_name(o.validation_model);
  j["identified_parameters"] = s.identified;
  j["noise_mm"] = s.request.noise_mm;
  j["threads"] = o.threads;
  j["observed"] = {{"rms_mm", s.result.observed_rms_mm},
                   {"mean_mm", s.result.observed_mean_mm},
                   {"run_mean_p05_mm", s.run_mean_p05_mm},
                   {"run_mean_p95_mm", s.run_mean_p95_mm},
                   {"run_max_p95_mm", s.run_max_p95_mm}};
  j["predicted"] = mean_rms_max_json(s.predicted.mean_mm, s.predicted.rms_mm, s.predicted.max_mm);
  j["ratio"] = s.result.ratio;
  return j;
}

}  // namespace robcal
