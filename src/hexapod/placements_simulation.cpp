#include "robcal/hexapod/placements_simulation.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/hexapod/leg_fit.hpp"
#include "robcal/identify/accuracy_prediction.hpp"

namespace robcal::hexapod {

PlacementsSimulation simulate_placements(const RobotModel& model, const TrueRobot& truth,
                                         const PointMass& payload,
                                         const std::vector<SimulatedPlacement>& placements,
                                         const PlacementsSimulationOptions& o,
                                         std::mt19937_64& rng) {
  if (placements.empty()) throw InputError({"", 0, 0, "placements"}, "expected a placement");
  if (o.validation_configurations < 1)
    throw InputError({"", 0, 0, "validation"}, "expected at least one configuration");
  PlacementsSimulation out;
  std::vector<SimulatedHexapodCell> cells;
  std::vector<LegPlacement> legs;
  for (size_t p = 0; p < placements.size(); ++p) {
    const HexapodPlan& plan = placements[p].plan;
    if (!plan.cell || !plan.session.flange_T_tool)
      throw InputError({fmt::format("plan {}", p + 1), 0, 0, "geometry"},
                       "the simulator needs the cell of a plan written by `robcal hexapod plan`");
    HexapodCellOptions cell;
    cell.design = plan.cell->geometry;
    cell.fixture_tolerance_mm = o.fixture_tolerance_mm;
    cell.placement = placement_pose(plan.cell->placement, plan.cell->tilt_deg);
    cell.tool_offset_mm = plan.cell->tool_offset_mm;
    cell.ball_offset_mm = plan.cell->ball_offset_mm;
    cell.table_z_mm = plan.cell->table_z_mm;
    cell.sigma_mm = o.sigma_mm;
    cell.range_mm = plan.session.range_mm;
    SimulatedHexapodCell c = set_up_simulated_cell(truth, model, cell, rng);
    if (!cells.empty()) {  // one tool fixture throughout: its cups and measured distances
      c.tool_cups_flange = cells.front().tool_cups_flange;
      c.tool_sides = cells.front().tool_sides;
      c.tool_cup4_flange = cells.front().tool_cup4_flange;
      c.tool_cup4_mm = cells.front().tool_cup4_mm;
    }
    LegPlacement placement{c.base_fixture(), {}, c.world.robot_T_fixture};
    for (int k : placements[p].chosen) {
      const SessionConfiguration& config = plan.session.configurations.at(k);
      const std::optional<LegDesign> design = design_of_legs(config.legs);
      if (!design || config.joints_deg.size() != kJointCount)
        throw InputError(
            {fmt::format("plan {}", p + 1), 0, 0, fmt::format("configurations[{}]", k)},
            "expected the joints and the six legs of design 1^12 2^123 3^1");
      Vector6d q;
      for (int j = 0; j < kJointCount; ++j) q[j] = deg2rad(config.joints_deg[j]);
      LegLengths<double> lengths{};
      bool readable = true;
      for (int i = 0; i < 6 && readable; ++i) {
        const std::optional<double> r = simulate_leg(c, config.legs[i], q, rng);
        readable = r.has_value();
        if (r) lengths[i] = *r;
      }
      // The legs to or from a fourth cup, after the design's six.
      std::vector<MeasuredLeg> extra;
      for (size_t i = kDesignLegs.size(); i < config.legs.size() && readable; ++i) {
        const std::optional<double> r = simulate_leg(c, config.legs[i], q, rng);
        readable = r.has_value();
        if (r) extra.push_back({config.legs[i].base, config.legs[i].tool, *r});
      }
      if (!readable) {
        ++out.out_of_range;
        continue;
      }
      out.legs += static_cast<int>(kDesignLegs.size() + extra.size());
      placement.readings.push_back(
          {fmt::format("{}-{}", p + 1, k), q, *design, config.mode, lengths, std::move(extra)});
    }
    out.configurations += static_cast<int>(placement.readings.size());
    // A placement with nothing measured brings only its unknown cups: left out of the fit.
    if (p == 0 && placement.readings.empty())
      throw InputError({"plan 1", 0, 0, "configurations"},
                       "expected configurations measured at the first placement");
    if (!placement.readings.empty()) legs.push_back(std::move(placement));
    cells.push_back(std::move(c));
  }

  LegFitOptions fit_options;
  for (int i :
       identified_model_parameters(model, Tool{}, MeasurementKind::Poses, o.level, o.identify))
    if (i >= kBaseParamCount) fit_options.free_parameters.push_back(i);
  const SimulatedHexapodCell& first = cells.front();
  const LegFitResult fit =
      fit_from_legs(model, payload, FixtureDistances{first.tool_sides, first.tool_cup4_mm}, legs,
                    model.nominal(), first.cell.flange_T_tool, fit_options);
  out.fit_rms_mm = fit.rms_mm;
  out.converged = fit.converged;

  // The whole workspace: random configurations within the joint limits; the tool fixture's
  // centroid, truth against model, in the first placement's base fixture frame.
  Vector6d lower, upper;
  for (int j = 0; j < kJointCount; ++j) {
    lower[j] = model.limits[j].lower;
    upper[j] = model.limits[j].upper;
  }
  std::mt19937_64 validation_rng(o.validation_seed);
  const std::vector<Vector6d> joints =
      sample_configurations(lower, upper, o.validation_configurations, validation_rng);
  const Eigen::Vector3d true_point = centroid(first.tool_cups_flange);
  const Eigen::Vector3d nominal_point =
      first.cell.flange_T_tool * centroid(fixture_cups(first.tool_sides, "tool fixture sides"));
  const Eigen::Vector3d fitted_point = centroid(fit.tool_cups_flange);
  const Pose<double> world_T_nominal = first.world.robot_T_fixture.inverse();
  const Pose<double> world_T_fit = frame_from_cups(fit.base_cups_robot.front()).inverse();
  const auto n = static_cast<Eigen::Index>(joints.size());
  Eigen::Matrix3Xd truth_points(3, n), model_points(3, n);
  std::vector<double> nominal, calibrated, registered;
  for (Eigen::Index k = 0; k < n; ++k) {
    const Vector6d& q = joints[k];
    truth_points.col(k) = first.world_T_sim * (true_flange_pose(truth, q) * true_point);
    model_points.col(k) = world_T_fit * (flange_pose(model, payload, fit.params, q) * fitted_point);
    nominal.push_back(
        (world_T_nominal * (flange_pose(model, payload, model.nominal(), q) * nominal_point) -
         truth_points.col(k))
            .norm());
    calibrated.push_back((model_points.col(k) - truth_points.col(k)).norm());
  }
  const Eigen::Isometry3d truth_T_model(Eigen::umeyama(model_points, truth_points, false));
  for (Eigen::Index k = 0; k < n; ++k)
    registered.push_back(
        (truth_T_model * Eigen::Vector3d(model_points.col(k)) - truth_points.col(k)).norm());
  out.nominal = error_statistics(nominal);
  out.calibrated = error_statistics(calibrated);
  out.registered = error_statistics(registered);
  return out;
}

}  // namespace robcal::hexapod
