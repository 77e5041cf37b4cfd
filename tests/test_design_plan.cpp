// Planning in the simulated cell (docs/method/05-observability.md, issue 5): every planned
// configuration is measured by the simulator, the task box, and the closed loop plan → simulate →
// calibrate against random configurations with the accuracy predicted before measuring.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <filesystem>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/design/predicted_accuracy.hpp"
#include "robcal/design/selection.hpp"
#include "robcal/design/task_region.hpp"
#include "robcal/identify/accuracy_prediction.hpp"
#include "robcal/identify/unknowns.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/campaign.hpp"
#include "robcal/sim/plan_study.hpp"

namespace robcal {
namespace {

TEST(DesignPlan, EveryPlannedConfigurationIsMeasured) {
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  std::vector<TrueRobot> truths{published_irb120_truth(model, tool)};
  for (uint64_t seed : {21u, 31u}) {  // the two random truths whose flanges err most (≈ 2.5°)
    std::mt19937_64 rng(seed);
    truths.push_back(random_truth(model, tool, ErrorBounds{}, rng));
  }
  for (const InstrumentKind kind : {InstrumentKind::LaserTracker, InstrumentKind::OpticalCmm}) {
    for (const TrueRobot& truth : truths) {
      SCOPED_TRACE(instrument_name(kind) + ", truth " + truth.origin);
      const VirtualInstrument instrument = standard_instrument(kind, truth);
      std::mt19937_64 rng(1), noise(2);
      const std::vector<PlannedConfiguration> plan =
          plan_calibration(truth, instrument, model, tool, CalibrationLevel::Full, 50, 2000, rng);
      ASSERT_EQ(plan.size(), 50u);
      const SimulationResult measured = simulate_measurements(truth, instrument, plan, noise);
      EXPECT_EQ(measured.measurements.size(), 50u);
      EXPECT_TRUE(measured.skipped.empty()) << measured.skipped.front();
    }
  }
}

TEST(DesignPlan, PlanningMarginKeepsTargetsInsideTheSimulatorsCone) {
  // The candidates pass the simulator's own visibility test (visible_targets) with the cone
  // narrowed by the margin, on the nominal robot: check both against the narrowed tracker.
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  const TrueRobot truth = published_irb120_truth(model, tool);
  const TrueRobot cell = planning_cell(model, tool, truth.robot.params.head<kBaseParamCount>());
  const VirtualInstrument tracker = standard_instrument(InstrumentKind::LaserTracker, truth);
  PlanSettings settings;
  settings.candidates = 300;
  std::mt19937_64 rng(4);
  const CandidateSet set = instrument_candidates(cell, tracker, settings, rng);
  ASSERT_EQ(set.candidates.size(), 300u);
  LaserTracker narrow = tracker.tracker;
  narrow.cone_half_angle_deg = 30 - settings.visibility_margin_deg;
  for (const Candidate& c : set.candidates) {
    const Pose<double> flange = flange_pose(model, tool.payload, cell.robot.params, c.joints);
    const std::vector<int> seen = visible_targets(narrow, flange, tool);
    EXPECT_NE(std::find(seen.begin(), seen.end(), c.target), seen.end());
  }
  EXPECT_GT(set.not_visible, 0);
}

TEST(DesignPlan, TaskBoxConfigurationsPutTheTcpInTheBox) {
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  const TrueRobot truth = published_irb120_truth(model, tool);
  const TrueRobot cell = planning_cell(model, tool, truth.robot.params.head<kBaseParamCount>());
  const TaskBox box = parse_task_box("-500,-300, 1100,1300, 150,350", "--task-box");
  EXPECT_EQ(box.min_mm, Eigen::Vector3d(-500, 1100, 150));
  EXPECT_EQ(box.max_mm, Eigen::Vector3d(-300, 1300, 350));
  std::mt19937_64 rng(6);
  const JointConstraints constraints = published_joint_constraints();
  const std::vector<Vector6d> task =
      task_box_configurations(model, tool, cell.robot.params, constraints, box, 50, rng);
  ASSERT_EQ(task.size(), 50u);
  for (const Vector6d& q : task) {
    const Pose<double> flange = flange_pose(model, tool.payload, cell.robot.params, q);
    const Eigen::Vector3d tcp = flange * Eigen::Vector3d(tool.flange_T_tcp.translation());
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(tcp[k], box.min_mm[k] - 1e-6);
      EXPECT_LE(tcp[k], box.max_mm[k] + 1e-6);
    }
    EXPECT_NEAR((flange.R * tool.flange_T_tcp.linear()).col(2).z(), -1.0, 1e-9);  // tool down
    for (int j = 0; j < kJointCount; ++j) {
      EXPECT_GE(q[j], std::max(model.limits[j].lower, constraints.range[j].lower));
      EXPECT_LE(q[j], std::min(model.limits[j].upper, constraints.range[j].upper));
    }
  }
  // Bad boxes: a clear error naming the flag.
  EXPECT_REFUSED(parse_task_box("1,2,3", "--task-box"), InputError,
                 "--task-box: expected xmin,xmax,ymin,ymax,zmin,zmax (6 numbers, mm), found 3");
  EXPECT_REFUSED(parse_task_box("1,0,0,1,0,1", "--task-box"), InputError,
                 "--task-box: x range [1, 0] has min > max");
  EXPECT_REFUSED(parse_task_box("a,1,0,1,0,1", "--task-box"), InputError,
                 "--task-box: expected a number (mm), found 'a'");
  try {
    task_box_configurations(model, tool, cell.robot.params, constraints,
                            parse_task_box("5000,6000,0,100,0,100", "--task-box"), 5, rng);
    FAIL() << "a box out of reach must be an error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "--task-box");
  }
}

TEST(DesignPlan, TaskPosesGiveBackTheConfigurationsThatMadeThem) {
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  const TrueRobot truth = published_irb120_truth(model, tool);
  const TrueRobot cell = planning_cell(model, tool, truth.robot.params.head<kBaseParamCount>());
  const JointConstraints constraints = published_joint_constraints();
  Pose<double> flange_T_tcp;
  flange_T_tcp.R = tool.flange_T_tcp.linear();
  flange_T_tcp.p = tool.flange_T_tcp.translation();
  const auto world_T_tcp = [&](const Vector6d& q) {
    return flange_pose(model, tool.payload, cell.robot.params, q) * flange_T_tcp;
  };
  // Known configurations inside the constraints, away from the wrist singularity (θ5 = 0,
  // where only θ4 + θ6 follows from the pose); their TCP poses by forward kinematics, each with
  // its configuration branch, as a pose-list file would give them.
  CandidateOptions options;
  options.constraints = constraints;
  options.count = 40;
  std::mt19937_64 rng(8);
  std::vector<Vector6d> known;
  std::vector<ListedPose> poses;
  for (const Candidate& c : generate_candidates(model, tool, options, rng).candidates) {
    if (std::abs(c.joints[4]) < deg2rad(5.0)) continue;
    known.push_back(c.joints);
    poses.push_back({fmt::format("P{}", poses.size() + 1), world_T_tcp(c.joints),
                     arm_config(model, c.joints), static_cast<int>(poses.size()) + 2});
  }
  ASSERT_GE(known.size(), 30u);
  const std::vector<Vector6d> task =
      task_pose_configurations(model, tool, cell.robot.params, constraints, poses, "poses.csv");
  ASSERT_EQ(task.size(), known.size());
  for (size_t k = 0; k < known.size(); ++k)
    EXPECT_LT((task[k] - known[k]).cwiseAbs().maxCoeff(), 1e-9) << poses[k].name;

  // The prediction over them is the one over the same configurations given as a
  // configurations file (--task-configs: degrees with 6 decimals).
  std::vector<PlannedConfiguration> listed;
  for (size_t k = 0; k < known.size(); ++k) listed.push_back({poses[k].name, known[k], 0});
  const std::string path =
      (std::filesystem::temp_directory_path() / "robcal_task_configs_test.csv").string();
  write_file_atomically(path, write_configurations_csv(listed, tool));
  std::vector<Vector6d> from_file;
  for (const PlannedConfiguration& c : read_configurations_csv(path, tool))
    from_file.push_back(c.joints);
  std::filesystem::remove(path);
  std::mt19937_64 candidate_rng(9);
  CandidateOptions pool;
  pool.constraints = constraints;
  pool.count = 300;
  DesignSettings settings;
  settings.parameters = level_parameters(CalibrationLevel::Full);
  const DesignMatrix design = build_design_matrix(
      model, tool, generate_candidates(model, tool, pool, candidate_rng).candidates, settings);
  const Eigen::MatrixXd covariance =
      design_parameter_covariance(design, select_d_optimal(design, 30).chosen, 0.02);
  const auto predict = [&](const std::vector<Vector6d>& region) {
    return predict_position_error(model, tool.payload, cell.robot.params, design.parameters,
                                  covariance, region, {tool.flange_T_tcp.translation()}, 0.02);
  };
  const PredictedAccuracy by_poses = predict(task), by_configs = predict(from_file);
  EXPECT_EQ(by_poses.configurations, static_cast<int>(known.size()));
  EXPECT_GT(by_poses.mean_mm, 0);
  EXPECT_NEAR(by_poses.mean_mm, by_configs.mean_mm, 1e-6 * by_configs.mean_mm);
  EXPECT_NEAR(by_poses.max_mm, by_configs.max_mm, 1e-6 * by_configs.max_mm);

  // Without a branch: a solution inside the constraints that reaches the pose.
  std::vector<ListedPose> any = poses;
  for (ListedPose& p : any) p.config.reset();
  const std::vector<Vector6d> any_task =
      task_pose_configurations(model, tool, cell.robot.params, constraints, any, "poses.csv");
  for (size_t k = 0; k < any.size(); ++k)
    EXPECT_LT((world_T_tcp(any_task[k]).p - any[k].world_T_tcp.p).norm(), 1e-6);
}

TEST(DesignPlan, TaskPoseOutOfReachNamesFileLineAndReason) {
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  const TrueRobot truth = published_irb120_truth(model, tool);
  const TrueRobot cell = planning_cell(model, tool, truth.robot.params.head<kBaseParamCount>());
  Pose<double> flange_T_tcp;
  flange_T_tcp.R = tool.flange_T_tcp.linear();
  flange_T_tcp.p = tool.flange_T_tcp.translation();
  // θ2 = −20° is inside the robot's limits but outside the published constraints (θ2 ≥ 0).
  Vector6d q;
  q << deg2rad(10.0), deg2rad(-20.0), deg2rad(10.0), deg2rad(30.0), deg2rad(40.0), deg2rad(50.0);
  const ListedPose outside{"low",
                           flange_pose(model, tool.payload, cell.robot.params, q) * flange_T_tcp,
                           arm_config(model, q), 4};
  ListedPose far = outside;
  far.name = "far";
  far.world_T_tcp.p.x() += 5000;
  far.line = 7;
  ListedPose wrong_branch = outside;
  wrong_branch.config = ArmConfig{!outside.config->back, outside.config->down, false};
  wrong_branch.line = 9;
  const auto error = [&](const ListedPose& pose) {
    try {
      task_pose_configurations(model, tool, cell.robot.params, published_joint_constraints(),
                               {pose}, "poses.csv");
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().file, "poses.csv");
      EXPECT_EQ(e.where().line, pose.line);
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error(far).find("poses.csv:7 (far): task pose"), std::string::npos) << error(far);
  EXPECT_NE(error(far).find("no configuration reaches it"), std::string::npos) << error(far);
  EXPECT_NE(error(outside).find("outside the joint constraints"), std::string::npos)
      << error(outside);
  EXPECT_NE(error(wrong_branch).find("does not reach it"), std::string::npos)
      << error(wrong_branch);
  // Without the constraints the same configuration is found.
  const std::vector<Vector6d> free = task_pose_configurations(
      model, tool, cell.robot.params, unconstrained_joints(), {outside}, "poses.csv");
  EXPECT_LT((free[0] - q).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(DesignPlan, SummaryTakesMeansOfMeansAndQuadraticMeansOfRms) {
  std::vector<StudyOutcome> outcomes(2);
  outcomes[0].achieved = {1.0, 3.0, 5.0};
  outcomes[1].achieved = {2.0, 4.0, 9.0};
  outcomes[0].predicted = {0.5, 1.0, 2.0};
  outcomes[1].predicted = {1.5, 7.0, 8.0};
  outcomes[0].O1 = 0.2;
  outcomes[1].O1 = 0.4;
  const StudySummary s = summarize(outcomes);
  EXPECT_DOUBLE_EQ(s.achieved_mean_mm, 1.5);
  EXPECT_DOUBLE_EQ(s.achieved_rms_mm, std::sqrt(12.5));  // √((9 + 16) / 2)
  EXPECT_DOUBLE_EQ(s.achieved_max_mm, 7.0);
  EXPECT_DOUBLE_EQ(s.predicted_mean_mm, 1.0);
  EXPECT_DOUBLE_EQ(s.predicted_rms_mm, 5.0);  // √((1 + 49) / 2)
  EXPECT_DOUBLE_EQ(s.O1, 0.3);
}

void expect_closed_loop_properties(const PlanStudyResult& r, const char* region) {
  SCOPED_TRACE(region);
  ASSERT_EQ(r.rows.size(), 2u);
  for (const StudyRow& row : r.rows) {
    for (const auto* design : {&row.optimal, &row.random})
      for (const StudyOutcome& o : *design) {
        EXPECT_EQ(o.measured, row.count);
        EXPECT_TRUE(o.converged);
      }
    const StudySummary optimal = summarize(row.optimal), random = summarize(row.random);
    const double opt = optimal.achieved_mean_mm, rnd = random.achieved_mean_mm;
    // Prediction before measuring (Cramér–Rao, σ²(JᵀJ)⁻¹) against the closed loop: the RMS
    // TCP error over the region (quadratic mean over the true robots) within 30 %.
    const double ratio_opt = optimal.achieved_rms_mm / optimal.predicted_rms_mm;
    const double ratio_rnd = random.achieved_rms_mm / random.predicted_rms_mm;
    std::printf(
        "[ study ] %s, %d configurations: D-optimal %.4f mm, random %.4f mm (gain %.2f); "
        "achieved/predicted RMS %.3f and %.3f\n",
        region, row.count, opt, rnd, rnd / opt, ratio_opt, ratio_rnd);
    EXPECT_LT(opt, rnd);
    EXPECT_NEAR(ratio_opt, 1.0, 0.3);
    EXPECT_NEAR(ratio_rnd, 1.0, 0.3);
  }
  // More configurations, better accuracy.
  EXPECT_LT(summarize(r.rows[1].optimal).achieved_mean_mm,
            summarize(r.rows[0].optimal).achieved_mean_mm);
  // Calibration pays: far below the nominal robot's error.
  EXPECT_LT(summarize(r.rows[1].optimal).achieved_mean_mm, 0.05 * r.nominal[0].mean_mm);
}

TEST(DesignPlan, ClosedLoopStudyOptimalBeatsRandomAndMatchesThePrediction) {
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  PlanStudyOptions options;
  options.counts = {15, 40};
  options.seeds = 4;
  options.seed = 3;
  options.plan.candidates = 800;
  options.task_count = 100;
  options.prior_count = 0;  // no effects outside the model: nothing for a prior to measure
  expect_closed_loop_properties(run_plan_study(model, tool, options), "joint box");
  // The same over a box of TCP positions (world frame) in front of the robot. Over a small
  // region the error concentrates in a few parameter directions, so one robot's RMS scatters
  // widely about the prediction (0.2–1.8× seen): more true robots for the same tolerance.
  options.seeds = 12;
  options.plan.candidates = 600;
  options.task_count = 60;
  options.task_box = parse_task_box("-500,-300,1100,1300,150,350", "--task-box");
  expect_closed_loop_properties(run_plan_study(model, tool, options), "TCP box");
}

}  // namespace
}  // namespace robcal
