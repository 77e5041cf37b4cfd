/// `robcal simulate`: measurements of a virtual robot by a virtual instrument, written as the
/// files a real campaign gives, with the truth kept apart under truth/.

#include <fmt/format.h>

#include <memory>
#include <optional>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/campaign/cell.hpp"
#include "robcal/campaign/cell_planning.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/simulation_files.hpp"

namespace robcal::cli {
namespace {

struct SimulateOptions {
  std::string robot = "abb-irb120";
  std::string truth = "published";
  std::string instrument;  ///< default: the cell's, else laser-tracker
  std::string cell;
  std::string tool;
  std::string configs;
  int random = 0;
  uint64_t seed = 1;
  double noise_mm = 0;
  std::vector<std::string> effects;
  std::string approach = "below";
  double error_length_mm = ErrorBounds{}.length_mm;
  double error_angle_deg = ErrorBounds{}.angle_deg;
  std::string out;
  bool json = false;
};

void run_simulate(const SimulateOptions& o) {
  if (o.configs.empty() == (o.random <= 0))
    throw InputError({"", 0, 0, "--configs"}, "give exactly one of --configs FILE or --random N");
  if (o.approach != "below" && o.approach != "sequence")
    throw InputError({"", 0, 0, "--approach"}, "expected 'below' or 'sequence'");
  const RobotModel model = load_robot(o.robot);
  const Tool tool = o.tool.empty() ? default_simulation_tool() : load_tool(o.tool);
  std::mt19937_64 truth_rng(o.seed), config_rng(o.seed + 1), noise_rng(o.seed + 2);

  TrueRobot truth;
  if (o.truth == "published") {
    truth = published_irb120_truth(model, tool);
  } else if (o.truth == "random") {
    ErrorBounds bounds;
    bounds.length_mm = o.error_length_mm;
    bounds.angle_deg = o.error_angle_deg;
    truth = random_truth(model, tool, bounds, truth_rng);
    truth.origin = fmt::format("random (seed {})", o.seed);
  } else {
    truth = load_truth(o.truth, o.robot);
    // The truth file's own targets are the real ones; the pipeline gets the given tool.
  }
  enable_effects(truth, o.effects, truth_rng);

  // The cell places the robot and the instrument; without one, the simulator's standard cell
  // (data/cells/default-tracker.yaml describes the same placement).
  std::optional<campaign::Cell> cell;
  if (!o.cell.empty()) cell = campaign::load_cell(o.cell);
  if (cell && o.truth != "published" && o.truth != "random")
    throw InputError({"", 0, 0, "--cell"},
                     "the truth file places the robot ('base:') and so does the cell "
                     "('robot_base:'): give one of --truth FILE or --cell");
  const std::string name = !o.instrument.empty() ? o.instrument
                           : cell                ? instrument_name(cell->instrument.kind)
                                                 : "laser-tracker";
  const InstrumentKind kind = parse_instrument_kind(name, "--instrument");
  if (cell && kind != cell->instrument.kind)
    throw InputError({"", 0, 0, "--instrument"},
                     fmt::format("the cell {} holds a {}; --instrument {} contradicts it (leave "
                                 "it out, or use another cell)",
                                 o.cell, instrument_name(cell->instrument.kind), name));
  VirtualInstrument instrument = standard_instrument(kind, truth, o.noise_mm);
  if (cell) {
    truth.robot.params.head<6>() = campaign::base_parameters(*cell);
    const VirtualInstrument placed = campaign::virtual_instrument(*cell, tool);
    instrument.tracker = placed.tracker;
    instrument.cmm = placed.cmm;
    if (o.noise_mm > 0) {
      instrument.tracker.sigma_mm.setConstant(o.noise_mm);
      instrument.cmm.sigma_mm = o.noise_mm;
      instrument.cmm.sigma_orientation_deg = rad2deg(o.noise_mm / 100.0);
    }
  }
  std::vector<PlannedConfiguration> configs;
  if (!o.configs.empty()) {
    configs = read_configurations_csv(o.configs, tool);
  } else {
    RandomConfigurationOptions options;
    options.box = published_joint_box(truth.robot.model);
    configs = random_configurations(truth, instrument, o.random, config_rng, options);
  }
  SimulationOptions sim;
  sim.approach_from_below = o.approach == "below";
  const SimulationResult result = simulate_measurements(truth, instrument, configs, noise_rng, sim);
  if (result.measurements.size() == 0)
    throw InputError({"", 0, 0, o.configs.empty() ? "--random" : "--configs"},
                     fmt::format("the instrument could read none of the {} configurations "
                                 "(first: {})",
                                 configs.size(), result.skipped.front()));
  const std::string comment =
      fmt::format("simulated by robcal: robot {}, truth {}, instrument {}, seed {}, noise {}",
                  model.name, truth.origin, name, o.seed,
                  o.noise_mm > 0 ? fmt::format("{} mm per axis", o.noise_mm)
                                 : std::string("the instrument's own"));
  const SimulationFiles files =
      write_simulation(o.out, "measurements", result, tool, instrument, truth, o.robot, comment);
  if (o.json) {
    nlohmann::json out;
    out["seed"] = o.seed;
    out["instrument"] = name;
    if (cell) out["cell"] = o.cell;
    out["truth"] = truth.origin;
    out["configurations"] = configs.size();
    out["measured"] = result.measurements.size();
    out["skipped"] = result.skipped;
    out["files"] = {{"measurements", files.measurements.string()},
                    {"tool", files.tool.string()},
                    {"instrument", files.instrument.string()},
                    {"truth", files.truth.string()}};
    print_json(out);
    return;
  }
  fmt::print("simulated {} of {} configurations with a {} (seed {}, truth {})\n",
             result.measurements.size(), configs.size(), name, o.seed, truth.origin);
  for (const std::string& line : result.skipped) fmt::print("  skipped {}\n", line);
  fmt::print("wrote {}\n      {}\n      {}\n      {} (the truth: never give it to the pipeline)\n",
             files.measurements.string(), files.tool.string(), files.instrument.string(),
             files.truth.string());
}

const bool registered = register_command(80, [](CLI::App& app) {
  auto o = std::make_shared<SimulateOptions>();
  auto* cmd = app.add_subcommand(
      "simulate", "Measure a virtual robot with a virtual instrument (files as a real campaign)");
  cmd->add_option("--robot", o->robot, "Built-in robot name or robot file")->capture_default_str();
  cmd->add_option("--truth", o->truth,
                  "The real robot: published (docs/method/11-published-results.md IRB 120), "
                  "random, or a truth file")
      ->capture_default_str();
  cmd->add_option(
      "--instrument", o->instrument,
      "laser-tracker, optical-cmm or ballbar (default: the cell's, else laser-tracker)");
  cmd->add_option("--cell", o->cell,
                  "Cell file (data/cells/): the robot base and the instrument's placement, range "
                  "and line-of-sight rules (default: the simulator's standard cell, "
                  "data/cells/default-tracker.yaml)");
  cmd->add_option("--tool", o->tool, "Tool file (default: 3 SMRs, 2.6 kg payload)");
  cmd->add_option("--configs", o->configs, "Configurations to measure: config,target,j1..j6 (deg)");
  cmd->add_option("--random", o->random, "Or: this many random measurable configurations");
  cmd->add_option("--seed", o->seed, "Seed of every random draw")->capture_default_str();
  cmd->add_option("--noise-mm", o->noise_mm, "Instrument σ per axis in mm (default: its own)");
  cmd->add_option("--effects", o->effects,
                  "Unmodelled effects: backlash,j6-periodic,mass-error,thermal")
      ->delimiter(',');
  cmd->add_option("--approach", o->approach,
                  "below: every configuration approached from below (cancels backlash); "
                  "sequence: straight from the previous one")
      ->capture_default_str();
  cmd->add_option("--error-length-mm", o->error_length_mm, "Random truth: ± bound of a_i, d_i")
      ->capture_default_str();
  cmd->add_option("--error-angle-deg", o->error_angle_deg,
                  "Random truth: ± bound of alpha_i, theta offsets")
      ->capture_default_str();
  cmd->add_option("--out", o->out, "Output folder")->required();
  cmd->add_flag("--json", o->json, "Machine-readable summary");
  cmd->callback([o] { run_simulate(*o); });
});

}  // namespace
}  // namespace robcal::cli
