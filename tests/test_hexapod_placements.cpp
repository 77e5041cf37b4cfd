// Several base-fixture placements in one calibration (issue 20 item 1,
// docs/method/08-world-frame.md §4), simulated with one true robot and validated against it (no
// instrument noise) over the whole workspace: the planner's best single placement (all its
// configurations, N) against two placements — the planner's next placement added to it — at the
// same N configurations (6N legs), split between them by the I-optimal design over both, and every
// other configuration of each. The two-placement fit must reach the gauge noise (a world frame
// shared by mistake would leave millimetres), and the figures are printed for the report. The
// issue's expectation (two placements ≥ 30 % better at equal count) is what the printed ratio is
// compared with; see the report.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <numeric>

#include <fmt/format.h>

#include "refusal.hpp"
#include "robcal/hexapod/placement_search.hpp"
#include "robcal/hexapod/placements_simulation.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal::hexapod {
namespace {

struct TwoPlacements {
  PlacementSearchRequest request;
  PlacementScore best;
  HexapodPlan first, second;
  PlacementsDesign split;  ///< I-optimal, N configurations over both
  PlacementSearchResult next;
};

TwoPlacements plan_two(const RobotModel& model, const std::string& robot,
                       const std::vector<std::string>& identify = {}) {
  TwoPlacements t;
  PlacementSearchRequest& request = t.request;
  request.identify = identify;
  request.plan.robot = robot;
  request.plan.gauge.range_mm = 5;  // every planned configuration readable on the true robot
  request.x_mm = {350, 500};
  request.y_mm = {-300, 0, 300};
  request.z_mm = {150, 300};
  request.yaw_deg = {0, 90};
  request.validation_configurations = 300;
  request.seed = 3;
  const PlacementSearchResult singles = search_placements(model, request);
  t.best = singles.ranked.front();
  HexapodPlanRequest plan_request = request.plan;
  plan_request.placement = t.best.placement;
  t.first = plan_hexapod(model, plan_request);
  request.measured = {measured_placement(t.first, "first")};
  t.next = search_placements(model, request);
  EXPECT_FALSE(t.next.next.empty());
  plan_request.placement = t.next.ranked[t.next.next.front().rank].placement;
  t.second = plan_hexapod(model, plan_request);
  t.split = design_placements(model, {t.first, t.second},
                              static_cast<int>(t.first.session.configurations.size()), request);
  return t;
}

struct Figures {
  PlacementsSimulation single, split, alternate;
  PlacementsSimulation both;  ///< every configuration of both placements (2 N), when asked
};

/// One seeded true robot, with `effects` and `periodic_deg` on every periodic harmonic term of
/// every joint, on which any design is simulated with the same set-up and noise draws.
struct TrueRobotTrial {
  const RobotModel* model;
  uint64_t seed;
  PointMass payload{2.6, Eigen::Vector3d(50, 25, 100)};
  TrueRobot truth;
  PlacementsSimulationOptions options;

  [[nodiscard]] PlacementsSimulation run(const std::vector<SimulatedPlacement>& placements) const {
    auto readings = test::seeded_rng(seed + 2);
    return simulate_placements(*model, truth, payload, placements, options, readings);
  }
};

TrueRobotTrial true_robot_trial(const RobotModel& model, const TwoPlacements& t, uint64_t seed,
                                const std::vector<std::string>& effects, double periodic_deg) {
  TrueRobotTrial trial{&model, seed};
  auto rng = test::seeded_rng(seed);
  trial.truth =
      levelled_random_truth(model, trial.payload, ErrorBounds{0.3, 0.1, 0.05e-6, 1.0, 0.1}, rng);
  enable_effects(trial.truth, effects, rng);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int joint = 1; joint <= kJointCount && periodic_deg > 0; ++joint)
    for (int k = 0; k < kPeriodicPerJoint; ++k)
      trial.truth.robot.params[periodic_param(joint, 1, false) + k] =
          deg2rad(periodic_deg) * unit(rng);
  trial.options.identify = t.request.identify;
  trial.options.validation_configurations = 1000;
  trial.options.validation_seed = seed + 1;
  return trial;
}

Figures simulate(const RobotModel& model, const TwoPlacements& t, uint64_t seed,
                 bool with_both = false, const std::vector<std::string>& effects = {},
                 double periodic_deg = 0) {
  const TrueRobotTrial trial = true_robot_trial(model, t, seed, effects, periodic_deg);
  const auto run = [&trial](const std::vector<SimulatedPlacement>& placements) {
    return trial.run(placements);
  };
  // Every other configuration of each placement: N/2 + N/2.
  const int n = static_cast<int>(t.first.session.configurations.size());
  const int m = static_cast<int>(t.second.session.configurations.size());
  std::vector<int> odd, even;
  for (int k = 0; k < n; k += 2) odd.push_back(k);
  for (int start : {0, 1})  // every other of the second, then the rest, up to N in all
    for (int k = start; k < m && static_cast<int>(odd.size() + even.size()) < n; k += 2)
      even.push_back(k);
  std::sort(even.begin(), even.end());
  Figures f;
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  f.single = run({{t.first, all}});
  f.split = run({{t.first, t.split.chosen[0]}, {t.second, t.split.chosen[1]}});
  f.alternate = run({{t.first, odd}, {t.second, even}});
  EXPECT_EQ(f.alternate.configurations, n);
  if (with_both) {
    std::vector<int> second(m);
    std::iota(second.begin(), second.end(), 0);
    f.both = run({{t.first, all}, {t.second, second}});
  }
  return f;
}

TEST(HexapodPlacements, TwoPlacementsCalibrateTogetherAndArePlannedAgainstTheBestSingleOne) {
  for (const char* robot : {"fanuc-lrmate200ic", "abb-irb120"}) {
    SCOPED_TRACE(robot);
    const RobotModel model = load_robot(robot);
    const TwoPlacements t = plan_two(model, robot);
    const int n = static_cast<int>(t.first.session.configurations.size());
    // The next placement: apart from the first, and with all its configurations it predicts
    // better than the first alone.
    const NextPlacement& next = t.next.next.front();
    EXPECT_NE(t.next.ranked[next.rank].placement, t.best.placement);
    EXPECT_LT(next.predicted_mean_mm, t.next.measured_mean_mm);
    EXPECT_NEAR(t.next.measured_mean_mm, t.best.predicted_mean_mm, 1e-9);
    // The I-optimal split at N configurations predicts no worse than the single placement's N.
    EXPECT_EQ(static_cast<int>(t.split.chosen[0].size() + t.split.chosen[1].size()), n);
    EXPECT_LE(t.split.predicted_mean_mm, 1.02 * t.best.predicted_mean_mm);

    const Figures f = simulate(model, t, 11);
    for (const PlacementsSimulation* s : {&f.single, &f.split, &f.alternate}) {
      EXPECT_TRUE(s->converged);
      EXPECT_LT(s->fit_rms_mm, 1.2 * PlacementsSimulationOptions{}.sigma_mm);
      EXPECT_LT(s->calibrated.mean, 0.01 * s->nominal.mean);
    }
    std::printf(
        "%s: best single %s, %d configurations: predicted %.5f, achieved %.5f mean / %.5f max "
        "(nominal %.3f)\n  next placement %s: I-optimal split %zu + %zu predicted %.5f, achieved "
        "%.5f / %.5f (ratio %.2f); every other of each %d: achieved %.5f / %.5f (ratio %.2f)\n",
        robot, placement_text(t.best.placement).c_str(), n, t.best.predicted_mean_mm,
        f.single.calibrated.mean, f.single.calibrated.max, f.single.nominal.mean,
        placement_text(t.next.ranked[next.rank].placement).c_str(), t.split.chosen[0].size(),
        t.split.chosen[1].size(), t.split.predicted_mean_mm, f.split.calibrated.mean,
        f.split.calibrated.max, f.split.calibrated.mean / f.single.calibrated.mean,
        f.alternate.configurations, f.alternate.calibrated.mean, f.alternate.calibrated.max,
        f.alternate.calibrated.mean / f.single.calibrated.mean);
  }
}

// The slower version (run with --gtest_also_run_disabled_tests): eight true robots per arm, the
// mean ratio of the two-placement designs' whole-workspace error to the single placement's.
TEST(HexapodPlacements, DISABLED_TwoPlacementsOverEightTrueRobots) {
  for (const char* robot : {"fanuc-lrmate200ic", "abb-irb120"}) {
    const RobotModel model = load_robot(robot);
    const TwoPlacements t = plan_two(model, robot);
    double split = 0, alternate = 0, better = 0, both = 0, registered_alternate = 0,
           registered_both = 0;
    const int seeds = 8;
    for (int seed = 1; seed <= seeds; ++seed) {
      const Figures f = simulate(model, t, static_cast<uint64_t>(seed) * 100, true);
      EXPECT_LT(f.both.fit_rms_mm, 1.2 * PlacementsSimulationOptions{}.sigma_mm);
      both += f.both.calibrated.mean / f.single.calibrated.mean / seeds;
      registered_alternate += f.alternate.registered.mean / f.single.registered.mean / seeds;
      registered_both += f.both.registered.mean / f.single.registered.mean / seeds;
      split += f.split.calibrated.mean / f.single.calibrated.mean / seeds;
      alternate += f.alternate.calibrated.mean / f.single.calibrated.mean / seeds;
      better += f.alternate.calibrated.mean < 0.7 * f.single.calibrated.mean ? 1 : 0;
    }
    std::printf(
        "%s, %d true robots: mean ratio to the single placement: I-optimal split (%zu + %zu) %.2f, "
        "every other of each %.2f (≥ 30 %% better in %g of %d); all of both (2 N) %.2f; after a "
        "rigid best fit: every other of each %.2f, all of both %.2f\n",
        robot, seeds, t.split.chosen[0].size(), t.split.chosen[1].size(), split, alternate, better,
        seeds, both, registered_alternate, registered_both);
  }
}

// With effects the model does not contain (a joint-6 gear error and masses 10 % off), the
// extrapolation from one placement to the whole workspace is what a second placement could
// improve: four true robots per arm, each design's whole-workspace mean against the single
// placement's (run with --gtest_also_run_disabled_tests; the figures are in the note).
TEST(HexapodPlacements, DISABLED_TwoPlacementsWithUnmodelledEffects) {
  for (const char* robot : {"fanuc-lrmate200ic", "abb-irb120"}) {
    const RobotModel model = load_robot(robot);
    const TwoPlacements t = plan_two(model, robot);
    for (int seed = 1; seed <= 4; ++seed) {
      const Figures f = simulate(model, t, static_cast<uint64_t>(seed) * 100, false,
                                 {"j6-periodic", "mass-error"});
      std::printf(
          "%s, true robot %d: single %.5f mm (fit rms %.5f); I-optimal split %.5f; every other "
          "of each %.5f (fit rms %.5f): ratios %.2f, %.2f\n",
          robot, seed, f.single.calibrated.mean, f.single.fit_rms_mm, f.split.calibrated.mean,
          f.alternate.calibrated.mean, f.alternate.fit_rms_mm,
          f.split.calibrated.mean / f.single.calibrated.mean,
          f.alternate.calibrated.mean / f.single.calibrated.mean);
    }
  }
}

/// The best single placement's I-optimal `count` configurations against the I-optimal `count`
/// over it and the planner's next placement, each true robot carrying `periodic_deg` on every
/// periodic harmonic term of every joint: the means of the whole-workspace error over `robots`
/// true robots.
struct CountComparison {
  PlacementsDesign single, split;
  double single_mean_mm = 0, split_mean_mm = 0;
  bool converged = true;
  double worst_fit_rms_mm = 0;
};

CountComparison compare_at_count(const RobotModel& model, const TwoPlacements& t, int count,
                                 double periodic_deg, int robots) {
  CountComparison c;
  c.single = design_placements(model, {t.first}, count, t.request);
  c.split = design_placements(model, {t.first, t.second}, count, t.request);
  for (int robot = 1; robot <= robots; ++robot) {
    const TrueRobotTrial trial =
        true_robot_trial(model, t, static_cast<uint64_t>(robot) * 100, {}, periodic_deg);
    const auto run = [&](const std::vector<SimulatedPlacement>& placements) {
      const PlacementsSimulation s = trial.run(placements);
      c.converged = c.converged && s.converged;
      c.worst_fit_rms_mm = std::max(c.worst_fit_rms_mm, s.fit_rms_mm);
      return s.calibrated.mean / robots;
    };
    c.single_mean_mm += run({{t.first, c.single.chosen[0]}});
    c.split_mean_mm += run({{t.first, c.split.chosen[0]}, {t.second, c.split.chosen[1]}});
  }
  return c;
}

// Joint-dependent errors the calibration identifies (the periodic group, 0.005° per harmonic
// term of every joint, docs/method/03-error-model.md §5) need the joint ranges that several
// placements visit. Eight simulated true robots per arm: the planner's two placements, with the
// configurations split between them (I-optimal, started from equal shares: one-at-a-time steps
// never leave the first placement), are at least 30 % below the best single placement at the
// same count. IRB 120: all 84 configurations of its best placement (measured 0.0244 against
// 0.0511 mm). LR Mate 200iC: the published count, 46 (measured 0.0031 against 0.0047 mm); with
// all its 180 the single placement reaches the fixture-side floor and the split gains 6 %
// (DISABLED_TwoPlacementsWithJointPeriodicErrorsBothArms; other counts in
// DISABLED_TwoPlacementsAtSeveralCounts).
TEST(HexapodPlacements, JointPeriodicErrorsMakeTheSecondPlacementPayOff) {
  for (const auto& [robot, published_count] :
       {std::pair<const char*, int>{"abb-irb120", 0}, {"fanuc-lrmate200ic", 46}}) {
    SCOPED_TRACE(robot);
    const RobotModel model = load_robot(robot);
    const TwoPlacements t = plan_two(model, robot, {"periodic"});
    const int count = published_count > 0 ? published_count
                                          : static_cast<int>(t.first.session.configurations.size());
    const CountComparison c = compare_at_count(model, t, count, 0.005, 8);
    EXPECT_EQ(static_cast<int>(c.split.chosen[0].size() + c.split.chosen[1].size()), count);
    EXPECT_GE(c.split.chosen[1].size(), 6u);  // a second placement worth its world frame
    EXPECT_LT(c.split.predicted_mean_mm, 0.85 * c.single.predicted_mean_mm);
    EXPECT_TRUE(c.converged);
    EXPECT_LT(c.worst_fit_rms_mm, 1.2 * PlacementsSimulationOptions{}.sigma_mm);
    std::printf(
        "%s with the periodic group, %d configurations: best single %s predicted %.4f, achieved "
        "%.4f mm; split %zu + %zu with %s predicted %.4f, achieved %.4f mm (ratio %.2f)\n",
        robot, count, placement_text(t.best.placement).c_str(), c.single.predicted_mean_mm,
        c.single_mean_mm, c.split.chosen[0].size(), c.split.chosen[1].size(),
        placement_text(t.second.cell->placement).c_str(), c.split.predicted_mean_mm,
        c.split_mean_mm, c.split_mean_mm / c.single_mean_mm);
    EXPECT_LT(c.split_mean_mm, 0.7 * c.single_mean_mm);
  }
}

TEST(HexapodPlacements, DISABLED_TwoPlacementsWithJointPeriodicErrorsBothArms) {
  for (const char* robot : {"abb-irb120", "fanuc-lrmate200ic"}) {
    const RobotModel model = load_robot(robot);
    const TwoPlacements t = plan_two(model, robot, {"periodic"});
    std::printf("%s: best %s predicted %.5f; next %s; split %zu + %zu predicted %.5f\n", robot,
                placement_text(t.best.placement).c_str(), t.best.predicted_mean_mm,
                placement_text(t.next.ranked[t.next.next.front().rank].placement).c_str(),
                t.split.chosen[0].size(), t.split.chosen[1].size(), t.split.predicted_mean_mm);
    double single = 0, split = 0, alternate = 0, both = 0;
    for (int seed = 1; seed <= 8; ++seed) {
      const Figures f = simulate(model, t, static_cast<uint64_t>(seed) * 100, true, {}, 0.005);
      single += f.single.calibrated.mean / 8;
      split += f.split.calibrated.mean / 8;
      alternate += f.alternate.calibrated.mean / 8;
      both += f.both.calibrated.mean / 8;
    }
    std::printf(
        "  means over 8 true robots: single %.5f, split %.5f (%.2f), every other of each "
        "%.5f (%.2f), all of both %.5f (%.2f)\n",
        single, split, split / single, alternate, alternate / single, both, both / single);
  }
}

// The split against the single placement at several counts, with and without the periodic
// group, eight true robots per arm (run with --gtest_also_run_disabled_tests).
TEST(HexapodPlacements, DISABLED_TwoPlacementsAtSeveralCounts) {
  for (const char* robot : {"fanuc-lrmate200ic", "abb-irb120"}) {
    const RobotModel model = load_robot(robot);
    for (const double periodic_deg : {0.0, 0.005}) {
      const TwoPlacements t = plan_two(
          model, robot,
          periodic_deg > 0 ? std::vector<std::string>{"periodic"} : std::vector<std::string>{});
      for (const int count : {30, 46, 60, 84}) {
        const CountComparison c = compare_at_count(model, t, count, periodic_deg, 8);
        std::printf(
            "%s %s, %d configurations: single predicted %.5f achieved %.5f; split %zu + %zu "
            "predicted %.5f achieved %.5f (ratio %.2f)\n",
            robot, periodic_deg > 0 ? "periodic" : "kinematic", count, c.single.predicted_mean_mm,
            c.single_mean_mm, c.split.chosen[0].size(), c.split.chosen[1].size(),
            c.split.predicted_mean_mm, c.split_mean_mm, c.split_mean_mm / c.single_mean_mm);
      }
    }
  }
}

TEST(HexapodPlacements, MeasuredPlacementsGivenTwiceAreRefused) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  PlacementSearchRequest request;
  HexapodPlanRequest plan_request;
  const HexapodPlan plan = plan_hexapod(model, plan_request);
  request.measured = {measured_placement(plan, "a.json"), measured_placement(plan, "b.json")};
  EXPECT_REFUSED(
      search_placements(model, request), InputError,
      "b.json (--measured): this placement overlaps the one of a.json: its base cup B1 is "
      "0.0 mm from their B1");
  // 10 mm apart: still within a cup diameter.
  plan_request.placement[0] += 10;
  request.measured[1] = measured_placement(plan_hexapod(model, plan_request), "b.json");
  EXPECT_REFUSED(search_placements(model, request), InputError, "is 10.0 mm from their B1");
}

TEST(HexapodPlacements, AGridWithNothingToMeasureIsRefused) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  PlacementSearchRequest request;
  request.x_mm = {1500, 2000};  // beyond the LR Mate's reach
  EXPECT_REFUSED(search_placements(model, request), InputError,
                 "--x-mm, --y-mm, --z-mm, --yaw-deg, --tilt-deg: none of the 2 placements has a "
                 "configuration to measure");
}

// `robcal hexapod design` (PlacementsDesignRequest): every configuration chosen with the count
// of both plans, the prediction then equals the one the placement search makes of the same two
// placements as measured (another code path: the `measured` figure of search_placements); the
// default count is the first plan's, and the reduced plans hold exactly the chosen
// configurations, numbered from 1, through a file round trip.
TEST(HexapodPlacements, DesignWorkflowKeepsEachPlansChosenConfigurations) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "robcal_placements_design_test";
  std::filesystem::create_directories(dir);
  HexapodPlanRequest plan_request;
  plan_request.gauge.range_mm = 5;
  plan_request.placement = {500, 300, 150, 0};
  const HexapodPlan a = plan_hexapod(model, plan_request);
  plan_request.placement = {350, 0, 300, 0};
  const HexapodPlan b = plan_hexapod(model, plan_request);
  const std::string a_file = (dir / "a.json").string(), b_file = (dir / "b.json").string();
  write_hexapod_plan(a_file, a);
  write_hexapod_plan(b_file, b);
  const int na = static_cast<int>(a.session.configurations.size());
  const int nb = static_cast<int>(b.session.configurations.size());
  ASSERT_GT(na, 50);
  ASSERT_GT(nb, 50);

  PlacementsDesignRequest request;
  request.plan_files = {a_file, b_file};
  request.validation_configurations = 300;
  request.seed = 3;
  request.count = na + nb;
  const PlacementsDesignResult all = design_placements(request);
  EXPECT_EQ(all.design.chosen[0].size(), static_cast<size_t>(na));
  EXPECT_EQ(all.design.chosen[1].size(), static_cast<size_t>(nb));
  PlacementSearchRequest search;
  search.plan = plan_request;
  search.validation_configurations = 300;
  search.seed = 3;
  // The plans as the workflow reads them (joints rounded to 1e-6° in the file).
  const HexapodPlan a_read = read_hexapod_plan(a_file), b_read = read_hexapod_plan(b_file);
  search.measured = {measured_placement(a_read, "a"), measured_placement(b_read, "b")};
  const PlacementSearchResult measured = search_placements(model, search);
  ASSERT_EQ(measured.measured_undetermined, 0);
  EXPECT_NEAR(all.design.predicted_mean_mm, measured.measured_mean_mm,
              1e-9 * measured.measured_mean_mm);
  EXPECT_NEAR(all.design.predicted_max_mm, measured.measured_max_mm,
              1e-9 * measured.measured_max_mm);
  // The first plan alone, every configuration: the search's figure of `a` measured alone.
  search.measured = {measured_placement(a_read, "a")};
  const PlacementSearchResult a_alone = search_placements(model, search);
  EXPECT_EQ(all.first_alone.chosen.front().size(), static_cast<size_t>(na));
  EXPECT_NEAR(all.first_alone.predicted_mean_mm, a_alone.measured_mean_mm,
              1e-9 * a_alone.measured_mean_mm);

  request.count = 0;  // as many as the first plan offers
  const PlacementsDesignResult split = design_placements(request);
  EXPECT_EQ(split.count, na);
  EXPECT_EQ(split.design.chosen[0].size() + split.design.chosen[1].size(), static_cast<size_t>(na));
  const std::array<const HexapodPlan*, 2> originals{&a, &b};
  for (size_t p = 0; p < 2; ++p) {
    const std::string reduced_file = (dir / "reduced.json").string();
    write_hexapod_plan(reduced_file, split.plans[p]);
    const HexapodPlan reread = read_hexapod_plan(reduced_file);
    ASSERT_EQ(reread.session.configurations.size(), split.design.chosen[p].size());
    for (size_t k = 0; k < split.design.chosen[p].size(); ++k) {
      const SessionConfiguration& got = reread.session.configurations[k];
      const SessionConfiguration& want =
          originals[p]->session.configurations[static_cast<size_t>(split.design.chosen[p][k])];
      EXPECT_EQ(got.id, static_cast<int>(k) + 1);
      EXPECT_EQ(got.pose, want.pose);
      ASSERT_EQ(got.joints_deg.size(), want.joints_deg.size());
      for (size_t j = 0; j < want.joints_deg.size(); ++j)
        EXPECT_NEAR(got.joints_deg[j], want.joints_deg[j], 1e-6);
    }
  }
  std::printf(
      "design over two LR Mate placements, %d configurations: %zu + %zu, predicted %.6f "
      "mm; first alone %.6f mm\n",
      split.count, split.design.chosen[0].size(), split.design.chosen[1].size(),
      split.design.predicted_mean_mm, split.first_alone.predicted_mean_mm);

  // Refusals: another robot's plan, more configurations than offered, a placement twice.
  HexapodPlanRequest irb;
  irb.robot = "abb-irb120";
  irb.placement = {400, 0, 200, 0};
  const std::string irb_file = (dir / "irb.json").string();
  write_hexapod_plan(irb_file, plan_hexapod(load_robot("abb-irb120"), irb));
  request.plan_files = {a_file, irb_file};
  EXPECT_REFUSED(design_placements(request), InputError,
                 "irb.json (robot): this plan is for abb-irb120");
  request.plan_files = {a_file, b_file};
  request.count = na + nb + 1;
  EXPECT_REFUSED(design_placements(request), InputError,
                 fmt::format("--count: expected at most {} configurations", na + nb));
  request.count = 0;
  request.plan_files = {a_file, a_file};
  EXPECT_REFUSED(design_placements(request), InputError, "this placement overlaps the one of");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace robcal::hexapod
