#include "robcal/hexapod/simulated_readings.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "robcal/core/error.hpp"
#include "robcal/hexapod/end_to_end.hpp"
#include "robcal/hexapod/measurement.hpp"
#include "robcal/hexapod/session_answers.hpp"
#include "robcal/hexapod/simulation.hpp"
#include "robcal/io/measurement_file.hpp"

namespace robcal::hexapod {
namespace {

/// The simulated cell of a plan: the true robot and fixtures drawn from the seed.
SimulatedHexapodCell cell_of_plan(const std::string& file, const HexapodPlan& plan,
                                  const RobotModel& model, const PointMass& payload,
                                  std::mt19937_64& rng) {
  if (!plan.cell)
    throw InputError({file, 0, 0, "geometry"},
                     "the simulator needs the cell of a plan written by `robcal hexapod plan` "
                     "(geometry, placement, tool and ball offsets)");
  HexapodCellOptions cell;
  cell.design = plan.cell->geometry;
  cell.placement = placement_pose(plan.cell->placement, plan.cell->tilt_deg);
  cell.range_mm = plan.session.range_mm;
  cell.tool_offset_mm = plan.cell->tool_offset_mm;
  cell.ball_offset_mm = plan.cell->ball_offset_mm;
  const TrueRobot truth = levelled_random_truth(model, payload, EndToEndOptions{}.errors, rng);
  return set_up_simulated_cell(truth, model, cell, rng);
}

}  // namespace

SimulatedReadings simulate_readings(const HexapodPlan& plan, const RobotModel& model,
                                    const SimulatedReadingsRequest& request) {
  const int validation = request.validation;
  if (validation < 0) throw InputError({"", 0, 0, "--validation"}, "expected a non-negative count");
  const PointMass payload = request.payload.value_or(PointMass{2.6, Eigen::Vector3d(50, 25, 100)});
  std::mt19937_64 rng(request.seed);
  const SimulatedHexapodCell cell = cell_of_plan(request.plan_file, plan, model, payload, rng);
  SimulatedReadings out;
  out.seed = request.seed;
  // Drive the session script itself, so the readings come in the order the session asks.
  Session session(plan.session);
  while (const std::optional<SessionStep> step = session.next_step()) {
    const std::optional<double> r = simulate_session_reading(cell, plan.session, *step, rng);
    out.readings.push_back(r);
    out.out_of_range += r ? 0 : 1;
    session.record(r);
  }
  const Pose<double> flange_T_tool =
      plan.session.flange_T_tool ? *plan.session.flange_T_tool : cell.cell.flange_T_tool;
  out.tool = hexapod_tool(payload, flange_T_tool, cell.tool_sides);
  out.validation.kind = MeasurementKind::Points;
  if (validation > 0) {
    // The tracker reads the SMR in tool cup T1; its points go to the robot frame of the hexapod's
    // world (the frame of the poses file) through the world frame of the base cups.
    const TrackerValidation v =
        simulate_tracker_validation(cell, cell.tool_cups_flange[0], validation, 0.022, rng);
    for (size_t k = 0; k < v.joints.size(); ++k)
      out.validation.points.push_back(
          {fmt::format("v{}", k + 1), 0, v.joints[k],
           cell.world.robot_T_fixture * Eigen::Vector3d(v.measured.col(k)), 0});
  }
  return out;
}

std::string readings_text(const SimulatedReadings& simulated) {
  std::string text;
  for (const std::optional<double>& r : simulated.readings) text += session_answer_text(r) + "\n";
  return text;
}

std::string validation_csv(const SimulatedReadings& simulated) {
  return write_measurements_csv(
      simulated.validation, simulated.tool,
      fmt::format("simulated laser tracker (0.022 mm) on tool cup T1, seed {}", simulated.seed));
}

nlohmann::json simulated_readings_json(const SimulatedReadings& simulated, const std::string& out,
                                       const std::string& tool_out,
                                       const std::string& validation_out) {
  return {{"seed", simulated.seed},
          {"readings", simulated.readings.size()},
          {"legs_out_of_range", simulated.out_of_range},
          {"out", out},
          {"tool", tool_out},
          {"validation", validation_out}};
}

}  // namespace robcal::hexapod
