// Task-aware selection and the `plan` workflow (docs/method/05-observability.md §5, issue 13 item
// 7, issue 16 `plan --cell`, issue 21 streamed candidates): the I-optimal criterion against the
// prediction it stands for, a local optimum checked by brute force, the robustness guard,
// default constraints from the robot file, the user's candidate list, the cell's feasibility.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <fstream>

#include "refusal.hpp"
#include "robcal/campaign/feasibility.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/design/calibration_planning.hpp"
#include "robcal/design/predicted_accuracy.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/plan_study.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

struct Fixture {
  RobotModel model = load_robot("abb-irb120");
  Tool tool = default_simulation_tool();
  TrueRobot cell = planning_cell(model, tool, Eigen::Matrix<double, 6, 1>::Zero());
  std::vector<Candidate> candidates;
  std::vector<Vector6d> joints, task;
  DesignMatrix design;
  Eigen::MatrixXd task_info;
  SelectionGuard guard;

  explicit Fixture(int n, uint64_t seed = 5) {
    std::mt19937_64 rng(seed);
    CandidateOptions options;
    options.count = n;
    candidates = generate_candidates(model, tool, options, rng).candidates;
    for (const Candidate& c : candidates) joints.push_back(c.joints);
    DesignSettings settings;
    settings.parameters = level_parameters(CalibrationLevel::Full);
    design = build_design_matrix(model, tool, candidates, settings);
    options.count = 50;
    for (const Candidate& c : generate_candidates(model, tool, options, rng).candidates)
      task.push_back(c.joints);
    task_info = task_information(design, position_jacobian(model, tool.payload, model.nominal(),
                                                           design.parameters, task, tcp()));
    guard.box = constrained_joint_box(model, published_joint_constraints());
  }
  [[nodiscard]] std::vector<Eigen::Vector3d> tcp() const {
    return {tool.flange_T_tcp.translation()};
  }
};

TEST(TaskSelection, CriterionIsTheMeanPredictedSquaredError) {
  // σ²·tr(M⁻¹B) is the mean over the task configurations of the predicted squared TCP error
  // that identify's predict_position_error computes from the design covariance (ridge 1e-6
  // aside).
  const Fixture f(300);
  const std::vector<int> subset{3, 17, 29, 41, 52, 60, 77, 81, 95, 110, 123, 140, 151, 170, 199};
  const double sigma = 0.02;
  const PredictedAccuracy p = predict_position_error(
      f.model, f.tool.payload, f.model.nominal(), f.design.parameters,
      design_parameter_covariance(f.design, subset, sigma), f.task, f.tcp(), sigma);
  EXPECT_NEAR(sigma * sigma * i_criterion(f.design, f.task_info, subset) / (p.rms_mm * p.rms_mm),
              1.0, 1e-4);
}

TEST(TaskSelection, IOptimalIsALocalOptimumBySwapsAndBeatsDOptimalOnItsCriterion) {
  const Fixture f(150);
  SelectionGuard off = f.guard;
  off.enabled = false;
  const int count = 12;
  const TaskSelection s = select_i_optimal(f.design, f.task_info, count, f.joints, off);
  ASSERT_EQ(s.chosen.size(), static_cast<size_t>(count));
  EXPECT_NEAR(s.criterion, i_criterion(f.design, f.task_info, s.chosen), 1e-12 * s.criterion);
  // Brute force: no single swap lowers the criterion by more than the exchange's threshold.
  double best = s.criterion;
  for (size_t k = 0; k < s.chosen.size(); ++k)
    for (int i = 0; i < f.design.candidates(); ++i) {
      if (std::find(s.chosen.begin(), s.chosen.end(), i) != s.chosen.end()) continue;
      std::vector<int> swapped = s.chosen;
      swapped[k] = i;
      best = std::min(best, i_criterion(f.design, f.task_info, swapped));
    }
  EXPECT_GT(best, s.criterion * (1 - 2e-4));
  // Each criterion wins on its own terms.
  const Selection d = select_d_optimal(f.design, count);
  EXPECT_LT(s.criterion, i_criterion(f.design, f.task_info, d.chosen));
  EXPECT_GT(d.log_det, information_log_det(f.design, s.chosen));
}

// A start design (hexapod design: equal shares of every placement): the search fills up from it and
// its exchanges only lower the criterion, so the result is no worse than the start itself; a
// start that is not a set of at most `count` candidates is a programming error.
TEST(TaskSelection, StartDesignIsImprovedNeverWorsened) {
  const Fixture f(150);
  SelectionGuard off = f.guard;
  off.enabled = false;
  const int count = 12;
  std::vector<int> start;
  for (int i = 0; i < count; ++i) start.push_back(5 * i);  // an arbitrary full design
  const TaskSelection s = select_i_optimal(f.design, f.task_info, count, f.joints, off, {}, start);
  ASSERT_EQ(s.chosen.size(), static_cast<size_t>(count));
  EXPECT_NEAR(s.criterion, i_criterion(f.design, f.task_info, s.chosen), 1e-12 * s.criterion);
  EXPECT_LT(s.criterion, i_criterion(f.design, f.task_info, start));
  EXPECT_GT(s.exchanges, 0);
  // Half a design: filled up greedily to the count.
  const std::vector<int> half(start.begin(), start.begin() + count / 2);
  const TaskSelection filled =
      select_i_optimal(f.design, f.task_info, count, f.joints, off, {}, half);
  EXPECT_EQ(filled.chosen.size(), static_cast<size_t>(count));
  EXPECT_THROW(select_i_optimal(f.design, f.task_info, count, f.joints, off, {}, {3, 3}),
               std::invalid_argument);
  EXPECT_THROW(select_i_optimal(f.design, f.task_info, 2, f.joints, off, {}, {1, 2, 3}),
               std::invalid_argument);
}

TEST(TaskSelection, GuardCapsEdgesKeepsSpacingAndTheTaskShare) {
  const Fixture f(400);
  const int count = 20;
  std::vector<char> in_task(static_cast<size_t>(f.design.candidates()), 0);
  for (size_t i = 0; i < in_task.size(); i += 7) in_task[i] = 1;  // 58 "near the task"
  const TaskSelection s =
      select_i_optimal(f.design, f.task_info, count, f.joints, f.guard, in_task);
  int edge = 0, near = 0;
  for (int i : s.chosen) {
    edge += near_joint_edge(f.guard, f.joints[static_cast<size_t>(i)]) ? 1 : 0;
    near += in_task[static_cast<size_t>(i)];
    for (int j : s.chosen) {
      if (i != j) {
        EXPECT_GE(joint_spacing(f.guard, f.joints[static_cast<size_t>(i)],
                                f.joints[static_cast<size_t>(j)]),
                  f.guard.min_spacing);
      }
    }
  }
  EXPECT_EQ(s.near_edge, edge);
  EXPECT_LE(edge, 5);   // ⌊0.25 · 20⌋
  EXPECT_GE(near, 10);  // ⌈0.5 · 20⌉
  // Unguarded, the criterion is at least as good and the edges are not capped.
  SelectionGuard off = f.guard;
  off.enabled = false;
  const TaskSelection free = select_i_optimal(f.design, f.task_info, count, f.joints, off);
  EXPECT_LE(free.criterion, s.criterion * 1.0001);
  EXPECT_GT(free.near_edge, 5);
}

TEST(TaskSelection, EdgesAndSpacingByHand) {
  SelectionGuard g;
  for (auto& r : g.box) r = {deg2rad(-100), deg2rad(100)};  // 200° ranges: 5 % = 10°
  Vector6d q = Vector6d::Zero();
  EXPECT_FALSE(near_joint_edge(g, q));
  q[3] = deg2rad(89);
  EXPECT_FALSE(near_joint_edge(g, q));
  q[3] = deg2rad(91);
  EXPECT_TRUE(near_joint_edge(g, q));
  Vector6d a = Vector6d::Zero(), b = Vector6d::Zero();
  b[1] = deg2rad(30);
  b[4] = deg2rad(-50);
  EXPECT_NEAR(joint_spacing(g, a, b), 0.25, 1e-12);
  EXPECT_EQ(guard_edge_limit(g, 40), 10);
  g.enabled = false;
  EXPECT_EQ(guard_edge_limit(g, 40), 40);
}

PlanRequest small_request(const std::string& robot) {
  PlanRequest r;
  r.model = load_robot(robot);
  r.tool = default_simulation_tool();
  r.count = 12;
  r.candidates = 400;
  r.task_count = 40;
  return r;
}

TEST(PlanWorkflow, DefaultConstraintsComeFromTheRobotFile) {
  const RobotModel irb = load_robot("abb-irb120");
  const RobotModel ur = load_robot("universal-robots-ur10e");
  EXPECT_DOUBLE_EQ(default_joint_constraints(irb).range[1].lower, 0.0);  // published θ2 ≥ 0
  const auto box = constrained_joint_box(ur, default_joint_constraints(ur));
  for (int k = 0; k < kJointCount; ++k) {
    EXPECT_DOUBLE_EQ(box[static_cast<size_t>(k)].lower, ur.limits[k].lower);
    EXPECT_DOUBLE_EQ(box[static_cast<size_t>(k)].upper, ur.limits[k].upper);
  }
  // A UR plans with its own limits: shoulder values below 0 (upper arm raised) are chosen,
  // which the published θ2 ≥ 0 forbids.
  const PlanResult r = plan_calibration(small_request("universal-robots-ur10e"));
  ASSERT_EQ(r.configurations.size(), 12u);
  int raised = 0;
  for (const PlannedConfiguration& c : r.configurations) raised += c.joints[1] < 0 ? 1 : 0;
  EXPECT_GT(raised, 0);
  EXPECT_REFUSED(plan_joint_constraints(ur, "publised"), InputError,
                 "--constraints: unknown constraint preset 'publised', expected 'auto'");
}

TEST(PlanWorkflow, CriterionDefaultsToTaskAwareWithATaskRegion) {
  PlanRequest request = small_request("abb-irb120");
  const PlanResult d = plan_calibration(request);
  EXPECT_EQ(d.criterion, SelectionCriterion::DOptimal);
  // D-optimality rests on the edges, past the guard's cap: the user is told (6 of 12 here).
  EXPECT_EQ(d.near_edge, 6);
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_NE(d.notes[0].find(fmt::format("{} of 12 configurations are near a joint-range edge "
                                        "(the guard allows 3)",
                                        d.near_edge)),
            std::string::npos)
      << d.notes[0];
  request.task_box = TaskBox{{-500, 1100, 150}, {-300, 1300, 350}};
  const PlanResult r = plan_calibration(request);
  EXPECT_EQ(r.criterion, SelectionCriterion::IOptimal);
  EXPECT_TRUE(r.notes.empty());
  EXPECT_LE(r.near_edge, r.edge_limit);
  EXPECT_EQ(r.edge_limit, 3);  // ⌊0.25 · 12⌋
  EXPECT_LT(r.predicted_selected.mean_mm, r.predicted_random.mean_mm);
  request.criterion = SelectionCriterion::DOptimal;
  EXPECT_GT(plan_calibration(request).predicted_selected.mean_mm, r.predicted_selected.mean_mm);
}

TEST(PlanWorkflow, SelectsAmongListedConfigurations) {
  PlanRequest request = small_request("abb-irb120");
  std::mt19937_64 rng(9);
  CandidateOptions options;
  options.count = 60;
  for (const Candidate& c :
       generate_candidates(request.model, request.tool, options, rng).candidates)
    request.candidate_configurations.push_back(
        {fmt::format("M{}", request.candidate_configurations.size()), c.joints, c.target});
  PlannedConfiguration outside = request.candidate_configurations.front();
  outside.joints[1] = deg2rad(150);  // beyond the IRB 120's ±110°
  request.candidate_configurations.push_back(outside);
  request.candidates_file = "measured.csv";
  const PlanResult r = plan_calibration(request);
  EXPECT_EQ(r.outside_limits, 1);
  EXPECT_EQ(r.candidates, 60);
  for (const PlannedConfiguration& c : r.configurations) {
    bool listed = false;
    for (size_t k = 0; k + 1 < request.candidate_configurations.size(); ++k)
      listed = listed || (c.joints == request.candidate_configurations[k].joints &&
                          c.target == request.candidate_configurations[k].target);
    EXPECT_TRUE(listed) << c.name;
  }
  request.candidate_configurations = {outside};
  try {
    plan_calibration(request);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1 outside the robot's joint limits"), std::string::npos)
        << e.what();
  }
}

TEST(PlanWorkflow, StreamedCandidatesKeepAPoolAndARandomSampleOfAll) {
  PlanRequest request = small_request("abb-irb120");
  request.candidates = 2500;
  request.pool = 1000;
  const PlanResult r = plan_calibration(request);
  EXPECT_EQ(r.candidates, 2500);
  EXPECT_EQ(r.pooled, 1000);
  ASSERT_EQ(r.configurations.size(), 12u);
  // The pool keeps the high-leverage candidates: the choice from it is as D-efficient as one
  // from every candidate at once (within a few per cent).
  request.pool = 2500;
  const PlanResult all = plan_calibration(request);
  EXPECT_EQ(all.pooled, 2500);
  EXPECT_GT(r.selected.O1, 0.97 * all.selected.O1);
}

TEST(PlanWorkflow, PlannedConfigurationsRespectTheCell) {
  // A cell with a keep-out box across the robot's right side: every planned configuration passes
  // the cell's own feasibility check (an independent geometry test), and the box rejects draws.
  const std::string path = ::testing::TempDir() + "plan-cell.yaml";
  {
    std::ofstream out(path);
    out << "format: robcal-cell\nname: test cell\nrobot_base:\n"
           "  position_mm: [-812.25, 1503.5, -95]\n  rotation_xyz_deg: [0.25, -0.4, -57]\n"
           "instrument:\n  kind: laser-tracker\n  position_mm: [0, 0, 0]\n"
           "  range_mm: [0, 35000]\n  cone_half_angle_deg: 30\nfloor_z_mm: -95\n"
           "link_radius_mm: 60\nkeep_out:\n"
           "  - {name: fixture, min_mm: [-700, 1000, -95], max_mm: [-300, 1300, 400]}\n";
  }
  PlanRequest request = small_request("abb-irb120");
  request.cell = campaign::load_cell(path);
  const PlanResult r = plan_calibration(request);
  EXPECT_EQ(r.cell, "test cell");
  EXPECT_GT(r.below_floor, 0);  // floor and keep-out rejections
  for (const PlannedConfiguration& c : r.configurations) {
    const campaign::Feasibility f = campaign::check_configuration(*request.cell, request.model,
                                                                  request.tool, c.joints, c.target);
    EXPECT_EQ(f.reason, campaign::Rejection::None) << c.name << ": " << f.detail;
  }
}

}  // namespace
}  // namespace robcal
