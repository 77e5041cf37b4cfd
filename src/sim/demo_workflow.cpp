#include "robcal/sim/demo_workflow.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "robcal/identify/calibration_output.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/report/report_workflow.hpp"
#include "robcal/sim/simulation_files.hpp"

namespace robcal {
namespace {

namespace fs = std::filesystem;

nlohmann::json summary(const ModelErrors& errors) {
  ReportData data;
  data.models = {errors};
  return report_json(data)["models"][0]["summary"];
}

void write_demo_files(const DemoResult& result, const Tool& tool, const TrueRobot& truth,
                      const VirtualInstrument& tracker) {
  const CampaignResult& campaign = result.campaign;
  const uint64_t seed = result.request.seed;
  const fs::path out(result.request.out);
  write_simulation(out / "calibration", "measurements", campaign.calibration, tool, tracker, truth,
                   "abb-irb120",
                   fmt::format("robcal demo: calibration measurements, seed {}", seed));
  write_simulation(out / "validation", "measurements", campaign.validation, tool, tracker, truth,
                   "abb-irb120",
                   fmt::format("robcal demo: validation measurements, seed {}", seed + 2));
  write_file_atomically(out / "plan.csv", write_configurations_csv(campaign.plan, tool));
  // The nominal robot with its base fitted on the calibration data: the report's "before".
  write_file_atomically(out / "models" / "nominal.yaml",
                        calibrated_robot_to_yaml(campaign.nominal));
  for (const LevelOutcome& level : campaign.levels)
    write_file_atomically(out / "models" / (std::string(level_name(level.level)) + ".yaml"),
                          calibrated_robot_to_yaml(level.fit.robot, statistics_writer(level.fit)));
  // The report from the files just written, as `robcal report` builds it: provenance (every
  // input's SHA-256, instrument, seed) and the classes by region of the calibration set.
  ReportRequest report;
  report.title = "robcal demo: ABB IRB 120, simulated laser tracker";
  report.before = (out / "models" / "nominal.yaml").string();
  for (size_t k = 0; k + 1 < campaign.levels.size(); ++k)
    report.between.push_back(
        (out / "models" / (std::string(level_name(campaign.levels[k].level)) + ".yaml")).string());
  report.model =
      (out / "models" / (std::string(level_name(campaign.levels.back().level)) + ".yaml")).string();
  report.measurements = {(out / "validation" / "measurements.csv").string()};
  report.calibration = (out / "calibration" / "measurements.csv").string();
  report.instrument = (out / "validation" / "instrument.yaml").string();
  report.seed = seed;
  ReportData data = build_report(report).data;
  data.models.front().label = "nominal (base fitted on the calibration data)";
  data.sources.push_back(fmt::format("seed {}", seed));
  data.sources.push_back(fmt::format("{} calibration configurations (D-optimal of {})",
                                     campaign.calibration.measurements.size(), result.candidates));
  data.notes.push_back(
      "Simulated: the true robot is the identified IRB 120 published by Nubiola & "
      "Bonev (docs/method/11-published-results.md); tracker noise 0.022 mm per axis. Errors are "
      "against the simulated validation readings, which carry that noise too.");
  write_report(report_json(data), out / "report.html");
}

}  // namespace

DemoResult run_demo(const DemoRequest& request) {
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  const TrueRobot truth = published_irb120_truth(model, tool);
  const VirtualInstrument tracker = standard_instrument(InstrumentKind::LaserTracker, truth);
  // Fail before any work when the report cannot be written.
  if (!request.out.empty()) {
    refuse_non_folder(request.out);
    (void)load_chartjs();
  }
  CampaignOptions options;
  options.seed = request.seed;
  options.calibration_count = request.count;
  options.validation_count = request.validation;
  DemoResult result{request, options.candidates,
                    run_campaign(truth, tracker, model, tool, options)};
  if (!request.out.empty()) write_demo_files(result, tool, truth, tracker);
  return result;
}

nlohmann::json demo_json(const DemoResult& result) {
  const CampaignResult& campaign = result.campaign;
  nlohmann::json j;
  j["seed"] = result.request.seed;
  j["calibration_rows"] = campaign.calibration.measurements.size();
  j["validation_rows"] = campaign.validation.measurements.size();
  j["candidates"] = result.candidates;
  j["vs_measurements"]["nominal"] = summary(campaign.nominal_vs_measurements);
  j["vs_truth"]["nominal"] = summary(campaign.nominal_vs_truth);
  for (const LevelOutcome& level : campaign.levels) {
    j["vs_measurements"][level_name(level.level)] = summary(level.vs_measurements);
    j["vs_truth"][level_name(level.level)] = summary(level.vs_truth);
    j["identified"][level_name(level.level)] = level.fit.identified_count;
  }
  j["out"] = result.request.out;
  return j;
}

}  // namespace robcal
