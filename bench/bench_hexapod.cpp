// Ballbar hexapod speed: the direct kinematics on measured distances (all 8 cascade solutions,
// the 4 above the base), the Jet sensitivities of one mode, the 72-pose enumeration.

#include <benchmark/benchmark.h>

#include <random>

#include "robcal/hexapod/direct_kinematics.hpp"
#include "robcal/hexapod/poses.hpp"
#include "robcal/hexapod/uncertainty.hpp"

namespace robcal::hexapod {
namespace {

std::vector<LegLengths<double>> random_legs(int count) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<LegLengths<double>> out;
  for (int i = 0; i < count; ++i) {
    LegLengths<double> legs;
    for (double& l : legs) l = 300 + u(rng);
    out.push_back(legs);
  }
  return out;
}

void BM_HexapodDkp(benchmark::State& state) {
  const auto legs = random_legs(256);
  const TriangleSides base{300.01, 299.98, 300.02}, tool{150.01, 149.99, 150.0};
  size_t i = 0;
  for (auto _ : state) {
    DkpResult r = solve_dkp(base, tool, legs[i++ & 255]);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_HexapodDkp);

void BM_HexapodSensitivities(benchmark::State& state) {
  const HexapodGeometry g;
  for (auto _ : state) {
    auto r = dkp_uncertainty(g);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_HexapodSensitivities);

void BM_HexapodEnumerate72(benchmark::State& state) {
  const HexapodGeometry g;
  for (auto _ : state) {
    auto poses = enumerate_poses(g);
    benchmark::DoNotOptimize(poses);
  }
}
BENCHMARK(BM_HexapodEnumerate72);

}  // namespace
}  // namespace robcal::hexapod
