#include "robcal/sim/campaign.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "robcal/design/candidates.hpp"
#include "robcal/design/design_matrix.hpp"
#include "robcal/design/selection.hpp"
#include "robcal/validate/base_fit.hpp"

namespace robcal {

std::vector<PlannedConfiguration> plan_calibration(const TrueRobot& truth,
                                                   const VirtualInstrument& instrument,
                                                   const RobotModel& model, const Tool& tool,
                                                   CalibrationLevel level, int count,
                                                   int candidates, std::mt19937_64& rng) {
  // The planner knows the nominal robot and roughly where it stands in the instrument's frame
  // (the truth's placement); it never sees the truth's errors.
  ParameterVector placed = model.nominal();
  placed.head<kBaseParamCount>() = truth.robot.params.head<kBaseParamCount>();
  std::vector<Candidate> pool;
  MeasurementKind kind = MeasurementKind::Distances;
  if (instrument.kind == InstrumentKind::Ballbar) {
    // Ballbar configurations must put the cup on the bar's sphere: the simulator's generator
    // moves each draw there with the nominal geometry, as the measuring program does.
    TrueRobot cell;
    cell.robot = CalibratedRobot::nominal(model, tool);
    cell.robot.params = placed;
    RandomConfigurationOptions options;
    options.box = published_joint_box(model);
    for (const PlannedConfiguration& c :
         random_configurations(cell, instrument, candidates, rng, options))
      pool.push_back({c.joints, c.target});
  } else {
    CandidateOptions options;
    options.count = candidates;
    options.instrument_frame_params = placed;
    if (instrument.kind == InstrumentKind::LaserTracker) {
      kind = options.kind = MeasurementKind::Points;
      options.visible = [&](const Pose<double>& world_T_flange, int target) {
        const std::vector<int> visible = visible_targets(instrument.tracker, world_T_flange, tool);
        return std::find(visible.begin(), visible.end(), target) != visible.end();
      };
    } else {
      kind = options.kind = MeasurementKind::Poses;
      options.visible = [&](const Pose<double>& world_T_flange, int) {
        return cmm_sees_tool(instrument.cmm, world_T_flange, tool);
      };
    }
    pool = generate_candidates(model, tool, options, rng).candidates;
  }
  DesignSettings settings;
  settings.kind = kind;
  settings.parameters = level_parameters(level);
  settings.linearisation = placed;
  settings.ballbar_centre_mm = instrument.ballbar.centre_mm;
  const DesignMatrix design = build_design_matrix(model, tool, pool, settings);
  const Selection selection = select_d_optimal(design, count);
  std::vector<PlannedConfiguration> plan;
  for (size_t k = 0; k < selection.chosen.size(); ++k) {
    const Candidate& c = pool[static_cast<size_t>(selection.chosen[k])];
    plan.push_back({fmt::format("C{}", k + 1), c.joints, c.target});
  }
  return plan;
}

CampaignResult run_campaign(const TrueRobot& truth, const VirtualInstrument& instrument,
                            const RobotModel& model, const Tool& tool,
                            const CampaignOptions& options) {
  CampaignResult out;
  std::mt19937_64 plan_rng(options.seed), calibration_noise(options.seed + 1),
      validation_rng(options.seed + 2), validation_noise(options.seed + 3);
  RandomConfigurationOptions random_options;
  random_options.box = published_joint_box(model);
  if (options.optimal_plan) {
    out.plan = plan_calibration(truth, instrument, model, tool, options.levels.back(),
                                options.calibration_count, options.candidates, plan_rng);
  } else {
    random_options.name_prefix = "C";
    out.plan = random_configurations(truth, instrument, options.calibration_count, plan_rng,
                                     random_options);
  }
  out.calibration =
      simulate_measurements(truth, instrument, out.plan, calibration_noise, options.simulation);

  random_options.name_prefix = "V";
  out.validation_configs = random_configurations(truth, instrument, options.validation_count,
                                                 validation_rng, random_options);
  out.validation = simulate_measurements(truth, instrument, out.validation_configs,
                                         validation_noise, options.simulation);
  VirtualInstrument exact = instrument;
  exact.tracker.sigma_mm.setZero();
  exact.cmm.sigma_mm = 0;
  exact.cmm.sigma_orientation_deg = 0;
  exact.ballbar.sigma_mm = 0;
  std::mt19937_64 unused(0);
  out.validation_truth =
      simulate_measurements(truth, exact, out.validation_configs, unused, options.simulation);

  const std::vector<MeasurementSet> measured{out.validation.measurements};
  const std::vector<MeasurementSet> exact_rows{out.validation_truth.measurements};
  out.nominal = fit_base(CalibratedRobot::nominal(model, tool), out.validation.measurements);
  out.nominal_vs_measurements = model_errors("nominal", out.nominal, measured);
  out.nominal_vs_truth = model_errors("nominal", out.nominal, exact_rows);
  for (const CalibrationLevel level : options.levels) {
    IdentifyOptions identify;
    identify.level = level;
    identify.seed = options.seed;
    LevelOutcome outcome;
    outcome.level = level;
    outcome.fit = calibrate(model, tool, out.calibration.measurements, identify);
    outcome.vs_measurements = model_errors(level_name(level), outcome.fit.robot, measured);
    outcome.vs_truth = model_errors(level_name(level), outcome.fit.robot, exact_rows);
    out.levels.push_back(std::move(outcome));
  }
  return out;
}

ReportData campaign_report(const CampaignResult& campaign, const std::string& title,
                           const std::string& robot) {
  ReportData data;
  data.title = title;
  data.robot = robot;
  data.models.push_back(campaign.nominal_vs_measurements);
  data.models.back().label = "nominal (rigid base fit)";
  for (const LevelOutcome& level : campaign.levels) data.models.push_back(level.vs_measurements);
  data.distance_to_calibration_mm = distance_to_calibration({campaign.validation.measurements},
                                                            campaign.calibration.measurements);
  if (!campaign.levels.empty()) {
    const IdentificationResult& fit = campaign.levels.back().fit;
    data.parameters = report_parameters(fit.robot);
    data.diagnostics = yaml_to_json(statistics_yaml(fit));
  }
  return data;
}

}  // namespace robcal
