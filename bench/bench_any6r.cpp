// Any six-axis robot (issue 15): the UR family's closed form and the calibrated IK seeded by it,
// on the UR10e, and the general 6R inverse (CRX, random 6R; goal ≤ 20 µs all solutions),
// inputs generated here from fixed seeds.
//   Nominal IK with every solution: all 8 branches with every turn inside the UR's ±360° limits
//   (2⁶ turns per branch: up to 512 solutions), and the same with the limits narrowed to ±180°
//   (the 8 branches alone; the goal ≤ 0.5 µs); one branch (nominal_ik_branch).
//   Calibrated IK (Newton from the closed-form seed, 31-parameter error model with compliance):
//   goal ≤ 2 µs median per target, reported in the median_us counter.
// Run: build/robcal_bench --benchmark_filter=Any6r --benchmark_repetitions=5

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <random>
#include <vector>

#include "../tests/test_compensate_support.hpp"
#include "../tests/test_ik_round_trip.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/closed_form_ik.hpp"
#include "robcal/kinematics/nominal_chain.hpp"

namespace robcal {
namespace {

constexpr std::uint64_t kSeed = 20261124;
constexpr int kInputs = 1024;

template <typename Geometry>
struct NominalInputs {
  Geometry geometry;
  std::vector<Pose<double>> poses;
  std::vector<Vector6d> joints;
};

/// Flange poses of random joints of `model`.
template <typename Geometry>
NominalInputs<Geometry> inputs_for(const RobotModel& model, Geometry geometry) {
  NominalInputs<Geometry> in{std::move(geometry), {}, {}};
  const NominalChain chain = make_nominal_chain(model);
  std::mt19937_64 rng(kSeed);
  for (int k = 0; k < kInputs; ++k) {
    const Vector6d q = test::random_joints(model, rng);
    in.joints.push_back(q);
    in.poses.push_back(nominal_flange_pose(chain, q));
  }
  return in;
}

/// The UR10e with its limits set to ±`limit_deg`.
NominalInputs<ParallelAxesGeometry> ur10e_inputs(double limit_deg) {
  RobotModel model = load_robot("universal-robots-ur10e");
  for (JointLimit& l : model.limits) l = {-deg2rad(limit_deg), deg2rad(limit_deg)};
  return inputs_for(model, *analyze_parallel_axes(model));
}

template <typename Geometry>
void nominal_all(benchmark::State& state, const NominalInputs<Geometry>& in) {
  size_t k = 0;
  long solutions = 0, solves = 0;
  for (auto _ : state) {
    const IkResult r = nominal_ik(in.geometry, in.poses[k], in.joints[k]);
    benchmark::DoNotOptimize(r.count);
    solutions += r.count;
    ++solves;
    k = (k + 1) % in.poses.size();
  }
  state.counters["solutions"] = static_cast<double>(solutions) / static_cast<double>(solves);
}

/// Which paths the general solver took, per pose over the inputs (counted once, untimed).
void report_general_paths(benchmark::State& state, const NominalInputs<General6rGeometry>& in) {
  General6rCounts sum;
  for (const Pose<double>& pose : in.poses) {
    std::array<std::array<double, kJointCount>, kMaxGeneral6rSolutions> out;
    General6rCounts c;
    general_6r_link_angles(in.geometry, pose, out, &c);
    sum += c;
  }
  const auto per_pose = [&](int total) {
    return static_cast<double>(total) / static_cast<double>(in.poses.size());
  };
  state.counters["real_roots"] = per_pose(sum.real_roots);
  state.counters["eigenvector"] = per_pose(sum.eigenvector_solutions);
  state.counters["null_spaces"] = per_pose(sum.null_spaces);
  state.counters["twin_searches"] = per_pose(sum.twin_searches);
  state.counters["polishes"] = per_pose(sum.polishes);
}

void Any6r_Ur10eNominalIkEveryTurn(benchmark::State& state) {
  nominal_all(state, ur10e_inputs(360));
}
BENCHMARK(Any6r_Ur10eNominalIkEveryTurn);

void Any6r_Ur10eNominalIk8Branches(benchmark::State& state) {
  nominal_all(state, ur10e_inputs(180));
}
BENCHMARK(Any6r_Ur10eNominalIk8Branches);

// The general 6R inverse (every real solution, up to 16) on the Fanuc CRX-10iA/L with its
// limits set to ±180° (each solution once), and on a random 6R geometry (fixed seed).
void Any6r_CrxGeneralIkAllSolutions(benchmark::State& state) {
  RobotModel model = load_robot("fanuc-crx10ia-l");
  for (JointLimit& l : model.limits) l = {-deg2rad(180), deg2rad(180)};
  const auto in = inputs_for(model, *analyze_general_6r(model));
  nominal_all(state, in);
  report_general_paths(state, in);
}
BENCHMARK(Any6r_CrxGeneralIkAllSolutions);

void Any6r_Random6rGeneralIkAllSolutions(benchmark::State& state) {
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> twist(-180.0, 180.0), length(-400.0, 400.0);
  RobotModel model;
  model.mdh[0] = {0.0, 0.0, 0.0, length(rng)};
  for (int i = 1; i < kJointCount; ++i)
    model.mdh[i] = {deg2rad(twist(rng)), length(rng), deg2rad(twist(rng)), length(rng)};
  for (JointLimit& l : model.limits) l = {-deg2rad(180), deg2rad(180)};
  const auto in = inputs_for(model, *analyze_general_6r(model));
  nominal_all(state, in);
  report_general_paths(state, in);
}
BENCHMARK(Any6r_Random6rGeneralIkAllSolutions);

void Any6r_Ur10eNominalIkBranch(benchmark::State& state) {
  const NominalInputs in = ur10e_inputs(360);
  const RobotModel model = load_robot("universal-robots-ur10e");
  std::vector<ArmConfig> configs;
  for (const Vector6d& q : in.joints) configs.push_back(arm_config(model, q));
  size_t k = 0;
  for (auto _ : state) {
    const IkBranchResult r = nominal_ik_branch(in.geometry, in.poses[k], configs[k], in.joints[k]);
    benchmark::DoNotOptimize(r.solution.joints);
    k = (k + 1) % in.poses.size();
  }
}
BENCHMARK(Any6r_Ur10eNominalIkBranch);

// One target per iteration (mean in the time column); afterwards each of 10,000 targets timed
// alone for the median (clock reading included, about 0.02 µs here).
void Any6r_Ur10eCalibratedIkNewton(benchmark::State& state) {
  std::mt19937_64 rng(kSeed);
  const CalibratedRobot robot = test::random_calibrated("universal-robots-ur10e", rng);
  const Compensator comp = make_compensator(robot);
  struct Case {
    Pose<double> wanted;
    ArmConfig config;
    Vector6d near;
  };
  std::vector<Case> cases;
  while (cases.size() < 10000) {
    const Vector6d q = test::random_joints(robot.model, rng);
    if (test::near_singular(robot.model, q)) continue;
    cases.push_back({calibrated_tcp_pose(comp.chain, q), arm_config(robot.model, q), q});
  }
  size_t k = 0;
  for (auto _ : state) {
    const Case& c = cases[k];
    const CalibratedIkResult r = calibrated_ik(comp, c.wanted, c.config, c.near);
    benchmark::DoNotOptimize(r.joints);
    k = (k + 1) % cases.size();
  }
  using Clock = std::chrono::steady_clock;
  std::vector<double> us;
  long ok = 0;
  for (const Case& c : cases) {
    const auto t0 = Clock::now();
    const CalibratedIkResult r = calibrated_ik(comp, c.wanted, c.config, c.near);
    const auto t1 = Clock::now();
    ok += r.ok();
    us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  std::sort(us.begin(), us.end());
  state.counters["median_us"] = us[us.size() / 2];
  state.counters["p99_us"] = us[us.size() * 99 / 100];
  state.counters["success_pct"] = 100.0 * static_cast<double>(ok) / static_cast<double>(us.size());
}
BENCHMARK(Any6r_Ur10eCalibratedIkNewton);

// The 100,000 configurations per built-in robot (12,500 per labelled branch, branches
// the limits exclude left empty): the branch solver seeded with the drawn joints returns them
// (test::ik_round_trip_ok: the pose, and the joints within the wrist's conditioning).
// tests/test_robot_library.cpp runs 2,000 per branch; this is the full count, reported as counters
// (failures must be 0). Run: build/robcal_bench
// --benchmark_filter='Any6r_Library100k/fanuc-crx10ia$'
void Any6r_Library100k(benchmark::State& state, const std::string& name) {
  const RobotModel model = load_robot(name);
  const auto g = analyze_closed_form(model);
  const NominalChain chain = make_nominal_chain(model);
  constexpr int kPerBranch = 12500;
  for (auto _ : state) {
    std::mt19937_64 rng(kSeed);
    std::array<int, 8> count{};
    long failures = 0, draws = 0;
    while (*std::min_element(count.begin(), count.end()) < kPerBranch && draws < 4'000'000) {
      ++draws;
      const Vector6d q = test::random_joints(model, rng);
      const ArmConfig config = arm_config(model, q);
      if (count[config.index()] >= kPerBranch) continue;
      ++count[config.index()];
      const Pose<double> target = nominal_flange_pose(chain, q);
      const IkBranchResult r = nominal_ik_branch(*g, target, config, q);
      failures += r.status != IkStatus::Solved ||
                  !test::ik_round_trip_ok(model, chain, q, target, r.solution.joints);
    }
    long total = 0;
    for (int c : count) total += c;
    state.counters["configurations"] = static_cast<double>(total);
    state.counters["failures"] = static_cast<double>(failures);
    state.counters["draws"] = static_cast<double>(draws);
  }
}

const bool library_registered = [] {
  for (const std::string& name : builtin_robot_names())
    benchmark::RegisterBenchmark(("Any6r_Library100k/" + name).c_str(), Any6r_Library100k, name)
        ->Iterations(1)
        ->Unit(benchmark::kSecond);
  return true;
}();

}  // namespace
}  // namespace robcal
