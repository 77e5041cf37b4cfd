#include "robcal/sim/simulate_workflow.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <optional>

#include "robcal/campaign/cell.hpp"
#include "robcal/campaign/cell_planning.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal {
namespace {

TrueRobot make_true_robot(const SimulateRequest& r, const RobotModel& model, const Tool& tool,
                          std::mt19937_64& rng) {
  TrueRobot truth;
  if (r.truth == "published") {
    truth = published_irb120_truth(model, tool);
  } else if (r.truth == "random") {
    ErrorBounds bounds;
    bounds.length_mm = r.error_length_mm;
    bounds.angle_deg = r.error_angle_deg;
    truth = random_truth(model, tool, bounds, rng);
    truth.origin = fmt::format("random (seed {})", r.seed);
  } else {
    // The truth file's own targets are the real ones; the pipeline gets the given tool.
    truth = load_truth(r.truth, r.robot);
  }
  enable_effects(truth, r.effects, rng);
  return truth;
}

}  // namespace

SimulateResult run_simulation(const SimulateRequest& r) {
  if (r.configs.empty() == (r.random <= 0))
    throw InputError({"", 0, 0, "--configs"}, "give exactly one of --configs FILE or --random N");
  if (r.approach != "below" && r.approach != "sequence" && r.approach != "random")
    throw InputError({"", 0, 0, "--approach"}, "expected 'below', 'sequence' or 'random'");
  if (r.noise_mm < 0)
    throw InputError({"", 0, 0, "--noise-mm"},
                     fmt::format("expected a σ ≥ 0 mm, found {}", r.noise_mm));
  SimulateResult result;
  result.request = r;
  const RobotModel model = load_robot(r.robot);
  result.tool = r.tool.empty() ? default_simulation_tool() : load_tool(r.tool);
  std::mt19937_64 truth_rng(r.seed), config_rng(r.seed + 1), noise_rng(r.seed + 2);
  TrueRobot truth = make_true_robot(r, model, result.tool, truth_rng);
  result.truth = truth.origin;

  // The cell places the robot and the instrument; without one, the simulator's standard cell
  // (data/cells/default-tracker.yaml describes the same placement).
  std::optional<campaign::Cell> cell;
  if (!r.cell.empty()) cell = campaign::load_cell(r.cell);
  if (cell && r.truth != "published" && r.truth != "random")
    throw InputError({"", 0, 0, "--cell"},
                     "the truth file places the robot ('base:') and so does the cell "
                     "('robot_base:'): give one of --truth FILE or --cell");
  result.instrument = !r.instrument.empty() ? r.instrument
                      : cell                ? instrument_name(cell->instrument.kind)
                                            : "laser-tracker";
  const InstrumentKind kind = parse_instrument_kind(result.instrument, "--instrument");
  if (cell && kind != cell->instrument.kind)
    throw InputError(
        {"", 0, 0, "--instrument"},
        fmt::format("the cell {} holds a {}; --instrument {} contradicts it (leave "
                    "it out, or use another cell)",
                    r.cell, instrument_name(cell->instrument.kind), result.instrument));
  VirtualInstrument instrument = standard_instrument(kind, truth, r.noise_mm);
  if (cell) {
    truth.robot.params.head<6>() = campaign::base_parameters(*cell);
    const VirtualInstrument placed = campaign::virtual_instrument(*cell, result.tool);
    instrument.tracker = placed.tracker;
    instrument.cmm = placed.cmm;
    if (r.noise_mm > 0) {
      instrument.tracker.sigma_mm.setConstant(r.noise_mm);
      instrument.cmm.sigma_mm = r.noise_mm;
      instrument.cmm.sigma_orientation_deg = rad2deg(r.noise_mm / 100.0);
    }
  }
  if (r.exact) {
    instrument.tracker.sigma_mm.setZero();
    instrument.cmm.sigma_mm = 0;
    instrument.cmm.sigma_orientation_deg = 0;
    instrument.ballbar.sigma_mm = 0;
  }

  std::vector<PlannedConfiguration> configs;
  if (!r.configs.empty()) {
    configs = read_configurations_csv(r.configs, result.tool);
  } else {
    RandomConfigurationOptions options;
    options.box = published_joint_box(truth.robot.model);
    if (cell)  // the cell's floor, keep-out boxes and line of sight (nominal robot, as planned)
      options.accept = [&](const PlannedConfiguration& c) {
        return campaign::check_configuration(*cell, model, result.tool, c.joints, c.target)
                   .reason == campaign::Rejection::None;
      };
    configs = random_configurations(truth, instrument, r.random, config_rng, options);
  }
  result.configurations = configs.size();
  SimulationOptions sim;
  sim.approach_from_below = r.approach == "below";
  sim.approach_random = r.approach == "random";  // sides drawn from seed + 3
  sim.approach_seed = r.seed + 3;
  sim.record_time = r.clock;
  result.simulation = simulate_measurements(truth, instrument, configs, noise_rng, sim);
  if (result.simulation.measurements.size() == 0)
    throw InputError({"", 0, 0, r.configs.empty() ? "--random" : "--configs"},
                     fmt::format("the instrument could read none of the {} configurations "
                                 "(first: {})",
                                 configs.size(), result.simulation.skipped.front()));
  if (!r.out.empty()) {
    const std::string comment =
        fmt::format("simulated by robcal: robot {}, truth {}, instrument {}, seed {}, noise {}",
                    model.name, truth.origin, result.instrument, r.seed,
                    r.exact          ? std::string("none (exact readings)")
                    : r.noise_mm > 0 ? fmt::format("{} mm per axis", r.noise_mm)
                                     : std::string("the instrument's own"));
    result.files = write_simulation(r.out, "measurements", result.simulation, result.tool,
                                    instrument, truth, r.robot, comment);
  }
  return result;
}

nlohmann::json simulation_json(const SimulateResult& result) {
  nlohmann::json out;
  out["seed"] = result.request.seed;
  out["instrument"] = result.instrument;
  if (!result.request.cell.empty()) out["cell"] = result.request.cell;
  out["truth"] = result.truth;
  out["configurations"] = result.configurations;
  out["measured"] = result.simulation.measurements.size();
  out["skipped"] = result.simulation.skipped;
  if (result.files)
    out["files"] = {{"measurements", result.files->measurements.string()},
                    {"tool", result.files->tool.string()},
                    {"instrument", result.files->instrument.string()},
                    {"truth", result.files->truth.string()}};
  return out;
}

}  // namespace robcal
