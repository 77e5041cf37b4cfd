/// `robcal axis-test plan|analyse`: the per-joint test (validate/axis_test.hpp): the moves of one
/// joint through its range from both sides, and the circle, errors and backlash of the
/// measured target positions.

#include <fmt/format.h>

#include <memory>
#include <tuple>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/units.hpp"
#include "robcal/validate/test_workflows.hpp"

namespace robcal::cli {
namespace {

struct AxisTestPlanOptions {
  std::string home, range, out;
  int joint = 1, steps = 12;
  double approach_deg = 5;
};

struct AnalyseOptions {
  std::string measurements;
  bool json = false;
};

void run_axis_test_plan(const AxisTestPlanOptions& o) {
  AxisTestPlanRequest request;
  request.home = parse_joints_deg(o.home, "--home");
  request.joint = o.joint - 1;
  const std::vector<double> range = parse_numbers(o.range, 2, "--range");
  request.from_rad = deg2rad(range[0]);
  request.to_rad = deg2rad(range[1]);
  request.steps = o.steps;
  request.approach_rad = deg2rad(o.approach_deg);
  (void)axis_test_plan_file(request, o.out);
  fmt::print(
      "axis test of joint {}: {} positions from {:g}° to {:g}°, each approached from {:g}° "
      "below and above; measure the target after every 'below'/'above' move\nwrote {}\n",
      o.joint, o.steps, range[0], range[1], o.approach_deg, o.out);
}

void run_analyse(const AnalyseOptions& o) {
  const AxisTestResult r = axis_test_analyse_file(o.measurements);
  if (o.json) {
    nlohmann::json out = axis_test_json(r);
    out["measurements"] = o.measurements;
    print_json(out);
    return;
  }
  fmt::print("axis test from {}: {} positions\n", o.measurements, r.samples);
  fmt::print(
      "  axis direction ({:.6f}, {:.6f}, {:.6f}) ± {:.4f}° through ({:.3f}, {:.3f}, {:.3f}) "
      "mm; radius {:.3f} mm; scale {:.5f}\n",
      r.axis_direction.x(), r.axis_direction.y(), r.axis_direction.z(), r.tilt_sigma_deg,
      r.axis_point_mm.x(), r.axis_point_mm.y(), r.axis_point_mm.z(), r.radius_mm, r.scale);
  fmt::print("  backlash {:.5f} ± {:.5f}° (1σ)\n", r.backlash_deg, r.backlash_sigma_deg);
  fmt::print("  error (mm)      mean |e|     max |e|       σ\n");
  for (const auto& [name, s, sigma] :
       {std::tuple{"tangential", r.tangential_mm, r.tangential_sigma_mm},
        std::tuple{"radial", r.radial_mm, r.radial_sigma_mm},
        std::tuple{"axial", r.axial_mm, r.axial_sigma_mm}})
    fmt::print("  {:<12} {:>10.4f}  {:>10.4f}  {:>8.4f}\n", name, s.mean, s.max, sigma);
}

const bool axis_test_registered = register_command(66, [](CLI::App& app) {
  auto* cmd = app.add_subcommand("axis-test",
                                 "Per-joint test: circle, tangential/radial/axial errors and "
                                 "backlash of one joint");
  cmd->require_subcommand(1);
  auto plan = std::make_shared<AxisTestPlanOptions>();
  auto* p = cmd->add_subcommand("plan", "The moves of one joint through a range, from both sides");
  p->add_option("--joint", plan->joint, "Joint 1..6")->required()->check(CLI::Range(1, 6));
  p->add_option("--home", plan->home, "The fixed joints j1..j6 (deg)")->required();
  p->add_option("--range", plan->range, "FROM,TO of the moving joint (deg)")->required();
  p->add_option("--steps", plan->steps, "Positions in the range")->capture_default_str();
  p->add_option("--approach", plan->approach_deg, "Approach distance (deg)")->capture_default_str();
  p->add_option("--out", plan->out, "Moves CSV (degrees)")->required();
  p->callback([plan] { run_axis_test_plan(*plan); });
  auto analyse = std::make_shared<AnalyseOptions>();
  auto* a = cmd->add_subcommand("analyse", "Fit the measured positions of one joint's test");
  a->add_option("--measurements", analyse->measurements,
                "CSV joint_deg,side,x,y,z (side: below or above; mm)")
      ->required();
  a->add_flag("--json", analyse->json, "Machine-readable output");
  a->callback([analyse] { run_analyse(*analyse); });
});

}  // namespace
}  // namespace robcal::cli
