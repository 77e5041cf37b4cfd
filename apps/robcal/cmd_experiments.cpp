/// `robcal experiments`: the published simulation experiments (docs/method/11-published-results.md
/// §2) reproduced as a bench, results as JSON and a markdown table beside the published figures.

#include <fmt/format.h>

#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/sim/experiments.hpp"

namespace robcal::cli {
namespace {

struct ExperimentOptions {
  std::string out = "bench/experiments/results";
  uint64_t seed = 1;
  bool json = false;
};

void run_experiments(const ExperimentOptions& o) {
  const bool progress = !o.json && stdout_is_terminal();
  const PublishedExperimentsRun run =
      run_published_experiments_files(o.seed, o.out, [&](const std::string& what) {
        if (progress) fmt::print("{}\n", what);
      });
  if (o.json) {
    print_json(published_experiments_run_json(run));
    return;
  }
  fmt::print("{}\nwrote {}/results.json and results.md ({:.1f} s)\n",
             published_experiments_markdown(run.experiments), o.out, run.seconds);
}

const bool experiments_registered = register_command(96, [](CLI::App& app) {
  auto o = std::make_shared<ExperimentOptions>();
  auto* cmd = app.add_subcommand(
      "experiments",
      "Reproduce the published simulation experiments (docs/method/11-published-results.md §2)");
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of every random draw")->capture_default_str();
  cmd->add_flag("--json", o->json, "Machine-readable output");
  cmd->callback([o] { run_experiments(*o); });
});

}  // namespace
}  // namespace robcal::cli
