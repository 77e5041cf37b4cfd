// Simulation benches (protocol: shared/design/BENCHMARKS.md). The Monte Carlo goal: 1000
// calibrations (50 poses, 31 parameters asked, 1000-configuration validation each) ≤ 0.4 s on
// 2 cores; 1 and 2 threads run interleaved in this binary on the same inputs.

#include <benchmark/benchmark.h>

#include "robcal/io/robot_file.hpp"
#include "robcal/sim/monte_carlo.hpp"

namespace robcal {
namespace {

struct MonteCarloBench {
  MonteCarloOptions options;
  MonteCarloSetup setup;
  MonteCarloBench() {
    const RobotModel model = load_robot("abb-irb120");
    const Tool tool = default_simulation_tool();
    const TrueRobot truth = published_irb120_truth(model, tool);
    const VirtualInstrument tracker =
        standard_instrument(InstrumentKind::LaserTracker, truth, 0.022);
    options.runs = 1000;
    options.poses = 50;
    options.validation = 1000;
    options.seed = 1;
    setup = prepare_monte_carlo(truth, tracker, model, tool, options);
  }
};

const MonteCarloBench& monte_carlo_bench() {
  static const MonteCarloBench bench;
  return bench;
}

void BM_MonteCarlo1000Calibrations(benchmark::State& state) {
  const MonteCarloBench& bench = monte_carlo_bench();
  MonteCarloOptions options = bench.options;
  options.threads = static_cast<int>(state.range(0));
  MonteCarloResult result;
  for (auto _ : state) {
    result = run_monte_carlo(bench.setup, options);
    benchmark::DoNotOptimize(result.ratio);
  }
  state.counters["ratio"] = result.ratio;
  state.counters["failed"] = result.failed;
  state.counters["poses"] = static_cast<double>(bench.setup.template_set.size());
}
BENCHMARK(BM_MonteCarlo1000Calibrations)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_SimulateValidation1000(benchmark::State& state) {
  const MonteCarloBench& bench = monte_carlo_bench();
  RandomConfigurationOptions options;
  options.box = published_joint_box(bench.setup.truth.robot.model);
  for (auto _ : state) {
    std::mt19937_64 config_rng(5), noise_rng(6);
    const auto configs =
        random_configurations(bench.setup.truth, bench.setup.instrument, 1000, config_rng, options);
    benchmark::DoNotOptimize(
        simulate_measurements(bench.setup.truth, bench.setup.instrument, configs, noise_rng));
  }
}
BENCHMARK(BM_SimulateValidation1000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace robcal
