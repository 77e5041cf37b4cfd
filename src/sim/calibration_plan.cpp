#include "robcal/sim/calibration_plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <memory>

#include "robcal/core/error.hpp"

namespace robcal {

TrueRobot planning_cell(const RobotModel& model, const Tool& tool,
                        const Eigen::Matrix<double, 6, 1>& base) {
  TrueRobot cell;
  cell.robot = CalibratedRobot::nominal(model, tool);
  cell.robot.params.head<kBaseParamCount>() = base;
  cell.robot.base_fitted = true;
  cell.origin = "nominal robot placed in the cell";
  return cell;
}

VirtualInstrument planning_instrument(const VirtualInstrument& instrument,
                                      const PlanSettings& settings) {
  VirtualInstrument narrowed = instrument;
  narrowed.tracker.cone_half_angle_deg -= settings.visibility_margin_deg;
  narrowed.tracker.min_range_mm += settings.visibility_margin_mm;
  narrowed.tracker.max_range_mm -= settings.visibility_margin_mm;
  narrowed.cmm.facing_limit_deg -= settings.visibility_margin_deg;
  narrowed.cmm.min_range_mm += settings.visibility_margin_mm;
  narrowed.cmm.max_range_mm -= settings.visibility_margin_mm;
  return narrowed;
}

MeasurementKind measurement_kind(InstrumentKind kind) {
  switch (kind) {
    case InstrumentKind::LaserTracker:
      return MeasurementKind::Points;
    case InstrumentKind::OpticalCmm:
      return MeasurementKind::Poses;
    case InstrumentKind::Ballbar:
      return MeasurementKind::Distances;
  }
  return MeasurementKind::Points;
}

double instrument_sigma(const VirtualInstrument& instrument) {
  switch (instrument.kind) {
    case InstrumentKind::LaserTracker:
      return instrument.tracker.sigma_mm.maxCoeff();
    case InstrumentKind::OpticalCmm:
      return instrument.cmm.sigma_mm;
    case InstrumentKind::Ballbar:
      return instrument.ballbar.sigma_mm;
  }
  return 0;
}

CandidateSet instrument_candidates(const TrueRobot& cell, const VirtualInstrument& instrument,
                                   const PlanSettings& settings, std::mt19937_64& rng) {
  const RobotModel& model = cell.robot.model;
  const Tool& tool = cell.robot.tool;
  if (instrument.kind == InstrumentKind::Ballbar) {
    // Ballbar configurations must put the target on the bar's sphere: the simulator's
    // generator moves each draw there, exactly as the measuring program will.
    RandomConfigurationOptions options;
    options.box = constrained_joint_box(model, settings.constraints);
    options.min_target_height_mm = settings.floor_mm;
    CandidateSet out;
    try {
      for (const PlannedConfiguration& c :
           random_configurations(cell, instrument, settings.candidates, rng, options))
        out.candidates.push_back({c.joints, c.target});
    } catch (const InputError& e) {
      throw InputError({"", 0, 0, "--instrument"}, e.what());
    }
    out.draws = static_cast<long>(out.candidates.size());
    return out;
  }
  const VirtualInstrument seen = planning_instrument(instrument, settings);
  CandidateOptions options;
  options.constraints = settings.constraints;
  options.floor_z_mm = settings.floor_mm;
  options.count = settings.candidates;
  options.instrument_frame_params = cell.robot.params;
  options.kind = measurement_kind(instrument.kind);
  if (instrument.kind == InstrumentKind::LaserTracker) {
    // Asked once per target of the same flange pose (generate_candidates draws sequentially):
    // the visible set is computed once per pose.
    struct SeenFrom {
      Pose<double> world_T_flange;
      std::vector<int> targets;
      bool valid = false;
    };
    auto last = std::make_shared<SeenFrom>();
    options.visible = [&seen, &tool, last](const Pose<double>& world_T_flange, int target) {
      if (!last->valid || last->world_T_flange.p != world_T_flange.p ||
          last->world_T_flange.R != world_T_flange.R) {
        last->targets = visible_targets(seen.tracker, world_T_flange, tool);
        last->world_T_flange = world_T_flange;
        last->valid = true;
      }
      return std::find(last->targets.begin(), last->targets.end(), target) != last->targets.end();
    };
  } else {
    options.visible = [&](const Pose<double>& world_T_flange, int) {
      return cmm_sees_tool(seen.cmm, world_T_flange, tool);
    };
  }
  return generate_candidates(model, tool, options, rng);
}

DesignSettings plan_design_settings(const TrueRobot& cell, const VirtualInstrument& instrument,
                                    CalibrationLevel level) {
  DesignSettings settings;
  settings.kind = measurement_kind(instrument.kind);
  settings.parameters = level_parameters(level);
  settings.linearisation = cell.robot.params;
  settings.ballbar_centre_mm = instrument.ballbar.centre_mm;
  return settings;
}

std::vector<PlannedConfiguration> planned_configurations(const std::vector<Candidate>& candidates,
                                                         const std::vector<int>& chosen) {
  // Grouped by payload, in selection order within each, so that the operator changes the
  // payload as few times as there are payloads.
  std::vector<int> order = chosen;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return candidates[static_cast<size_t>(a)].payload < candidates[static_cast<size_t>(b)].payload;
  });
  std::vector<PlannedConfiguration> plan;
  for (size_t k = 0; k < order.size(); ++k) {
    const Candidate& c = candidates[static_cast<size_t>(order[k])];
    plan.push_back({fmt::format("C{}", k + 1), c.joints, c.target, c.approach, c.payload});
  }
  return plan;
}

CalibrationPlan plan_calibration(const TrueRobot& cell, const VirtualInstrument& instrument,
                                 const PlanSettings& settings, std::mt19937_64& rng) {
  CalibrationPlan plan;
  plan.candidates = instrument_candidates(cell, instrument, settings, rng);
  plan.design = build_design_matrix(cell.robot.model, cell.robot.tool, plan.candidates.candidates,
                                    plan_design_settings(cell, instrument, settings.level));
  plan.selection = select_d_optimal(plan.design, settings.count);
  plan.configurations = planned_configurations(plan.candidates.candidates, plan.selection.chosen);
  return plan;
}

}  // namespace robcal
