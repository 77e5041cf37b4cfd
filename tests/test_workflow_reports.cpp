// Library workflows behind CLI commands: the percentile of the Monte Carlo spread (hand-derived
// values), the pose selection's closest pair (the pruning threshold it reports is the one that
// starts pruning), the uncertainty study against its own parts, and the plan-study request checks.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/hexapod/geometry_reports.hpp"
#include "robcal/sim/monte_carlo_study.hpp"
#include "robcal/sim/plan_study_report.hpp"

namespace robcal {
namespace {

TEST(WorkflowReports, PercentileInterpolatesBetweenOrderStatistics) {
  // Sorted: 1 2 4 8 16. p = 0.5 → the third; p = 0.05 → 1 + 0.2·(2 − 1); p = 0.95 → 8 + 0.8·8.
  const std::vector<double> v{16, 2, 8, 1, 4};
  EXPECT_DOUBLE_EQ(percentile(v, 0.5), 4);
  EXPECT_DOUBLE_EQ(percentile(v, 0.05), 1.2);
  EXPECT_DOUBLE_EQ(percentile(v, 0.95), 14.4);
  EXPECT_DOUBLE_EQ(percentile(v, 0), 1);
  EXPECT_DOUBLE_EQ(percentile(v, 1), 16);
  EXPECT_DOUBLE_EQ(percentile({}, 0.5), 0);
}

TEST(WorkflowReports, ClosestPairIsWherePruningStarts) {
  const hexapod::HexapodGeometry g;
  const hexapod::PoseSelection none = hexapod::select_poses(g, 0, 1e6);
  ASSERT_EQ(none.kept.size(), none.enumerated.size());
  const double closest = none.closest_orientation_deg;
  ASSERT_GT(closest, 0);
  // Just below the closest pair's angle nothing is redundant; just above it (any distance) the
  // pair's second pose goes.
  EXPECT_EQ(hexapod::select_poses(g, closest * 0.999, 1e6).kept.size(), none.enumerated.size());
  EXPECT_LT(hexapod::select_poses(g, closest * 1.001, 1e6).kept.size(), none.enumerated.size());
  const nlohmann::json j = hexapod::pose_selection_json(none);
  EXPECT_EQ(j["enumerated"], none.enumerated.size());
  EXPECT_EQ(j["poses"].size(), none.kept.size());
  EXPECT_REFUSED(hexapod::select_poses(g, -1, 0), InputError,
                 "--angle-deg: expected a non-negative threshold in degrees, found -1");
}

TEST(WorkflowReports, UncertaintyWorstCaseIsTheLargestCupNorm) {
  const hexapod::HexapodGeometry g;
  const hexapod::UncertaintyStudy s = hexapod::uncertainty_study(g, 0.51, 7, 2000);
  double worst = 0;
  for (const hexapod::ModeUncertainty& m : s.analytic)
    for (const hexapod::CupUncertainty& c : m.cups) worst = std::max(worst, c.norm);
  EXPECT_EQ(s.worst_norm_sigma, worst);
  // 2000 draws: the Monte Carlo norms agree with the analytic ones to a few per cent.
  EXPECT_LT(s.monte_carlo_max_relative_difference, 0.1);
  const nlohmann::json j = hexapod::uncertainty_study_json(s);
  EXPECT_NEAR(j["worst_norm_um"].get<double>(), worst * 0.51, 1e-4);
  EXPECT_REFUSED(hexapod::uncertainty_study(g, 0, 7, 2000), InputError,
                 "--sigma-um: expected a positive σ in µm, found 0");
  EXPECT_REFUSED(hexapod::uncertainty_study(g, 0.51, 7, 99), InputError,
                 "--samples: expected at least 100 samples, found 99");
}

TEST(WorkflowReports, PlanStudyOptionsAreCheckedByName) {
  const auto key_of = [](const PlanStudyOptions& o) {
    try {
      check_plan_study_options(o);
    } catch (const InputError& e) {
      return e.where().key;
    }
    return std::string("accepted");
  };
  PlanStudyOptions o;
  EXPECT_EQ(key_of(o), "accepted");
  o.counts = {15, 0};
  EXPECT_EQ(key_of(o), "--counts");
  o = PlanStudyOptions{};
  o.seeds = 0;
  EXPECT_EQ(key_of(o), "--seeds");
  o = PlanStudyOptions{};
  o.task_count = 0;
  EXPECT_EQ(key_of(o), "--task-count");
  o = PlanStudyOptions{};
  o.noise_mm = -1;
  EXPECT_EQ(key_of(o), "--noise-mm");
  o = PlanStudyOptions{};
  o.prior_count = 19;  // too few for 5 fold models of the full level
  EXPECT_EQ(key_of(o), "--prior-count");
  o.prior_count = 0;
  EXPECT_EQ(key_of(o), "accepted");
  o.criterion = SelectionCriterion::Published;
  EXPECT_EQ(key_of(o), "--criterion");
  PlanStudyOptions box;
  box.task_box = TaskBox{Eigen::Vector3d(300, -100, 200), Eigen::Vector3d(500, 100, 400)};
  EXPECT_EQ(task_region_description(box),
            "TCP box 300,500,-100,100,200,400 mm (world frame), tool pointing down");
}

}  // namespace
}  // namespace robcal
