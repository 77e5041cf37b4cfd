// Ballbar hexapod speed: the direct kinematics on measured distances (the 8 cascade solutions
// alone, and the checked DKP keeping the 4 above the base), the Jet sensitivities of the 4 modes,
// the 72-pose enumeration and the planning of the 72 poses for an LR Mate 200iC.

#include <benchmark/benchmark.h>

#include <random>

#include "robcal/hexapod/direct_kinematics.hpp"
#include "robcal/hexapod/planning.hpp"
#include "robcal/hexapod/poses.hpp"
#include "robcal/hexapod/uncertainty.hpp"
#include "robcal/io/robot_file.hpp"

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

void BM_HexapodCascadeAll8(benchmark::State& state) {
  const auto legs = random_legs(256);
  const Cups<double> base = triangle_from_sides(300.01, 299.98, 300.02);
  const std::array<double, 3> tool{150.01, 149.99, 150.0};
  size_t i = 0;
  for (auto _ : state) {
    auto all = cascade_all(base, tool, legs[i++ & 255]);
    benchmark::DoNotOptimize(all);
  }
}
BENCHMARK(BM_HexapodCascadeAll8);

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

void BM_HexapodPlan72LrMate(benchmark::State& state) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  const HexapodGeometry g;
  const std::vector<HexapodPose> poses = enumerate_poses(g);
  const Cups<double> base = fixture_cups(g.base, "base");
  CellSetup cell;
  cell.robot_T_base.p = Eigen::Vector3d(450, 0, 300) - centroid(base);
  cell.flange_T_tool = default_tool_mount(g.tool);
  int configurations = 0;
  for (auto _ : state) {
    const PlanSummary plan = plan_poses(model, cell, base, poses);
    configurations = plan.configurations;
    benchmark::DoNotOptimize(plan);
  }
  state.counters["configurations"] = configurations;
}
BENCHMARK(BM_HexapodPlan72LrMate)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace robcal::hexapod
