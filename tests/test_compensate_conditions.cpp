// Compensation under each target's own condition (issue 19 item 2, docs/method/10-compensation.md
// §6): a true IRB 120 with backlash, thermal drift and two payloads besides its own, calibrated
// with the groups enabled; targets whose rows give their own approach, temperature and payload
// are reached to 1e-6 mm on the calibrated model under that condition (checked by the templated
// forward model, not the compensator's chain) and to the noise floor on the true robot, and the
// same targets compensated under the run's one condition miss by far more. Also the targets
// file's condition columns and their refusals.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <set>
#include <tuple>

#include "refusal.hpp"
#include "robcal/compensate/compensate_targets.hpp"
#include "robcal/compensate/compensation_setup.hpp"
#include "robcal/compensate/corrected_targets.hpp"
#include "robcal/core/error.hpp"
#include "robcal/identify/identification.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/pose_list_file.hpp"
#include "robcal/sim/simulator.hpp"
#include "test_error_groups_support.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

/// The published IRB 120 with the simulator's backlash and a 10 K warm-up (23 ppm/K).
TrueRobot worn_warm_truth() {
  TrueRobot truth = published_irb120_truth(load_robot("abb-irb120"), test::tool_with_payloads());
  truth.effects.backlash = true;
  truth.effects.thermal = true;
  truth.effects.temperature_rise_k = 10;
  return truth;
}

struct Calibrated {
  TrueRobot truth;
  CalibratedRobot robot;
};

/// 100 tracker readings (σ = 0.01 mm) approached from random sides during the warm-up, each
/// carrying one of the three payloads, calibrated at level full with backlash and thermal.
const Calibrated& calibrated() {
  static const Calibrated c = [] {
    Calibrated out{worn_warm_truth(), {}};
    SimulationOptions sim;
    sim.approach_random = true;
    sim.random_payloads = true;
    const MeasurementSet data =
        test::simulate_campaign(out.truth, 0.01, 2101, published_joint_box(out.truth.robot.model),
                                sim)
            .calibration;
    IdentifyOptions options;
    options.level = CalibrationLevel::Full;
    options.identify = {"*.backlash", "*.expansion"};
    out.robot =
        calibrate(load_robot("abb-irb120"), test::tool_with_payloads(), data, options).robot;
    return out;
  }();
  return c;
}

/// The condition of target k: sides, temperature and payload cycling through different values.
struct RowCondition {
  Vector6d approach;
  double temperature_c;
  std::string payload;  // empty: the tool's own
};
RowCondition row_condition(int k, std::mt19937_64& rng) {
  RowCondition c;
  for (int j = 0; j < kJointCount; ++j) c.approach[j] = rng() % 2 ? 1.0 : -1.0;
  c.temperature_c = 20 + 5 * (k % 3);  // 20, 25, 30 °C over the 20 °C reference
  static const char* const kPayloads[] = {"", "empty", "gripper"};
  c.payload = kPayloads[(k / 3) % 3];
  return c;
}

/// The truth's motion in a row's condition: each joint arriving from its side, at its
/// temperature, carrying its payload.
MotionState motion_of(const TrueRobot& truth, const RowCondition& c, const Vector6d& joints) {
  MotionState motion;
  motion.from_below = false;
  motion.previous_joints = joints - deg2rad(5.0) * c.approach;
  motion.temperature_rise_k = c.temperature_c - truth.robot.model.reference_temperature_c;
  motion.payload = truth.robot.tool.payload_index(c.payload);
  return motion;
}

struct Targets {
  std::vector<WantedTarget> wanted;
  std::vector<RowCondition> conditions;
};

/// `count` wanted poses: the true robot's TCP, in each row's condition, at random joints of the
/// published box 3° inside its edges and ≥ 10° from singularities; the rows give the condition.
Targets targets(const TrueRobot& truth, int count, std::mt19937_64& rng) {
  const auto box = published_joint_box(truth.robot.model);
  Pose<double> flange_T_tcp;
  flange_T_tcp.R = truth.robot.tool.flange_T_tcp.linear();
  flange_T_tcp.p = truth.robot.tool.flange_T_tcp.translation();
  Targets out;
  for (int k = 0; k < count;) {
    Vector6d j;
    for (int i = 0; i < kJointCount; ++i)
      j[i] = std::uniform_real_distribution<double>(box[i].lower + deg2rad(3),
                                                    box[i].upper - deg2rad(3))(rng);
    if (test::near_singular(truth.robot.model, j, 10)) continue;
    const RowCondition c = row_condition(k, rng);
    ++k;
    WantedTarget w;
    w.name = "t" + std::to_string(k);
    w.line = k + 1;
    w.world_T_tcp = true_flange_pose(truth, j, motion_of(truth, c, j)) * flange_T_tcp;
    w.config = arm_config(truth.robot.model, j);
    w.approach = c.approach;
    w.temperature_c = c.temperature_c;
    w.payload = c.payload;
    out.wanted.push_back(w);
    out.conditions.push_back(c);
  }
  return out;
}

/// Mean and largest distance (mm) of the true TCP, commanded to each row's corrected joints in
/// the row's true condition, from the wanted pose.
std::pair<double, double> true_errors_mm(const TrueRobot& truth, const Targets& t,
                                         const std::vector<CorrectedTarget>& rows,
                                         const Pose<double>& flange_T_tcp) {
  double sum = 0, worst = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const Vector6d& q = rows[i].ik.joints;
    const Pose<double> reached =
        true_flange_pose(truth, q, motion_of(truth, t.conditions[i], q)) * flange_T_tcp;
    const double e = (reached.p - t.wanted[i].world_T_tcp.p).norm();
    sum += e;
    worst = std::max(worst, e);
  }
  return {sum / static_cast<double>(rows.size()), worst};
}

TEST(CompensateConditions, EachTargetUnderItsOwnCondition) {
  const Calibrated& c = calibrated();
  const CalibratedRobot& robot = c.robot;
  ASSERT_EQ(robot.tool.payloads.size(), 2u);
  for (int joint = 1; joint <= kJointCount; ++joint)
    ASSERT_EQ(robot.status[static_cast<size_t>(backlash_param(joint))],
              ParameterStatus::Identified);
  for (const int link : {3, 4, 6})
    ASSERT_EQ(robot.status[static_cast<size_t>(expansion_param(link))],
              ParameterStatus::Identified);
  std::mt19937_64 rng(2102);
  const Targets t = targets(c.truth, 60, rng);

  CompensateTargetsRequest request;
  request.setup.robot = robot;
  request.targets = t.wanted;
  request.targets_file = "t.csv";
  request.truth = c.truth;
  const CompensateTargetsResult own = compensate_targets(request);
  ASSERT_EQ(own.rows.size(), t.wanted.size());

  // One compensator per distinct condition: every row has its own sides here.
  std::set<std::tuple<std::vector<double>, double, std::string>> distinct;
  for (const WantedTarget& w : t.wanted)
    distinct.emplace(std::vector<double>(w.approach->begin(), w.approach->end()), *w.temperature_c,
                     w.payload);
  EXPECT_EQ(own.conditions, static_cast<int>(distinct.size()));

  // On the calibrated model, by the templated forward model in the row's condition.
  const Compensator comp = make_compensator(robot);
  for (size_t i = 0; i < own.rows.size(); ++i) {
    const CorrectedTarget& r = own.rows[i];
    const RowCondition& rc = t.conditions[i];
    ASSERT_TRUE(r.ik.ok()) << r.name;
    EXPECT_EQ(r.condition.approach, rc.approach);
    EXPECT_EQ(r.condition.temperature_rise_k, rc.temperature_c - 20);
    EXPECT_EQ(r.condition.payload_name, rc.payload);
    const PointMass& payload = robot.tool.payload_of(robot.tool.payload_index(rc.payload));
    const Pose<double> model_tcp = flange_pose(robot.model, payload, robot.params, r.ik.joints,
                                               {&rc.approach, rc.temperature_c - 20}) *
                                   comp.flange_T_tcp;
    EXPECT_LT((model_tcp.p - t.wanted[i].world_T_tcp.p).norm(), 1e-6) << r.name;
  }

  // On the true robot: the closed loop in each row's condition, and the same by hand.
  const auto [own_mean, own_max] = true_errors_mm(c.truth, t, own.rows, comp.flange_T_tcp);
  ASSERT_TRUE(own.closed_loop);
  EXPECT_NEAR(own.closed_loop->compensated.mean_mm, own_mean, 1e-12);

  // The same targets with the rows' approach, temperature or payload left out, or all three:
  // those come from the run (from below, 20 °C, the tool's payload) and miss on the true robot.
  const auto run_condition_errors = [&](bool approach, bool temperature, bool payload) {
    request.targets = t.wanted;
    for (WantedTarget& w : request.targets) {
      if (approach) w.approach.reset();
      if (temperature) w.temperature_c.reset();
      if (payload) w.payload.clear();
    }
    const CompensateTargetsResult r = compensate_targets(request);
    if (approach && temperature && payload) {
      EXPECT_EQ(r.conditions, 1);
    }
    return true_errors_mm(c.truth, t, r.rows, comp.flange_T_tcp);
  };
  const auto [sides_mean, sides_max] = run_condition_errors(true, false, false);
  const auto [warm_mean, warm_max] = run_condition_errors(false, true, false);
  const auto [load_mean, load_max] = run_condition_errors(false, false, true);
  const auto [run_mean, run_max] = run_condition_errors(true, true, true);
  std::printf(
      "true TCP error (mean / max mm), %zu targets in %d conditions: each row's own %.4f / %.4f; "
      "the run's approach %.4f / %.4f, temperature %.4f / %.4f, payload %.4f / %.4f, all three "
      "%.4f / %.4f; uncompensated %.4f / %.4f\n",
      t.wanted.size(), own.conditions, own_mean, own_max, sides_mean, sides_max, warm_mean,
      warm_max, load_mean, load_max, run_mean, run_max, own.closed_loop->uncompensated.mean_mm,
      own.closed_loop->uncompensated.max_mm);
  // Measured: 0.0082 / 0.0183 mm own; the run's approach 0.096, temperature 0.056, payload
  // 0.43, all three 0.47 / 1.73 mm.
  EXPECT_LT(own_mean, 0.015);  // the noise propagated through the fit (σ = 0.01 mm)
  EXPECT_LT(own_max, 0.04);
  EXPECT_GT(sides_mean, 5 * own_mean);
  EXPECT_GT(warm_mean, 4 * own_mean);
  EXPECT_GT(load_mean, 20 * own_mean);
  EXPECT_GT(run_mean, 20 * own_mean);
  EXPECT_GT(run_max, 1.0);
}

// The targets file's condition columns in the measurement file's notation (any order, trailing
// cells optional, empty: the run's), the corrected CSV recording each row's condition, and bad
// cells refused at file:line:column (key) with the measurement reader's own messages.
// A program's points are reached from the previous point: each joint from the side of its
// move (make_program_corrector's `by_approach`, `compensate-program --approach motion`). A path
// of 80 RAPID targets with reversals on every joint, executed on the true robot (backlash by the
// actual commanded moves, at the reference temperature, with the tool's own payload): corrected
// under each move's side the true error is at the noise floor, under the run's one side
// (every joint from below) the backlash stays.
TEST(CompensateConditions, ProgramPointsUnderTheSideOfTheirMove) {
  const Calibrated& c = calibrated();
  const Compensation run{c.robot, make_compensator(c.robot), {}};
  const Compensator& comp = run.comp;
  Pose<double> flange_T_tcp;
  flange_T_tcp.R = c.truth.robot.tool.flange_T_tcp.linear();
  flange_T_tcp.p = c.truth.robot.tool.flange_T_tcp.translation();
  const auto box = published_joint_box(c.truth.robot.model);
  // The truth reaching q from `from`, each joint from the side of its move.
  const auto reached = [&](const Vector6d& q, const std::optional<Vector6d>& from) {
    MotionState motion;
    motion.temperature_rise_k = 0;
    if (from) {
      motion.from_below = false;
      motion.previous_joints = *from;
    }
    return Pose<double>(true_flange_pose(c.truth, q, motion) * flange_T_tcp);
  };
  std::mt19937_64 rng(2103);
  std::uniform_real_distribution<double> step(-deg2rad(4), deg2rad(4));
  std::vector<ProgramPoint> points;
  std::vector<Pose<double>> wanted;
  Vector6d q = Vector6d::Zero();
  q[1] = deg2rad(10);
  q[4] = deg2rad(40);
  std::optional<Vector6d> from;
  while (points.size() < 80) {
    Vector6d next = q;
    for (int i = 0; i < kJointCount; ++i) next[i] += step(rng);
    bool inside = true;
    for (int i = 0; i < kJointCount; ++i)
      inside &= next[i] > box[i].lower + deg2rad(3) && next[i] < box[i].upper - deg2rad(3);
    if (!inside || test::near_singular(c.truth.robot.model, next, 10)) continue;
    q = next;
    wanted.push_back(reached(q, from));
    from = q;
    ProgramPoint point;
    point.base_T_tcp = comp.base_T_world * wanted.back();
    point.config = maker_configuration(comp, ProgramLanguage::Rapid, q);
    points.push_back(point);
  }
  CompensatorsByCondition by_condition(run);
  const ApproachCompensators by_approach = [&](const Vector6d& approach) -> const Compensator& {
    ReachCondition condition = comp.condition;
    condition.approach = approach;
    return by_condition.at(condition);
  };
  // The corrected joints executed in order on the truth; mean and largest error (mm).
  const auto execute = [&](const PointCorrector& corrector) {
    double sum = 0, worst = 0;
    std::optional<Vector6d> previous;
    for (size_t k = 0; k < points.size(); ++k) {
      const CorrectedPoint p = corrector(points[k]);
      EXPECT_TRUE(p.failure.empty()) << p.failure;
      const Vector6d joints = p.joints_deg * kDegToRad;
      const double e = (reached(joints, previous).p - wanted[k].p).norm();
      sum += e;
      worst = std::max(worst, e);
      previous = joints;
    }
    return std::pair{sum / static_cast<double>(points.size()), worst};
  };
  const auto [motion_mean, motion_max] =
      execute(make_program_corrector(comp, ProgramLanguage::Rapid, nullptr, by_approach));
  const auto [run_mean, run_max] = execute(make_program_corrector(comp, ProgramLanguage::Rapid));
  std::printf(
      "program path, 80 points on the true robot: each move's side %.4f / %.4f mm, the "
      "run's side %.4f / %.4f mm (mean / max); %zu compensators\n",
      motion_mean, motion_max, run_mean, run_max, by_condition.made());
  EXPECT_LT(motion_mean, 0.02);
  EXPECT_GT(run_mean, 3 * motion_mean);
  EXPECT_GT(by_condition.made(), 10u);
}

TEST(CompensateConditions, TargetsFileColumns) {
  const std::vector<ListedPose> poses = parse_pose_list(
      "name,x,y,z,qw,qx,qy,qz,payload,temperature,approach,config\n"
      "p1,400,0,500,0,0,1,0,gripper,31.5,+-0+++,front-up-noflip\n"
      "p2,410,0,500,0,0,1,0,,,\n"
      "p3,420,0,500,0,0,1,0\n",
      "t.csv");
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_EQ(poses[0].payload, "gripper");
  EXPECT_EQ(poses[0].payload_column, 22);
  EXPECT_EQ(poses[0].temperature_c, 31.5);
  Vector6d sides;
  sides << 1, -1, 0, 1, 1, 1;
  EXPECT_EQ(poses[0].approach, sides);
  EXPECT_TRUE(poses[0].config.has_value());
  for (const size_t i : {1u, 2u}) {
    EXPECT_TRUE(poses[i].payload.empty());
    EXPECT_FALSE(poses[i].temperature_c || poses[i].approach || poses[i].config);
  }

  const std::string header = "name,x,y,z,qw,qx,qy,qz,approach,temperature\n";
  EXPECT_REFUSED(parse_pose_list(header + "p1,400,0,500,0,0,1,0,++x+++,\n", "t.csv"), InputError,
                 "t.csv:2:22 (approach): '++x+++' is not an approach");
  EXPECT_REFUSED(parse_pose_list(header + "p1,400,0,500,0,0,1,0,,451\n", "t.csv"), InputError,
                 "t.csv:2:23 (temperature): temperature 451 °C is implausible");
  EXPECT_REFUSED(parse_pose_list(header + "p1,400,0,500,0,0,1,0,,warm\n", "t.csv"), InputError,
                 "t.csv:2:23 (temperature): 'warm' is not a number");
  EXPECT_REFUSED(parse_pose_list("name,x,y,z,qw,qx,qy,qz,approach,approach\n", "t.csv"), InputError,
                 "t.csv:1:33 (approach): column 'approach' appears twice");
  // The warm-up time (s, or warm), as the measurement file's `time_s` column.
  const std::vector<ListedPose> timed = parse_pose_list(
      "name,x,y,z,qw,qx,qy,qz,time_s\np1,400,0,500,0,0,1,0,125.5\np2,410,0,500,0,0,1,0,warm\n"
      "p3,420,0,500,0,0,1,0,\n",
      "t.csv");
  EXPECT_EQ(timed[0].time_s, 125.5);
  EXPECT_EQ(timed[1].time_s, kFullyWarmS);
  EXPECT_FALSE(timed[2].time_s.has_value());
  const std::string time_header = "name,x,y,z,qw,qx,qy,qz,time_s\n";
  EXPECT_REFUSED(parse_pose_list(time_header + "p1,400,0,500,0,0,1,0,-5\n", "t.csv"), InputError,
                 "t.csv:2:22 (time_s): time -5 s is implausible: expected seconds in [0, 1e7]");
  EXPECT_REFUSED(parse_pose_list(time_header + "p1,400,0,500,0,0,1,0,nan\n", "t.csv"), InputError,
                 "t.csv:2:22 (time_s): ");
  EXPECT_REFUSED(parse_pose_list(time_header + "p1,400,0,500,0,0,1,0,hot\n", "t.csv"), InputError,
                 "t.csv:2:22 (time_s): 'hot' is not a number");
  // The measurement reader says the same of the same cell.
  EXPECT_REFUSED(parse_measurements_csv("config,target,j1,j2,j3,j4,j5,j6,x,y,z,temperature\n"
                                        "c1,1,0,10,20,30,40,50,100,200,300,451\n",
                                        "m.csv", default_simulation_tool()),
                 InputError, "m.csv:2:12 (temperature): temperature 451 °C is implausible");

  std::mt19937_64 rng(2103);
  CompensateTargetsRequest request;
  request.setup.robot = test::random_calibrated("abb-irb120", rng);
  request.setup.robot.tool.payloads = test::tool_with_payloads().payloads;
  request.setup.temperature_c = 22;
  // Two poses the calibrated robot reaches, as a targets file writes them.
  const Compensator comp = make_compensator(request.setup.robot);
  const auto pose_cells = [&](const Vector6d& joints_deg) {
    const Pose<double> p = calibrated_tcp_pose(comp.chain, joints_deg * kDegToRad);
    const Eigen::Quaterniond q(p.R);
    return fmt::format("{:.9f},{:.9f},{:.9f},{:.12f},{:.12f},{:.12f},{:.12f}", p.p.x(), p.p.y(),
                       p.p.z(), q.w(), q.x(), q.y(), q.z());
  };
  const std::string p1 = pose_cells((Vector6d() << 10, 20, 10, 30, 40, 50).finished());
  const std::string p2 = pose_cells((Vector6d() << -10, 25, 5, 20, 50, 40).finished());
  request.targets = parse_pose_list(
      "name,x,y,z,qw,qx,qy,qz,approach,temperature,payload\n"
      "p1," +
          p1 +
          ",+-0+++,31.5,gripper\n"
          "p2," +
          p2 + "\n",
      "t.csv");
  request.targets_file = "t.csv";
  const CompensateTargetsResult r = compensate_targets(request);
  EXPECT_EQ(r.conditions, 2);
  EXPECT_NE(r.csv.find(",approach,temperature,payload\n"), std::string::npos) << r.csv;
  EXPECT_NE(r.csv.find(",+-0+++,31.5,gripper\n"), std::string::npos) << r.csv;
  EXPECT_NE(r.csv.find(",++++++,22,\n"), std::string::npos) << r.csv;  // the run's
  request.targets[1].approach.reset();
  request.targets[0] = request.targets[1];
  request.targets[0].name = "p0";
  EXPECT_EQ(compensate_targets(request).csv.find("approach"), std::string::npos);

  // A row's own warm-up time, and the run's --warm for the others: the CSV's time_s column.
  request.targets =
      parse_pose_list("name,x,y,z,qw,qx,qy,qz,time_s\np1," + p1 + ",600\np2," + p2 + "\n", "t.csv");
  request.setup.warm = true;
  const CompensateTargetsResult warm = compensate_targets(request);
  EXPECT_EQ(warm.conditions, 2);
  EXPECT_NE(warm.csv.find(",approach,temperature,payload,time_s\n"), std::string::npos);
  EXPECT_NE(warm.csv.find(",++++++,22,,600\n"), std::string::npos) << warm.csv;
  EXPECT_NE(warm.csv.find(",++++++,22,,warm\n"), std::string::npos) << warm.csv;
  EXPECT_EQ(warm.rows[1].condition.warmup_fraction, 1.0);
  EXPECT_EQ(warm.rows[0].condition.warmup_fraction,
            warmup_fraction(request.setup.robot.model, 600));
  request.setup.warm = false;

  request.targets =
      parse_pose_list("name,x,y,z,qw,qx,qy,qz,payload\np1,400,0,500,0,0,1,0,vise\n", "t.csv");
  EXPECT_REFUSED(compensate_targets(request), InputError,
                 "t.csv:2:22 (payload): unknown payload 'vise': expected a name under "
                 "'payloads:' in the tool file ('empty', 'gripper'), or empty for the run's");
}

}  // namespace
}  // namespace robcal
