/// `robcal simulate`: measurements of a virtual robot by a virtual instrument, written as the
/// files a real campaign gives, with the truth kept apart under truth/.

#include <fmt/format.h>

#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/sim/simulate_workflow.hpp"

namespace robcal::cli {
namespace {

struct SimulateOptions {
  SimulateRequest request;
  bool json = false;
};

void run_simulate(const SimulateRequest& request, bool json) {
  const SimulateResult r = run_simulation(request);
  if (json) {
    print_json(simulation_json(r));
    return;
  }
  fmt::print("simulated {} of {} configurations with a {} (seed {}, truth {})\n",
             r.simulation.measurements.size(), r.configurations, r.instrument, request.seed,
             r.truth);
  for (const std::string& line : r.simulation.skipped) fmt::print("  skipped {}\n", line);
  fmt::print("wrote {}\n      {}\n      {}\n      {} (the truth: never give it to the pipeline)\n",
             r.files->measurements.string(), r.files->tool.string(), r.files->instrument.string(),
             r.files->truth.string());
}

const bool simulate_registered = register_command(80, [](CLI::App& app) {
  auto o = std::make_shared<SimulateOptions>();
  auto* cmd = app.add_subcommand(
      "simulate", "Measure a virtual robot with a virtual instrument (files as a real campaign)");
  cmd->add_option("--robot", o->request.robot, "Built-in robot name or robot file")
      ->capture_default_str();
  cmd->add_option("--truth", o->request.truth,
                  "The real robot: published (docs/method/11-published-results.md §3 IRB 120), "
                  "random, or a truth file")
      ->capture_default_str();
  cmd->add_option(
      "--instrument", o->request.instrument,
      "laser-tracker, optical-cmm or ballbar (default: the cell's, else laser-tracker)");
  cmd->add_option("--cell", o->request.cell,
                  "Cell file (data/cells/): the robot base and the instrument's placement, range "
                  "and line-of-sight rules; random configurations also keep its floor, keep-out "
                  "boxes and line of sight (default: the simulator's standard cell, "
                  "data/cells/default-tracker.yaml)");
  cmd->add_option("--tool", o->request.tool, "Tool file (default: 3 SMRs, 2.6 kg payload)");
  cmd->add_option("--configs", o->request.configs,
                  "Configurations to measure: config,target,j1..j6 (deg)");
  cmd->add_option("--random", o->request.random, "Or: this many random measurable configurations");
  cmd->add_option("--seed", o->request.seed, "Seed of every random draw")->capture_default_str();
  cmd->add_option("--noise-mm", o->request.noise_mm,
                  "Instrument σ per axis in mm (default: its own)");
  cmd->add_option("--effects", o->request.effects,
                  "Unmodelled effects: backlash,j6-periodic,mass-error,thermal")
      ->delimiter(',');
  cmd->add_option(
         "--approach", o->request.approach,
         "below: every configuration approached as the measurement program does, from q - 5 deg "
         "(cancels backlash) unless the configurations file's approach column gives "
         "another side; "
         "sequence: straight from the previous one; random: each joint from below or "
         "above at random (seeded), recorded in the 'approach' column (backlash group)")
      ->capture_default_str();
  cmd->add_flag("--clock", o->request.clock,
                "With thermal drift: record each row's time (time_s column, warmup group) "
                "instead of the arm's temperature");
  cmd->add_option("--error-length-mm", o->request.error_length_mm,
                  "Random truth: ± bound of a_i, d_i")
      ->capture_default_str();
  cmd->add_option("--error-angle-deg", o->request.error_angle_deg,
                  "Random truth: ± bound of alpha_i, theta offsets")
      ->capture_default_str();
  cmd->add_option("--out", o->request.out, "Output folder")->required();
  cmd->add_flag("--json", o->json, "Machine-readable summary");
  cmd->callback([o] { run_simulate(o->request, o->json); });
});

}  // namespace
}  // namespace robcal::cli
