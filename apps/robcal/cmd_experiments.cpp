/// `robcal experiments`: the published simulation experiments (docs/method/11-published-results.md)
/// reproduced as a bench, results as JSON and a markdown table beside the published figures.

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/sim/experiments.hpp"

namespace robcal::cli {
namespace {

struct ExperimentOptions {
  std::string out = "bench/experiments/results";
  uint64_t seed = 1;
  bool json = false;
};

void run_experiments(const ExperimentOptions& o) {
  const auto started = std::chrono::steady_clock::now();
  const bool progress = !o.json && stdout_is_terminal();
  const PublishedExperiments e = run_published_experiments(o.seed, [&](const std::string& what) {
    if (progress) fmt::print("{}\n", what);
  });
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  nlohmann::json all = published_experiments_json(e);
  all["seconds"] = seconds;
  const std::string md = published_experiments_markdown(e);
  const std::filesystem::path out(o.out);
  write_file_atomically(out / "results.json", all.dump(2) + "\n");
  write_file_atomically(out / "results.md", md);
  if (o.json) {
    print_json(all);
    return;
  }
  fmt::print("{}\nwrote {}/results.json and results.md ({:.1f} s)\n", md, out.string(), seconds);
}

const bool registered = register_command(96, [](CLI::App& app) {
  auto o = std::make_shared<ExperimentOptions>();
  auto* cmd = app.add_subcommand(
      "experiments",
      "Reproduce the published simulation experiments (docs/method/11-published-results.md)");
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of every random draw")->capture_default_str();
  cmd->add_flag("--json", o->json, "Machine-readable output");
  cmd->callback([o] { run_experiments(*o); });
});

}  // namespace
}  // namespace robcal::cli
