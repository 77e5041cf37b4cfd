// Placement search for the base fixture (issue 20 items 1–2): a grid with placements out of reach
// ranks them last; the predicted accuracy of the best placement and of the best pair is recomputed
// here by a second, straightforward implementation (unscaled Jacobians from design's candidate
// rows, C = σ²(JᵀJ)⁻¹ by a plain solve, point Jacobians at the same validation configurations;
// the second placement's world frame as six more columns: its rows' base-parameter columns, which
// span the same rigid motions as the search's frame columns); two placements predict better than
// either alone.

#include <gtest/gtest.h>

#include <algorithm>

#include <Eigen/Cholesky>

#include "refusal.hpp"
#include "robcal/core/units.hpp"
#include "robcal/design/design_matrix.hpp"
#include "robcal/hexapod/placement_search.hpp"
#include "robcal/identify/accuracy_prediction.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal::hexapod {
namespace {

/// The planned configurations of one placement.
std::vector<Vector6d> planned(const RobotModel& model, HexapodPlanRequest r,
                              const PlacementScore& s, Pose<double>* flange_T_tool) {
  r.placement = s.placement;
  r.tilt_deg = s.tilt_deg;
  const HexapodPlan plan = plan_hexapod(model, r);
  *flange_T_tool = *plan.session.flange_T_tool;
  std::vector<Vector6d> out;
  for (const SessionConfiguration& c : plan.session.configurations) {
    Vector6d q;
    for (int j = 0; j < 6; ++j) q[j] = deg2rad(c.joints_deg[j]);
    out.push_back(q);
  }
  return out;
}

/// Mean predicted position error, straight from the definitions (docs/method/05-observability.md).
double straight_prediction(const RobotModel& model,
                           const std::vector<std::vector<Vector6d>>& placements,
                           const Pose<double>& flange_T_tool, const std::vector<int>& parameters,
                           double sigma_mm, const std::vector<Vector6d>& validation) {
  Tool tool;
  tool.flange_T_tcp.linear() = flange_T_tool.R;
  tool.flange_T_tcp.translation() = flange_T_tool.p;
  tool.targets.push_back({"tcp", flange_T_tool.p, true});
  const ParameterVector params = model.nominal();
  const auto rows = [&](const Vector6d& q, MeasurementKind kind) {
    DesignSettings s;
    s.kind = kind;
    const Eigen::MatrixXd full = candidate_jacobian(model, tool, params, {q, 0}, s);
    Eigen::MatrixXd out(full.rows(), parameters.size());
    for (size_t k = 0; k < parameters.size(); ++k) out.col(k) = full.col(parameters[k]);
    return out;
  };
  const int p = static_cast<int>(parameters.size());
  const int n = p + 6 * static_cast<int>(placements.size() - 1);
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n, n);
  for (size_t g = 0; g < placements.size(); ++g)
    for (const Vector6d& q : placements[g]) {
      DesignSettings s;
      s.kind = MeasurementKind::Poses;
      const Eigen::MatrixXd full = candidate_jacobian(model, tool, params, {q, 0}, s);
      Eigen::MatrixXd J = Eigen::MatrixXd::Zero(full.rows(), n);
      J.leftCols(p) = rows(q, MeasurementKind::Poses);
      if (g > 0) J.middleCols(p + 6 * (static_cast<int>(g) - 1), 6) = full.leftCols(6);
      normal += J.transpose() * J;
    }
  // Equilibrate (mm and rad columns) before inverting.
  const Eigen::VectorXd d = normal.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled = d.asDiagonal() * normal * d.asDiagonal();
  const Eigen::MatrixXd cov =
      (sigma_mm * sigma_mm * d.asDiagonal() * scaled.ldlt().solve(Eigen::MatrixXd::Identity(n, n)) *
       d.asDiagonal())
          .topLeftCorner(p, p);
  double sum = 0;
  for (const Vector6d& v : validation) {
    const Eigen::MatrixXd Jv = rows(v, MeasurementKind::Points);
    sum += std::sqrt((Jv * cov * Jv.transpose()).trace());
  }
  return sum / static_cast<double>(validation.size());
}

TEST(HexapodPlacementSearch, RanksReachablePlacementsAndPredictsWhatAStraightComputationGives) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  PlacementSearchRequest request;
  request.x_mm = {350, 450, 1500};  // 1500 mm: out of the LR Mate's reach
  request.y_mm = {-250, 0, 250};
  request.yaw_deg = {0};
  request.tilt_deg = {0, 25};
  request.validation_configurations = 300;
  request.seed = 7;
  const PlacementSearchResult r = search_placements(model, request);
  ASSERT_EQ(r.ranked.size(), 18u);
  // Out of reach: no configuration, ranked after every usable placement.
  int unusable = 0;
  for (size_t i = 0; i < r.ranked.size(); ++i) {
    const PlacementScore& s = r.ranked[i];
    if (s.placement[0] == 1500) {
      EXPECT_EQ(s.configurations, 0);
      EXPECT_FALSE(s.usable());
    }
    if (!s.usable())
      ++unusable;
    else
      EXPECT_EQ(unusable, 0) << "usable placement ranked after an unusable one";
  }
  // Every unusable placement: the robot cannot place the base cups there.
  EXPECT_EQ(unusable, 7);  // the six out of reach and one tilted placement
  EXPECT_EQ(std::count_if(r.ranked.begin(), r.ranked.end(),
                          [](const PlacementScore& s) {
                            return s.refused.find("cannot put the setting ball") !=
                                   std::string::npos;
                          }),
            7);
  for (size_t i = 1; i < r.ranked.size(); ++i)
    if (r.ranked[i].usable() && r.ranked[i].undetermined == 0) {
      EXPECT_LE(r.ranked[i - 1].predicted_mean_mm, r.ranked[i].predicted_mean_mm);
    }
  const PlacementScore& best = r.ranked.front();
  ASSERT_TRUE(best.usable());
  ASSERT_EQ(best.undetermined, 0);
  EXPECT_GT(best.observability_o1, 0);

  // The same validation configurations the search drew.
  std::mt19937_64 rng(request.seed);
  Vector6d lower, upper;
  for (int j = 0; j < 6; ++j) {
    lower[j] = model.limits[j].lower;
    upper[j] = model.limits[j].upper;
  }
  const std::vector<Vector6d> validation = sample_configurations(lower, upper, 300, rng);
  Pose<double> mount;
  const std::vector<Vector6d> a = planned(model, request.plan, best, &mount);
  ASSERT_EQ(static_cast<int>(a.size()), best.configurations);
  const double straight_a =
      straight_prediction(model, {a}, mount, r.identified_parameters, r.pose_sigma_mm, validation);
  EXPECT_NEAR(best.predicted_mean_mm, straight_a, 1e-6 * straight_a);

  // The best pair: better than either of its placements alone, by the straight computation too.
  ASSERT_FALSE(r.pairs.empty());
  const PlacementPair& pair = r.pairs.front();
  const PlacementScore& first = r.ranked[pair.first];
  const PlacementScore& second = r.ranked[pair.second];
  const double straight_pair = straight_prediction(
      model,
      {planned(model, request.plan, first, &mount), planned(model, request.plan, second, &mount)},
      mount, r.identified_parameters, r.pose_sigma_mm, validation);
  EXPECT_NEAR(pair.predicted_mean_mm, straight_pair, 1e-6 * straight_pair);
  EXPECT_LT(straight_pair, std::min(first.predicted_mean_mm, second.predicted_mean_mm));
  EXPECT_EQ(pair.configurations, first.configurations + second.configurations);
  std::printf(
      "best placement %g,%g,%g yaw %g tilt %g: %d configurations, predicted mean %.4f mm "
      "(σ pose %.5f mm), O1 %.3f\n",
      best.placement[0], best.placement[1], best.placement[2], best.placement[3], best.tilt_deg,
      best.configurations, best.predicted_mean_mm, r.pose_sigma_mm, best.observability_o1);
  std::printf(
      "best pair (#%d + #%d): %d configurations %.4f mm; half of each (%d configurations) %.4f "
      "mm\n",
      pair.first + 1, pair.second + 1, pair.configurations, pair.predicted_mean_mm,
      pair.equal_count_configurations, pair.equal_count_mean_mm);
}

// A task region (`--task-box`): the predictions are over configurations putting the tool fixture
// in the box, tool axis down. Measured from one placement, the model is best where it was
// measured: a box over the base fixture predicts less than the same box on the far side of the
// robot. A box the robot cannot reach is refused naming the flag.
TEST(HexapodPlacementSearch, TaskBoxPredictsOverTheTaskRegion) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  PlacementSearchRequest request;  // the one placement 450,0,300,0
  request.validation_configurations = 300;
  const auto predicted = [&](const std::optional<TaskBox>& box) {
    request.task_box = box;
    const PlacementSearchResult r = search_placements(model, request);
    EXPECT_EQ(r.task_box.has_value(), box.has_value());
    return r.ranked.front().predicted_mean_mm;
  };
  const double workspace = predicted(std::nullopt);
  const double over_fixture = predicted(TaskBox{{350, -100, 450}, {550, 100, 600}});
  const double far_side = predicted(TaskBox{{-550, -100, 450}, {-350, 100, 600}});
  std::printf(
      "predicted mean: whole workspace %.6f mm, over the fixture %.6f mm, far side %.6f mm\n",
      workspace, over_fixture, far_side);
  EXPECT_LT(over_fixture, far_side);
  EXPECT_NE(over_fixture, workspace);
  request.task_box = TaskBox{{3000, 0, 0}, {3100, 100, 100}};
  EXPECT_REFUSED(search_placements(model, request), InputError, "--task-box");
}

TEST(HexapodPlacementSearch, BadGridsAreRefused) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  PlacementSearchRequest request;
  request.y_mm.clear();
  EXPECT_REFUSED(search_placements(model, request), InputError, "--y-mm");
  request.y_mm = std::vector<double>(50, 0.0);
  request.x_mm = std::vector<double>(50, 450.0);
  EXPECT_REFUSED(search_placements(model, request), InputError, "2500 placements");
  request = PlacementSearchRequest{};
  request.best = 0;
  EXPECT_REFUSED(search_placements(model, request), InputError, "--best");
}

}  // namespace
}  // namespace robcal::hexapod
