#include "robcal/hexapod/end_to_end.hpp"

#include "robcal/core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "robcal/core/units.hpp"
#include "robcal/hexapod/gauge.hpp"
#include "robcal/hexapod/leg_fit.hpp"
#include "robcal/hexapod/measurement.hpp"
#include "robcal/hexapod/plan_file.hpp"
#include "robcal/identify/identification.hpp"
#include "robcal/kinematics/numeric_ik.hpp"
#include "robcal/measure/instrument.hpp"
#include "robcal/sim/simulator.hpp"
#include "robcal/validate/pairwise_distance.hpp"

namespace robcal::hexapod {
namespace {

/// Errors of a model whose robot frame sits at `robot_T_world` (relative model).
ValidationFigures validate(const RobotModel& model, const PointMass& payload,
                           const ParameterVector& params, const Eigen::Vector3d& target_flange,
                           const Pose<double>& robot_T_world, const TrackerValidation& set,
                           int threads) {
  const Pose<double> world_T_robot = robot_T_world.inverse();
  Eigen::Matrix3Xd predicted(3, static_cast<int>(set.joints.size()));
  std::vector<double> errors(set.joints.size());
  for (size_t k = 0; k < set.joints.size(); ++k) {
    predicted.col(k) =
        world_T_robot * (flange_pose(model, payload, params, set.joints[k]) * target_flange);
    errors[k] = (predicted.col(k) - set.measured.col(k)).norm();
  }
  return {error_statistics(errors),
          pairwise_distance_errors(set.measured, predicted, threads).stats};
}

/// The full model with its base: the world frame from the base cups is where the uncalibrated
/// robot put them, off by its own error at those points (≈ 1 mm); holding the base (the relative
/// model) would force the link parameters to absorb that rigid offset, which they cannot. The base
/// parameters identify it, as the leg fit's free base cups do.
IdentifyOptions pose_fit_options(bool relative) {
  IdentifyOptions options;
  options.level = CalibrationLevel::Full;
  if (relative) options.fix = {"base.*"};
  options.prediction_configurations = 100;
  return options;
}

CalibrationStage stage_of(const IdentificationResult& r, int configurations) {
  CalibrationStage s;
  s.configurations = configurations;
  s.rms_mm = r.rms_mm;
  s.iterations = r.status.iterations;
  s.converged = r.status.converged;
  return s;
}

}  // namespace

EndToEndOptions end_to_end_options(const HexapodPlanRequest& plan, EndToEndOptions settings) {
  EndToEndOptions o = std::move(settings);
  o.cell.design = plan.geometry;
  o.cell.placement = placement_pose(plan.placement, plan.tilt_deg);
  o.cell.tool_offset_mm = plan.tool_offset_mm;
  o.cell.ball_offset_mm = plan.ball_offset_mm;
  o.cell.table_z_mm = plan.table_z_mm;
  o.cell.sigma_mm = plan.gauge.sigma_mm;
  o.cell.range_mm = plan.gauge.range_mm;
  o.angle_deg = plan.angle_deg;
  o.distance_mm = plan.distance_mm;
  o.cups = plan.cups;
  return o;
}

EndToEndReport run_end_to_end(const RobotModel& model, const EndToEndOptions& o,
                              std::mt19937_64& rng) {
  if (o.validation_configurations < 2)
    throw InputError({"", 0, 0, "--validation"}, "expected at least 2 configurations");
  if (o.threads < 1) throw InputError({"", 0, 0, "--threads"}, "expected at least 1 thread");
  check_gauge({o.cell.range_mm, o.cell.sigma_mm}, "--gauge-range-mm", "--gauge-sigma-mm");
  check_geometry(o.cell.design);  // as `hexapod plan` refuses it (a bad fourth cup named)
  EndToEndReport rep;
  rep.robot = model.name;
  // The true robot: random errors, levelled on its table (the relative model keeps gravity along
  // the base z), carrying the published end-effector (docs/method/03-error-model.md §3: 2.6 kg at
  // (50, 25, 100) mm).
  const PointMass payload{2.6, Eigen::Vector3d(50, 25, 100)};
  const TrueRobot truth = levelled_random_truth(model, payload, o.errors, rng);
  const SimulatedHexapodCell cell = set_up_simulated_cell(truth, model, o.cell, rng);
  rep.world_frame_rms_mm = cell.world.rms_mm;
  {
    // The fitted world frame against the true base fixture frame, both in the true robot's frame:
    // world_A_1 = Trans(x, y, z) · Rx Ry Rz(γ) · (the nominal Trans(0, 0, d1) Rz(θ1)) for a
    // levelled base (α = β = 0), so the true robot frame sits at Trans(x, y, z) · Rz(γ).
    const ParameterVector& t = truth.robot.params;
    Pose<double> sim_T_robot;
    sim_T_robot.R = Eigen::AngleAxisd(t[5], Eigen::Vector3d::UnitZ()).toRotationMatrix();
    sim_T_robot.p = Eigen::Vector3d(t[0], t[1], t[2]);
    const Pose<double> robot_T_fixture = sim_T_robot.inverse() * cell.world_T_sim.inverse();
    const Pose<double> error = robot_T_fixture.inverse() * cell.world.robot_T_fixture;
    rep.world_frame_error_mm = error.p.norm();
    rep.world_frame_error_deg = rad2deg(Eigen::AngleAxisd(error.R).angle());
  }

  // Plan with the measured fixtures (a fourth tool cup by its measured distances, its legs
  // read in every pose that has one, as `robcal hexapod plan` plans them).
  const HexapodGeometry measured{cell.base_sides, cell.tool_sides, o.cell.design.leg_mm,
                                 cell.tool_cup4_mm, cell.base_cup4_mm};
  const FixtureDistances tool_fixture = measured.tool_fixture();
  const FixtureDistances base_fixture = measured.base_fixture();
  const PoseScreening screening = plannable_poses(measured, o.cell.range_mm, o.angle_deg,
                                                  o.distance_mm, o.cups, &rep.poses_enumerated);
  const std::vector<HexapodPose>& kept = screening.kept;
  const PlanSummary plan =
      plan_poses(model, cell.cell, fixture_cups(cell.base_sides, "base fixture"), kept,
                 cell.base_cup4_mm ? std::optional(base_cup_positions(measured)[3]) : std::nullopt);
  rep.poses_refused = static_cast<int>(screening.refused.size());
  rep.poses_kept = static_cast<int>(kept.size());
  rep.poses_measurable = plan.measurable_poses;
  rep.configurations_planned = plan.configurations;

  // First pass: every planned configuration; a leg out of the ballbar's range → retry later.
  std::vector<LegReadings> readings;
  std::vector<std::pair<const PosePlan*, PoseConfiguration>> retry;
  for (const PosePlan& p : plan.poses)
    for (const PoseConfiguration& c : p.configurations) {
      const std::string name = fmt::format("{}-{}", p.pose.label, c.config.label());
      if (auto r = simulate_pose_readings(cell, p.pose, name, c.joints, rng))
        readings.push_back(std::move(*r));
      else
        retry.emplace_back(&p, c);
    }
  rep.measured_first = static_cast<int>(readings.size());
  rep.retried = static_cast<int>(retry.size());
  const Tool tool = hexapod_tool(payload, cell.cell.flange_T_tool, cell.tool_sides);
  const auto measurements = [&] {
    return pose_measurements(base_fixture, tool_fixture, readings, cell.world.robot_T_fixture,
                             "simulated hexapod");
  };
  const IdentificationResult preliminary =
      calibrate(model, tool, measurements(), pose_fit_options(o.relative_pose_fit));
  rep.preliminary = stage_of(preliminary, rep.measured_first);

  // Re-plan the rest: the joints that put the flange where the pose needs it on the
  // preliminary model (Newton from the nominal solution), then measure again.
  for (const auto& [p, c] : retry) {
    const NumericIkResult ik =
        numeric_ik(model, payload, preliminary.robot.params, p->robot_T_flange, c.joints);
    if (ik.status != NumericIkStatus::Converged || !ik.within_limits) continue;
    if (auto r = simulate_pose_readings(
            cell, p->pose, fmt::format("{}-{}", p->pose.label, c.config.label()), ik.joints, rng)) {
      readings.push_back(std::move(*r));
      ++rep.measured_after_replan;
    }
  }
  for (const LegReadings& r : readings) {
    rep.legs_read += static_cast<int>(kDesignLegs.size() + r.extra_legs.size());
    for (const MeasuredLeg& leg : r.extra_legs) {
      rep.legs_read_fourth_cup += leg.tool == 3 ? 1 : 0;
      rep.legs_read_base_cup4 += leg.base == 3 ? 1 : 0;
    }
  }
  const IdentificationResult final_fit =
      calibrate(model, tool, measurements(), pose_fit_options(o.relative_pose_fit));
  rep.final_pose_fit = stage_of(final_fit, static_cast<int>(readings.size()));

  // Validation: random configurations in the published joint box, a laser tracker reading the
  // tool fixture's centroid, registered on the base cups.
  const TrackerValidation validation = simulate_tracker_validation(
      cell, centroid(cell.tool_cups_flange), o.validation_configurations, o.tracker_sigma_mm, rng);
  rep.validation_configurations = o.validation_configurations;
  const Eigen::Vector3d target =
      cell.cell.flange_T_tool * centroid(fixture_cups(cell.tool_sides, "tool"));
  const Pose<double>& robot_T_world = cell.world.robot_T_fixture;
  rep.nominal =
      validate(model, payload, model.nominal(), target, robot_T_world, validation, o.threads);
  rep.preliminary.validation = validate(model, payload, preliminary.robot.params, target,
                                        robot_T_world, validation, o.threads);
  rep.final_pose_fit.validation = validate(model, payload, final_fit.robot.params, target,
                                           robot_T_world, validation, o.threads);

  if (o.leg_fit) {
    LegFitOptions leg_options;
    for (size_t i = 0; i < final_fit.free.size(); ++i)
      if (final_fit.free[i] >= kBaseParamCount && final_fit.free[i] < kParameterCount)
        leg_options.free_parameters.push_back(final_fit.free[i]);
    const LegFitResult legs =
        fit_from_legs(model, payload, base_fixture, tool_fixture, readings, model.nominal(),
                      cell.world.robot_T_fixture, cell.cell.flange_T_tool, leg_options);
    rep.leg_fit.configurations = static_cast<int>(readings.size());
    rep.leg_fit.rms_mm = legs.rms_mm;
    rep.leg_fit.iterations = legs.iterations;
    rep.leg_fit.converged = legs.converged;
    rep.leg_fit_offset_mm = legs.length_offset_mm;
    // Its world frame is the one of its own base cups.
    rep.leg_fit.validation =
        validate(model, payload, legs.params, centroid(legs.tool_cups_flange),
                 frame_from_cups(legs.base_cups_robot.front()), validation, o.threads);
    if (const auto& b4 = legs.base_cup4_robot.front()) {
      const Cups<double>& fitted = legs.base_cups_robot.front();
      const Eigen::Vector3d& truth4 = cell.base_cup4_sim.value();
      rep.leg_fit_base_cup4_error_mm =
          (frame_from_cups(fitted).inverse() * *b4 - cell.world_T_sim * truth4).norm();
      double worst = 0;
      for (int i = 0; i < 3; ++i)
        worst = std::max(
            worst, std::abs((*b4 - fitted[i]).norm() - (truth4 - cell.base_cups_sim[i]).norm()));
      rep.leg_fit_base_cup4_distance_error_mm = worst;
    }
  }
  return rep;
}

}  // namespace robcal::hexapod
