#include "robcal/sim/campaign.hpp"

#include "robcal/validate/base_fit.hpp"

namespace robcal {

std::vector<PlannedConfiguration> plan_calibration(const TrueRobot& truth,
                                                   const VirtualInstrument& instrument,
                                                   const RobotModel& model, const Tool& tool,
                                                   CalibrationLevel level, int count,
                                                   int candidates, std::mt19937_64& rng) {
  // The planner knows the nominal robot and roughly where it stands in the instrument's frame
  // (the truth's placement); it never sees the truth's errors.
  const TrueRobot cell = planning_cell(model, tool, truth.robot.params.head<kBaseParamCount>());
  PlanSettings settings;
  settings.level = level;
  settings.count = count;
  settings.candidates = candidates;
  return plan_calibration(cell, instrument, settings, rng).configurations;
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
  // Fitted on the calibration readings, as the published tables do: fitted on the validation
  // readings the nominal row would be tuned to the very data it is scored on.
  out.nominal = fit_base(CalibratedRobot::nominal(model, tool), out.calibration.measurements);
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

}  // namespace robcal
