// Choosing calibration configurations (METHOD §6, issue 5): the fast D-optimal greedy +
// exchange with rank-3 updates against the published exchange on O1 (SVD-type recomputation
// per trial), on the same IRB 120 candidates (full model, 31 parameters of which 30 are
// identifiable, points). Run interleaved:
//   build/robcal_bench --benchmark_filter=Design --benchmark_repetitions=15 \
//     --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
// Both run on 500 and 5000 candidates (the published exchange once per size: about 1 s and
// 14 s of CPU). Compare the `O1` counters too: the fast selection must match or beat it.

#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <random>

#include "robcal/design/candidates.hpp"
#include "robcal/design/design_matrix.hpp"
#include "robcal/design/observability.hpp"
#include "robcal/design/selection.hpp"
#include "robcal/identify/unknowns.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/true_robot.hpp"

namespace robcal {
namespace {

struct Setup {
  RobotModel model = load_robot("abb-irb120");
  Tool tool = default_simulation_tool();  // the reference set's three SMRs
  std::vector<Candidate> candidates;
  DesignSettings settings;

  explicit Setup(int count) {
    std::mt19937_64 rng(1);
    CandidateOptions options;
    options.count = count;
    candidates = generate_candidates(model, tool, options, rng).candidates;
    settings.parameters = level_parameters(CalibrationLevel::Full);
  }
};

const DesignMatrix& design(int count) {
  static const DesignMatrix d5000 = [] {
    const Setup s(5000);
    return build_design_matrix(s.model, s.tool, s.candidates, s.settings);
  }();
  static const DesignMatrix d500 = [] {
    const Setup s(500);
    return build_design_matrix(s.model, s.tool, s.candidates, s.settings);
  }();
  return count == 5000 ? d5000 : d500;
}

void report(benchmark::State& state, const DesignMatrix& d, const Selection& s) {
  state.counters["O1"] = observability_indices(d, s.chosen).O1;
  state.counters["exchanges"] = s.exchanges;
  state.counters["parameters"] = d.columns();
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["max_rss_MB"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
}

void BM_DesignFastDOptimal(benchmark::State& state) {
  const DesignMatrix& d = design(static_cast<int>(state.range(0)));
  Selection s;
  for (auto _ : state) {
    s = select_d_optimal(d, 40);
    benchmark::DoNotOptimize(s.chosen.data());
  }
  report(state, d, s);
}
BENCHMARK(BM_DesignFastDOptimal)->Arg(5000)->Arg(500)->Unit(benchmark::kMillisecond);

void BM_DesignPublishedExchange(benchmark::State& state) {
  const DesignMatrix& d = design(static_cast<int>(state.range(0)));
  Selection s;
  for (auto _ : state) {
    std::mt19937_64 rng(7);
    s = select_published_exchange(d, 40, rng);
    benchmark::DoNotOptimize(s.chosen.data());
  }
  report(state, d, s);
}
BENCHMARK(BM_DesignPublishedExchange)
    ->Arg(500)
    ->Arg(5000)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// What comes before the selection: 5000 candidate Jacobians (autodiff) and column scaling.
void BM_DesignMatrix5000(benchmark::State& state) {
  const Setup s(5000);
  for (auto _ : state) {
    const DesignMatrix d = build_design_matrix(s.model, s.tool, s.candidates, s.settings);
    benchmark::DoNotOptimize(d.rows.data());
  }
}
BENCHMARK(BM_DesignMatrix5000)->Iterations(1)->Unit(benchmark::kMillisecond);

// The certificate: continuous D-optimum over 5000 candidates (multiplicative algorithm).
void BM_DesignContinuousOptimum(benchmark::State& state) {
  const DesignMatrix& d = design(5000);
  ContinuousDesign c;
  for (auto _ : state) {
    c = d_optimal_continuous(d);
    benchmark::DoNotOptimize(c.weights.data());
  }
  state.counters["iterations"] = c.iterations;
  const Selection sel = select_d_optimal(d, 40);
  state.counters["d_efficiency_fast"] = d_efficiency(d, sel.chosen, c);
}
BENCHMARK(BM_DesignContinuousOptimum)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace robcal
