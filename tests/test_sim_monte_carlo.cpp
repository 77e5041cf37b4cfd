// Monte Carlo of simulated calibrations: the observed accuracy against the Cramér–Rao
// prediction (an efficient estimator gives a ratio of 1), the first-order validation against
// the exact forward kinematics, and identical results on 1 and 2 threads.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "robcal/io/robot_file.hpp"
#include "robcal/sim/monte_carlo.hpp"

namespace robcal {
namespace {

struct Fixture {
  RobotModel model = load_robot("abb-irb120");
  Tool tool = default_simulation_tool();
  TrueRobot truth = published_irb120_truth(model, tool);
  VirtualInstrument tracker = standard_instrument(InstrumentKind::LaserTracker, truth, 0.02);
  MonteCarloOptions options;
  MonteCarloSetup setup;
  Fixture() {
    options.runs = 200;
    options.poses = 40;
    options.validation = 300;
    options.optimal_plan = false;
    options.seed = 3;
    setup = prepare_monte_carlo(truth, tracker, model, tool, options);
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

TEST(SimMonteCarlo, AccuracyMatchesTheCramerRaoPrediction) {
  const Fixture& f = fixture();
  const MonteCarloResult result = run_monte_carlo(f.setup, f.options);
  EXPECT_EQ(result.failed, 0);
  // 200 runs × 300 configurations: the RMS is known to about ±1 % (one standard error), so an
  // efficient estimator lands within ±5 % of the prediction; the requirement is ≤ 1.03 at 1000.
  EXPECT_NEAR(result.ratio, 1.0, 0.05) << "observed " << result.observed_rms_mm << " mm, predicted "
                                       << f.setup.predicted.rms_mm << " mm";
  EXPECT_GT(f.setup.predicted.rms_mm, 0.001);
  EXPECT_LT(f.setup.predicted.rms_mm, 0.1);
}

TEST(SimMonteCarlo, FirstOrderValidationMatchesExactKinematics) {
  const Fixture& f = fixture();
  // The same runs validated both ways: the first-order map differs from the exact forward
  // kinematics by the second-order remainder, |δp|² scale (a few 1e-6 mm here); stated
  // tolerance 1e-5 mm on every run's RMS, mean and maximum, against errors of ≈0.01 mm (0.1 %).
  MonteCarloOptions options = f.options;
  options.runs = 20;
  const MonteCarloResult first_order = run_monte_carlo(f.setup, options);
  options.validation_model = ValidationModel::Exact;
  const MonteCarloResult exact = run_monte_carlo(f.setup, options);
  double worst = 0;
  for (size_t r = 0; r < exact.runs.size(); ++r) {
    ASSERT_TRUE(exact.runs[r].converged);
    EXPECT_GT(exact.runs[r].rms_mm, 1e-3);  // a real error to compare
    worst = std::max({worst, std::abs(first_order.runs[r].rms_mm - exact.runs[r].rms_mm),
                      std::abs(first_order.runs[r].mean_mm - exact.runs[r].mean_mm),
                      std::abs(first_order.runs[r].max_mm - exact.runs[r].max_mm)});
  }
  EXPECT_LT(worst, 1e-5);
  EXPECT_NEAR(first_order.ratio, exact.ratio, 1e-4);

  // And the exact mode against an independent computation: the templated FK of the fitted and
  // of the true robot at the validation configurations as prepare_monte_carlo drew them.
  const ParameterVector fitted = monte_carlo_fit(f.setup, f.options.seed, 7);
  ASSERT_TRUE(fitted.allFinite());
  std::mt19937_64 rng(f.options.seed + 2);
  RandomConfigurationOptions random_options;
  random_options.box = published_joint_box(f.model);
  random_options.name_prefix = "V";
  const auto configs =
      random_configurations(f.truth, f.tracker, f.options.validation, rng, random_options);
  double sum_sq = 0;
  for (const PlannedConfiguration& c : configs) {
    const Eigen::Vector3d& t = f.tool.targets[static_cast<size_t>(c.target)].position_mm;
    sum_sq += (flange_pose(f.model, f.tool.payload, fitted, c.joints) * t -
               true_flange_pose(f.truth, c.joints) * t)
                  .squaredNorm();
  }
  const MonteCarloRun run = validate_monte_carlo_run(f.setup, fitted, ValidationModel::Exact);
  EXPECT_NEAR(run.rms_mm, std::sqrt(sum_sq / static_cast<double>(configs.size())), 1e-10);
}

TEST(SimMonteCarlo, SameResultsOnOneAndTwoThreads) {
  const Fixture& f = fixture();
  MonteCarloOptions options = f.options;
  options.runs = 24;
  options.threads = 1;
  const MonteCarloResult one = run_monte_carlo(f.setup, options);
  options.threads = 2;
  const MonteCarloResult two = run_monte_carlo(f.setup, options);
  ASSERT_EQ(one.runs.size(), two.runs.size());
  for (size_t r = 0; r < one.runs.size(); ++r) {
    EXPECT_EQ(one.runs[r].rms_mm, two.runs[r].rms_mm) << r;
    EXPECT_EQ(one.runs[r].max_mm, two.runs[r].max_mm) << r;
  }
  EXPECT_EQ(one.observed_rms_mm, two.observed_rms_mm);
  EXPECT_EQ(one.ratio, two.ratio);
}

}  // namespace
}  // namespace robcal
