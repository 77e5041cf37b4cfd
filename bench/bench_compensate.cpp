// Compensation speed (issue 7, BENCHMARKS.md): calibrated IK per target (31-parameter IRB 120
// model with compliance, Newton and pose shift, same inputs, interleaved in one binary),
// median and p99 per call computed inside the bench; the 100,000-pose round trip per robot;
// filtering a 100,000-target RAPID program.

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <map>

#include "../tests/test_compensate_support.hpp"
#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/compensate/program_filter.hpp"

namespace robcal {
namespace {

constexpr uint64_t kSeed = 2026;

struct IkCase {
  Pose<double> wanted;
  ArmConfig config;
  Vector6d near;
};

/// Targets ≥ 5° from the singularities (BENCHMARKS.md labels), each in the configuration
/// of the joints it was drawn from.
struct IkFixture {
  Compensator comp;
  std::vector<IkCase> cases;
  explicit IkFixture(const std::string& robot, int count) {
    std::mt19937_64 rng(kSeed);
    const CalibratedRobot calibrated = test::random_calibrated(robot, rng);
    comp = make_compensator(calibrated);
    while (static_cast<int>(cases.size()) < count) {
      const Vector6d q = test::random_joints(calibrated.model, rng);
      if (test::near_singular(calibrated.model, q)) continue;
      const Pose<double> wanted = calibrated_tcp_pose(comp.chain, q);
      const IkResult nominal = nominal_ik(
          comp.geometry, comp.world_T_base.inverse() * wanted * comp.flange_T_tcp.inverse(), q);
      const IkSolution* own = nearest_solution(nominal, q);
      if (!own) continue;  // the nominal seed is beyond a joint limit
      cases.push_back({wanted, own->config, q});
    }
  }
};

const IkFixture& irb120_fixture() {
  static const IkFixture fixture("abb-irb120", 1000);
  return fixture;
}

void calibrated_ik_bench(benchmark::State& state, IkMethod method) {
  const IkFixture& f = irb120_fixture();
  size_t i = 0;
  for (auto _ : state) {
    const IkCase& c = f.cases[i];
    benchmark::DoNotOptimize(calibrated_ik(f.comp, c.wanted, c.config, c.near, method));
    i = (i + 1) % f.cases.size();
  }
  // Per-call distribution and success, timed call by call on the same inputs.
  std::vector<double> ns;
  int ok = 0, iterations = 0;
  for (const IkCase& c : f.cases) {
    const auto t0 = std::chrono::steady_clock::now();
    const CalibratedIkResult r = calibrated_ik(f.comp, c.wanted, c.config, c.near, method);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(r);
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
    ok += r.ok();
    iterations += r.iterations;
  }
  std::sort(ns.begin(), ns.end());
  state.counters["median_us"] = ns[ns.size() / 2] * 1e-3;
  state.counters["p99_us"] = ns[ns.size() * 99 / 100] * 1e-3;
  state.counters["success_pct"] = 100.0 * ok / static_cast<double>(f.cases.size());
  state.counters["mean_iterations"] = iterations / static_cast<double>(f.cases.size());
}

void BM_CalibratedIkNewton(benchmark::State& state) {
  calibrated_ik_bench(state, IkMethod::Newton);
}
void BM_CalibratedIkPoseShift(benchmark::State& state) {
  calibrated_ik_bench(state, IkMethod::PoseShift);
}
BENCHMARK(BM_CalibratedIkNewton);
BENCHMARK(BM_CalibratedIkPoseShift);

/// The nominal closed form alone: the seed's share of the calibrated IK time.
void BM_NominalSeed(benchmark::State& state) {
  const IkFixture& f = irb120_fixture();
  size_t i = 0;
  for (auto _ : state) {
    const IkCase& c = f.cases[i];
    benchmark::DoNotOptimize(
        nominal_solution(f.comp, f.comp.world_T_base.inverse() * c.wanted, c.config, c.near));
    i = (i + 1) % f.cases.size();
  }
}
BENCHMARK(BM_NominalSeed);

/// Round trip over 100,000 random poses per robot (≥ 5° from singularities): every
/// configuration the nominal inverse offers (≥ 10° from singularities) solved by both
/// iterations; counters: successes, worst errors, disagreement, counts per configuration.
void BM_RoundTrip100k(benchmark::State& state) {
  const std::string robot = test::kRobots[state.range(0)];
  constexpr int kPoses = 100000;
  for (auto _ : state) {
    std::mt19937_64 rng(kSeed + static_cast<uint64_t>(state.range(0)));
    const CalibratedRobot calibrated = test::random_calibrated(robot, rng);
    const Compensator comp = make_compensator(calibrated);
    std::map<int, int> per_config;
    long solves = 0, converged = 0, drawn_ok = 0, drawn = 0, skipped_limits = 0;
    int max_newton = 0, max_shift = 0;
    double worst_mm = 0, worst_deg = 0, worst_agree = 0;
    while (drawn < kPoses) {
      const Vector6d q = test::random_joints(calibrated.model, rng);
      if (test::near_singular(calibrated.model, q)) continue;
      ++drawn;
      const Pose<double> wanted = calibrated_tcp_pose(comp.chain, q);
      const IkResult nominal = nominal_ik(
          comp.geometry, comp.world_T_base.inverse() * wanted * comp.flange_T_tcp.inverse(), q);
      std::map<int, const IkSolution*> one_per_config;
      for (const IkSolution& s : nominal) one_per_config.emplace(s.config.index(), &s);
      const IkSolution* own = nearest_solution(nominal, q);
      for (const auto& [index, s] : one_per_config) {
        const bool is_own = own && s->config == own->config;
        if (!is_own && test::near_singular(calibrated.model, s->joints, 10)) continue;
        const auto newton = calibrated_ik(comp, wanted, s->config, is_own ? q : s->joints);
        const auto shift =
            calibrated_ik(comp, wanted, s->config, is_own ? q : s->joints, IkMethod::PoseShift);
        if (!calibrated.model.within_limits(newton.joints, -1e-3)) {
          ++skipped_limits;
          continue;
        }
        solves += 2;
        converged += newton.ok() + shift.ok();
        if (is_own) drawn_ok += newton.ok() && shift.ok();
        if (!newton.ok() || !shift.ok()) continue;
        for (const CalibratedIkResult* r : {&newton, &shift}) {
          const Pose<double> reached = calibrated_tcp_pose(comp.chain, r->joints);
          worst_mm = std::max(worst_mm, (reached.p - wanted.p).norm());
          worst_deg = std::max(
              worst_deg, rad2deg(Eigen::AngleAxisd(reached.R.transpose() * wanted.R).angle()));
        }
        worst_agree = std::max(worst_agree, (newton.joints - shift.joints).cwiseAbs().maxCoeff());
        max_newton = std::max(max_newton, newton.iterations);
        max_shift = std::max(max_shift, shift.iterations);
        ++per_config[index];
      }
    }
    state.counters["poses"] = drawn;
    state.counters["drawn_config_success_pct"] = 100.0 * drawn_ok / static_cast<double>(drawn);
    state.counters["solves"] = static_cast<double>(solves);
    state.counters["success_pct"] = 100.0 * converged / static_cast<double>(solves);
    state.counters["skipped_limits"] = static_cast<double>(skipped_limits);
    state.counters["worst_mm"] = worst_mm;
    state.counters["worst_deg"] = worst_deg;
    state.counters["worst_disagreement_rad"] = worst_agree;
    state.counters["max_newton_iterations"] = max_newton;
    state.counters["max_shift_iterations"] = max_shift;
    for (const auto& [index, n] : per_config) state.counters[fmt::format("config{}", index)] = n;
  }
}
BENCHMARK(BM_RoundTrip100k)
    ->DenseRange(0, 2)
    ->Iterations(1)
    ->Repetitions(1)
    ->Unit(benchmark::kSecond);

/// Filtering a RAPID module of 100,000 robtargets (a fixed shift as the corrector: the
/// parsing and rewriting cost alone) and with the calibrated IK as the corrector.
std::string big_program(int targets) {
  std::string text = "MODULE Big\n";
  for (int i = 0; i < targets; ++i)
    text += fmt::format(
        "  CONST robtarget p{}:=[[{:.3f},{:.3f},{:.3f}],[0,0.7071068,0.7071068,0],[0,0,-1,1],"
        "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];  ! point {}\n",
        i, 350.0 + (i % 100) * 0.5, -100.0 + (i % 200) * 0.25, 300.0 + (i % 50), i);
  return text + "ENDMODULE\n";
}

void BM_FilterProgram100k(benchmark::State& state) {
  const std::string text = big_program(100000);
  for (auto _ : state) {
    const auto result =
        filter_program(text, ProgramLanguage::Rapid, "big.mod", {}, [](const ProgramPoint& p) {
          CorrectedPoint c;
          c.base_T_tcp = p.base_T_tcp;
          c.base_T_tcp.p.x() += 0.25;
          return c;
        });
    benchmark::DoNotOptimize(result.text.data());
  }
  state.counters["bytes"] = static_cast<double>(text.size());
}
BENCHMARK(BM_FilterProgram100k)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace robcal
