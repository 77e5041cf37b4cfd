// Several base-fixture placements in one calibration (issue 20 item 1, docs/method/08-world-frame.md
// §4): the planner's best single placement against the planner's next placement added to it, at the
// same number of configurations (legs), simulated with one true robot and validated against it over
// the whole workspace.

#include <gtest/gtest.h>

#include "refusal.hpp"
#include "robcal/hexapod/placement_search.hpp"
#include "robcal/hexapod/placements_simulation.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal::hexapod {
namespace {

struct Comparison {
  int single_configurations = 0, pair_configurations = 0;
  PlacementsSimulation single, pair;
  double predicted_single_mm = 0, predicted_pair_mm = 0;
};

Comparison compare(const std::string& robot, uint64_t seed, const std::vector<std::string>& effects) {
  const RobotModel model = load_robot(robot);
  PlacementSearchRequest request;
  request.plan.robot = robot;
  request.plan.gauge.range_mm = 5;  // every planned configuration readable on the true robot
  request.x_mm = {350, 500};
  request.y_mm = {-300, 0, 300};
  request.z_mm = {150, 300};
  request.yaw_deg = {0, 90};
  request.validation_configurations = 500;
  request.seed = seed;
  const PlacementSearchResult singles = search_placements(model, request);
  const PlacementScore& best = singles.ranked.front();
  HexapodPlanRequest plan_request = request.plan;
  plan_request.placement = best.placement;
  const HexapodPlan first = plan_hexapod(model, plan_request);
  request.measured = {measured_placement(first, "first")};
  const PlacementSearchResult next = search_placements(model, request);
  EXPECT_FALSE(next.next.empty());
  plan_request.placement = next.ranked[next.next.front().rank].placement;
  const HexapodPlan second = plan_hexapod(model, plan_request);
  const int count = static_cast<int>(first.session.configurations.size());
  const PlacementsDesign design = design_placements(model, {first, second}, count, request);

  Comparison c;
  c.predicted_single_mm = best.predicted_mean_mm;
  c.predicted_pair_mm = design.predicted_mean_mm;
  auto rng = test::seeded_rng(seed);
  const PointMass payload{2.6, Eigen::Vector3d(50, 25, 100)};
  TrueRobot truth = levelled_random_truth(model, payload, ErrorBounds{0.3, 0.1, 0.05e-6, 1.0, 0.1}, rng);
  enable_effects(truth, effects, rng);
  PlacementsSimulationOptions options;
  auto rng_single = test::seeded_rng(seed + 100), rng_pair = test::seeded_rng(seed + 100);
  c.single = simulate_placements(model, truth, payload, {{first, {}}}, options, rng_single);
  c.pair = simulate_placements(model, truth, payload, {{first, design.chosen[0]}, {second, design.chosen[1]}},
                               options, rng_pair);
  std::printf(
      "%s seed %llu effects %zu: single %s %d configs: predicted %.5f, achieved %.5f mean / %.5f max "
      "(nominal %.3f); pair + %s (%zu + %zu): predicted %.5f, achieved %.5f / %.5f; rms %.5f / %.5f\n",
      robot.c_str(), static_cast<unsigned long long>(seed), effects.size(),
      placement_text(best.placement).c_str(), c.single.configurations, c.predicted_single_mm,
      c.single.calibrated.mean, c.single.calibrated.max, c.single.nominal.mean,
      placement_text(plan_request.placement).c_str(), design.chosen[0].size(),
      design.chosen[1].size(), c.predicted_pair_mm, c.pair.calibrated.mean, c.pair.calibrated.max,
      c.single.fit_rms_mm, c.pair.fit_rms_mm);
  return c;
}

TEST(HexapodPlacements, TwoPlannedPlacementsAgainstTheBestSingleOne) {
  for (const char* robot : {"fanuc-lrmate200ic", "abb-irb120"})
    for (uint64_t seed : {1, 2, 3}) compare(robot, seed, {});
}

}  // namespace
}  // namespace robcal::hexapod
