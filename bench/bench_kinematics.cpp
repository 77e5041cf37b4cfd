// Kinematics speed (BENCHMARKS.md): ABB IRB 120, inputs generated here from fixed seeds.
//   FK of the flange and 3 targets (goal ≤ 0.2 µs; error-model FK and the nominal chain), nominal
//   closed-form IK with every solution (goal ≤ 0.40 µs median; opw_kinematics 0.52–0.85 µs on this
//   machine), one branch of it (nominal_ik_branch), and the numeric (DLS) IK of a calibrated,
//   compliant robot seeded with the nominal analytic solution.
// Run: build/robcal_bench --benchmark_filter=Kinematics --benchmark_repetitions=15

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/kinematics/nominal_chain.hpp"
#include "robcal/kinematics/numeric_ik.hpp"

namespace robcal {
namespace {

constexpr std::uint64_t kSeed = 20261122;
constexpr int kInputs = 1024;

std::vector<Vector6d> random_joints(const RobotModel& model, std::mt19937_64& rng, int n) {
  std::vector<Vector6d> out(n);
  for (Vector6d& q : out)
    for (int i = 0; i < kJointCount; ++i)
      q[i] =
          std::uniform_real_distribution<double>(model.limits[i].lower, model.limits[i].upper)(rng);
  return out;
}

void Kinematics_FkFlangeAnd3Targets(benchmark::State& state) {
  const RobotModel model = load_robot("abb-irb120");
  const ParameterVector params = model.nominal();
  std::mt19937_64 rng(kSeed);
  const std::vector<Vector6d> joints = random_joints(model, rng, kInputs);
  const std::array<Eigen::Vector3d, 3> targets{
      Eigen::Vector3d(50, 0, 100), Eigen::Vector3d(-40, 60, 90), Eigen::Vector3d(0, -70, 120)};
  size_t k = 0;
  for (auto _ : state) {
    const Pose<double> flange =
        flange_pose<double>(model, PointMass{}, params.data(), joints[k].data());
    for (const Eigen::Vector3d& t : targets) {
      Eigen::Vector3d p = flange * t;
      benchmark::DoNotOptimize(p);
    }
    k = (k + 1) % joints.size();
  }
}
BENCHMARK(Kinematics_FkFlangeAnd3Targets);

// The same work with the nominal chain's precomputed twists (nominal_chain.hpp).
void Kinematics_NominalChainFkFlangeAnd3Targets(benchmark::State& state) {
  const RobotModel model = load_robot("abb-irb120");
  const NominalChain chain = make_nominal_chain(model);
  std::mt19937_64 rng(kSeed);
  const std::vector<Vector6d> joints = random_joints(model, rng, kInputs);
  const std::array<Eigen::Vector3d, 3> targets{
      Eigen::Vector3d(50, 0, 100), Eigen::Vector3d(-40, 60, 90), Eigen::Vector3d(0, -70, 120)};
  size_t k = 0;
  for (auto _ : state) {
    const Pose<double> flange = nominal_flange_pose(chain, joints[k]);
    for (const Eigen::Vector3d& t : targets) {
      Eigen::Vector3d p = flange * t;
      benchmark::DoNotOptimize(p);
    }
    k = (k + 1) % joints.size();
  }
}
BENCHMARK(Kinematics_NominalChainFkFlangeAnd3Targets);

void Kinematics_NominalIkAllSolutions(benchmark::State& state) {
  const RobotModel model = load_robot("abb-irb120");
  const OrthoParallelGeometry geometry = *analyze_ortho_parallel(model);
  std::mt19937_64 rng(kSeed);
  std::vector<Pose<double>> poses;
  for (const Vector6d& q : random_joints(model, rng, kInputs))
    poses.push_back(flange_pose(model, PointMass{}, model.nominal(), q));
  size_t k = 0;
  long solutions = 0;
  for (auto _ : state) {
    const IkResult result = nominal_ik(geometry, poses[k]);
    benchmark::DoNotOptimize(result.solutions.data());
    solutions += result.count;
    k = (k + 1) % poses.size();
  }
  state.counters["solutions_per_call"] =
      static_cast<double>(solutions) / static_cast<double>(state.iterations());
}
BENCHMARK(Kinematics_NominalIkAllSolutions);

// One configuration branch (nominal_ik_branch): the pose's own branch, seeded with its joints,
// as a compensation loop asks for it.
void Kinematics_NominalIkOneBranch(benchmark::State& state) {
  const RobotModel model = load_robot("abb-irb120");
  const OrthoParallelGeometry geometry = *analyze_ortho_parallel(model);
  std::mt19937_64 rng(kSeed);
  struct Case {
    Pose<double> pose;
    ArmConfig config;
    Vector6d seed;
  };
  std::vector<Case> cases;
  for (const Vector6d& q : random_joints(model, rng, kInputs))
    cases.push_back({flange_pose(model, PointMass{}, model.nominal(), q), arm_config(model, q), q});
  size_t k = 0;
  long solved = 0;
  for (auto _ : state) {
    const Case& c = cases[k];
    const IkBranchResult result = nominal_ik_branch(geometry, c.pose, c.config, c.seed);
    benchmark::DoNotOptimize(&result);
    solved += result.status == IkStatus::Solved;
    k = (k + 1) % cases.size();
  }
  state.counters["solved_fraction"] =
      static_cast<double>(solved) / static_cast<double>(state.iterations());
}
BENCHMARK(Kinematics_NominalIkOneBranch);

void Kinematics_NumericIkCalibrated(benchmark::State& state) {
  // A calibrated robot: seeded random errors of docs/method/03-error-model.md's size (0.5 mm,
  // 0.05°) and gravity compliance with a 2.6 kg payload; the target is its pose, the seed the
  // nominal solution.
  const RobotModel model = load_robot("abb-irb120");
  const OrthoParallelGeometry geometry = *analyze_ortho_parallel(model);
  std::mt19937_64 rng(kSeed);
  ParameterVector params = model.nominal();
  std::normal_distribution<double> length(0.0, 0.5), angle(0.0, deg2rad(0.05));
  for (int link = 2; link <= kJointCount; ++link) {
    params[link_param(link, 0)] += angle(rng);
    params[link_param(link, 1)] += length(rng);
    params[link_param(link, 2)] += angle(rng);
    params[link_param(link, 3)] += length(rng);
    params[compliance_param(link)] = 1e-7;
  }
  const PointMass payload{2.6, Eigen::Vector3d(50, 25, 100)};
  struct Case {
    Pose<double> target;
    Vector6d seed;
  };
  std::vector<Case> cases;
  for (const Vector6d& q : random_joints(model, rng, kInputs)) {
    const Pose<double> target = flange_pose(model, payload, params, q);
    const IkResult nominal = nominal_ik(geometry, target, q);
    if (const IkSolution* s = nearest_solution(nominal, q)) cases.push_back({target, s->joints});
  }
  size_t k = 0;
  long converged = 0;
  for (auto _ : state) {
    const NumericIkResult r = numeric_ik(model, payload, params, cases[k].target, cases[k].seed);
    converged += r.status == NumericIkStatus::Converged;
    benchmark::DoNotOptimize(r.joints.data());
    k = (k + 1) % cases.size();
  }
  state.counters["converged_fraction"] =
      static_cast<double>(converged) / static_cast<double>(state.iterations());
}
BENCHMARK(Kinematics_NumericIkCalibrated);

}  // namespace
}  // namespace robcal
