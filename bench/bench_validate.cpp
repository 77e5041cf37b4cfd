// All-pairs distance statistics over 10,000 validation rows (50 million pairs),
// docs/method/09-validation.md; 1 and 2 threads (BENCHMARKS.md: compared inside one process,
// interleaved).

#include <benchmark/benchmark.h>

#include <chrono>
#include <random>

#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/validate/pairwise_distance.hpp"

namespace robcal {
namespace {

/// 10,000 IRB 120 flange positions (uniform joints within limits, seed 2026): modelled by the
/// nominal robot, "measured" by the robot with the published link-3/4 length errors, a base
/// offset and 0.02 mm noise per axis.
struct ValidationPositions {
  Eigen::Matrix3Xd measured, modelled;
  ValidationPositions() {
    const RobotModel model = load_robot("abb-irb120");
    std::mt19937_64 rng(2026);
    std::normal_distribution<double> noise(0.0, 0.02);
    ParameterVector truth = model.nominal();
    truth[0] = -0.075;
    truth[1] = -0.096;
    truth[2] = 0.103;
    truth[link_param(3, 1)] += 0.236;
    truth[link_param(4, 3)] += 0.246;
    constexpr int kRows = 10000;
    measured.resize(3, kRows);
    modelled.resize(3, kRows);
    for (int r = 0; r < kRows; ++r) {
      Vector6d q;
      for (int j = 0; j < kJointCount; ++j)
        q[j] = std::uniform_real_distribution<double>(model.limits[j].lower,
                                                      model.limits[j].upper)(rng);
      modelled.col(r) = flange_pose(model, PointMass{}, model.nominal(), q).p;
      measured.col(r) = flange_pose(model, PointMass{}, truth, q).p +
                        Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    }
  }
};

const ValidationPositions& positions() {
  static const ValidationPositions data;
  return data;
}

void BM_AllPairs10k(benchmark::State& state) {
  const ValidationPositions& data = positions();
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const PairwiseDistanceErrors result =
        pairwise_distance_errors(data.measured, data.modelled, threads);
    benchmark::DoNotOptimize(result.stats.mean);
  }
  state.counters["pairs"] = 10000.0 * 9999.0 / 2;
}
BENCHMARK(BM_AllPairs10k)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

/// 1 and 2 threads alternating inside every iteration; counters are the mean times (ms).
void BM_AllPairs10kInterleaved(benchmark::State& state) {
  const ValidationPositions& data = positions();
  double one = 0, two = 0;
  for (auto _ : state) {
    for (int threads : {1, 2}) {
      const auto start = std::chrono::steady_clock::now();
      const PairwiseDistanceErrors result =
          pairwise_distance_errors(data.measured, data.modelled, threads);
      benchmark::DoNotOptimize(result.stats.mean);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      (threads == 1 ? one : two) += ms;
    }
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["ms_1_thread"] = one / n;
  state.counters["ms_2_threads"] = two / n;
  state.counters["speedup"] = one / two;
}
BENCHMARK(BM_AllPairs10kInterleaved)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace robcal
