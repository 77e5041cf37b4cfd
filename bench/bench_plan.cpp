// The `plan` workflow at scale (issue 21 item 7): 50,000 random candidates on the IRB 120 in the
// simulator's cell, drawn and scored in streaming batches (design/calibration_planning.hpp),
// 40 configurations chosen, D-optimal (no task region) and I-optimal over a TCP box. Goal:
// ≤ 1 s and < 100 MB. max_rss_MB is the process's peak, so run each alone:
//   build/robcal_bench --benchmark_filter='Plan50000/0'
//   build/robcal_bench --benchmark_filter='Plan50000/1'
// The time reported is CPU time of the calling thread's process (the D-optimal descents use a
// second thread; Google Benchmark's CPU time counts the main thread only, so `cpu_s_process`
// gives getrusage's user + system time of the whole process for the plan).

#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include "robcal/design/calibration_planning.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal {
namespace {

double process_cpu_s() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto s = [](const timeval& t) { return static_cast<double>(t.tv_sec) + t.tv_usec * 1e-6; };
  return s(usage.ru_utime) + s(usage.ru_stime);
}

void BM_Plan50000(benchmark::State& state) {
  PlanRequest request;
  request.model = load_robot("abb-irb120");
  request.tool = default_simulation_tool();
  request.candidates = 50000;
  request.count = 40;
  request.task_count = 200;
  if (state.range(0) == 1) request.task_box = TaskBox{{-500, 1100, 150}, {-300, 1300, 350}};
  PlanResult r;
  double cpu = 0;
  for (auto _ : state) {
    const double before = process_cpu_s();
    r = plan_calibration(request);
    cpu = process_cpu_s() - before;
    benchmark::DoNotOptimize(r.configurations.data());
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["max_rss_MB"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
  state.counters["cpu_s_process"] = cpu;
  state.counters["candidates"] = r.candidates;
  state.counters["pooled"] = r.pooled;
  state.counters["predicted_mean_um"] = 1000 * r.predicted_selected.mean_mm;
}
BENCHMARK(BM_Plan50000)
    ->ArgName("task_box")
    ->Arg(0)
    ->Arg(1)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace robcal
