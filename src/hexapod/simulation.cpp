#include "robcal/hexapod/simulation.hpp"

#include <fmt/format.h>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/measure/instrument.hpp"
#include "robcal/sim/simulator.hpp"

namespace robcal::hexapod {
namespace {

TriangleSides measure_sides(const Cups<double>& cups, double nominal, const HexapodCellOptions& o,
                            std::mt19937_64& rng) {
  Ballbar bar{cups[0], nominal, o.sigma_mm, o.range_mm};
  std::array<double, 3> d{};
  for (int i = 0; i < 3; ++i) {
    bar.centre_mm = cups[i];
    const std::optional<double> r = read_length(bar, cups[(i + 1) % 3], rng);
    if (!r)
      throw InputError({"", 0, 0, "fixture"},
                       fmt::format("fixture side {}-{} = {:.3f} mm is outside the ballbar's ±{} mm "
                                   "range about {} mm",
                                   i + 1, (i + 1) % 3 + 1, (cups[i] - cups[(i + 1) % 3]).norm(),
                                   o.range_mm, nominal));
    d[i] = *r;
  }
  return {d[0], d[1], d[2]};
}

/// A fourth cup's distances to cups 1..3 of its fixture, each read at its design length.
std::array<double, 3> measure_fourth_cup(const Cups<double>& cups, const Eigen::Vector3d& fourth,
                                         const std::array<double, 3>& design, char letter,
                                         const HexapodCellOptions& o, std::mt19937_64& rng) {
  std::array<double, 3> measured{};
  for (int j = 0; j < 3; ++j) {
    const Ballbar bar{cups[j], design[j], o.sigma_mm, o.range_mm};
    const std::optional<double> r = read_length(bar, fourth, rng);
    if (!r)
      throw InputError(
          {"", 0, 0, letter == 'T' ? "tool_cup4_mm" : "base_cup4_mm"},
          fmt::format("{} cup {}4 is {:.3f} mm from {}{}, outside the ballbar's ±{} "
                      "mm about its design {} mm",
                      letter == 'T' ? "tool" : "base", letter, (fourth - cups[j]).norm(), letter,
                      j + 1, o.range_mm, design[j]));
    measured[j] = *r;
  }
  return measured;
}

/// One leg's reading with the true flange at `sim_T_flange`.
std::optional<double> read_leg(const SimulatedHexapodCell& cell, const PhysicalLeg& leg,
                               const Pose<double>& sim_T_flange, std::mt19937_64& rng) {
  const Eigen::Vector3d& base_cup =
      leg.base < 3 ? cell.base_cups_sim[leg.base] : cell.base_cup4_sim.value();
  const Ballbar bar{base_cup, cell.options.design.leg_mm, cell.options.sigma_mm,
                    cell.options.range_mm};
  const Eigen::Vector3d& tool_cup =
      leg.tool < 3 ? cell.tool_cups_flange[leg.tool] : cell.tool_cup4_flange.value();
  return read_length(bar, sim_T_flange * tool_cup, rng);
}

}  // namespace

TrueRobot levelled_random_truth(const RobotModel& model, const PointMass& payload,
                                const ErrorBounds& errors, std::mt19937_64& rng) {
  Tool carried;
  carried.payload = payload;
  TrueRobot truth = random_truth(model, carried, errors, rng, {0, 0, 0, 0, 0, 0});
  truth.robot.params[3] = truth.robot.params[4] = 0;
  return truth;
}

SimulatedHexapodCell set_up_simulated_cell(const TrueRobot& truth, const RobotModel& nominal,
                                           const HexapodCellOptions& options,
                                           std::mt19937_64& rng) {
  SimulatedHexapodCell c;
  c.truth = truth;
  c.nominal = nominal;
  c.options = options;
  const auto geometry = analyze_ortho_parallel(nominal);
  if (!geometry) throw InputError({"", 0, 0, "robot"}, nominal.name + " is not ortho-parallel");
  // The true tool fixture: its sides within the tolerance of the design.
  std::uniform_real_distribution<double> tolerance(-options.fixture_tolerance_mm,
                                                   options.fixture_tolerance_mm);
  const TriangleSides& t = options.design.tool;
  const TriangleSides true_tool{t.d12 + tolerance(rng), t.d23 + tolerance(rng),
                                t.d31 + tolerance(rng)};
  const Pose<double> flange_T_tool =
      default_tool_mount(options.design.tool, options.tool_offset_mm);
  const Cups<double> tool_local = fixture_cups(true_tool, "tool fixture");
  for (int j = 0; j < 3; ++j) c.tool_cups_flange[j] = flange_T_tool * tool_local[j];
  // The robot puts the setting ball at three points leg_mm apart by its own model; each cup
  // snaps on where the ball truly is.
  c.setting_points = setting_ball_points(options.placement, options.design.leg_mm);
  const Eigen::Vector3d ball_flange(0, 0, options.ball_offset_mm);
  // The true cup where the nominal model puts the ball for base cup `cup` (1-based).
  const auto place_cup = [&](const Eigen::Vector3d& point, int cup) {
    Pose<double> robot_T_flange;
    robot_T_flange.R =
        Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix() * options.placement.R;
    robot_T_flange.p = point - robot_T_flange.R * ball_flange;
    const IkResult ik = nominal_ik(*geometry, robot_T_flange);
    const IkSolution* s = nearest_solution(ik, Vector6d::Zero());
    if (s == nullptr)
      throw InputError({"", 0, 0, cup == 4 ? "--base-cup4-mm" : "--placement"},
                       fmt::format("the robot cannot put the setting ball at base cup B{} ({})",
                                   cup, to_string(ik.status)));
    return Eigen::Vector3d(true_flange_pose(truth, s->joints) * ball_flange);
  };
  for (int i = 0; i < 3; ++i) c.base_cups_sim[i] = place_cup(c.setting_points[i], i + 1);
  if (const auto& design4 = options.design.base_cup4_mm) {
    // B4 is placed by the robot like B1..B3: off its design position by the robot's error there.
    c.setting_point4 = fourth_setting_ball_point(c.setting_points, *design4);
    c.base_cup4_sim = place_cup(*c.setting_point4, 4);
    c.base_cup4_mm =
        measure_fourth_cup(c.base_cups_sim, *c.base_cup4_sim, *design4, 'B', options, rng);
  }
  c.tool_sides = measure_sides(c.tool_cups_flange, options.design.tool.d12, options, rng);
  if (const auto& design4 = options.design.tool_cup4_mm) {
    // The true T4: where the design puts it, within the tolerance per axis (not trilaterated on
    // the true triangle: off its plane that amplifies the tolerance to √(tolerance·d14));
    // each distance read at its own set-up, its design length.
    Eigen::Vector3d local = fixture_cup_positions(options.design.tool_fixture())[3];
    for (int a = 0; a < 3; ++a) local[a] += tolerance(rng);
    c.tool_cup4_flange = flange_T_tool * local;
    c.tool_cup4_mm =
        measure_fourth_cup(c.tool_cups_flange, *c.tool_cup4_flange, *design4, 'T', options, rng);
  }
  c.base_sides = measure_sides(c.base_cups_sim, options.design.leg_mm, options, rng);
  c.world = fit_world_frame(c.setting_points, c.base_sides);
  c.world_T_sim = frame_from_cups(c.base_cups_sim).inverse();
  c.cell.robot_T_base = c.world.robot_T_fixture;
  c.cell.flange_T_tool = flange_T_tool;
  c.cell.table_z_mm = options.table_z_mm;
  return c;
}

std::optional<double> simulate_leg(const SimulatedHexapodCell& cell, const PhysicalLeg& leg,
                                   const Vector6d& joints, std::mt19937_64& rng) {
  return read_leg(cell, leg, true_flange_pose(cell.truth, joints), rng);
}

std::optional<double> simulate_session_reading(const SimulatedHexapodCell& cell,
                                               const SessionPlan& plan, const SessionStep& step,
                                               std::mt19937_64& rng) {
  switch (step.kind) {
    case StepKind::ToolSide:
      return step.item < 3 ? cell.tool_sides.as_array()[step.item]
                           : cell.tool_cup4_mm.value()[step.item - 3];
    case StepKind::BaseSide:
      return step.item < 3 ? cell.base_sides.as_array()[step.item]
                           : cell.base_cup4_mm.value()[step.item - 3];
    case StepKind::CalibratorCheck:
      return plan.leg_mm + std::normal_distribution<double>(0, cell.options.sigma_mm)(rng);
    case StepKind::Leg:
      break;
  }
  const SessionConfiguration& c = plan.configurations[step.configuration];
  if (c.joints_deg.size() != kJointCount)
    throw InputError({"", 0, 0, fmt::format("configurations[{}].joints_deg", step.configuration)},
                     "the simulator needs the joints of every configuration");
  Vector6d q;
  for (int i = 0; i < kJointCount; ++i) q[i] = deg2rad(c.joints_deg[i]);
  return simulate_leg(cell, c.legs[step.item], q, rng);
}

TrackerValidation simulate_tracker_validation(const SimulatedHexapodCell& cell,
                                              const Eigen::Vector3d& point_flange, int count,
                                              double sigma_mm, std::mt19937_64& rng) {
  const std::array<JointLimit, kJointCount> box = published_joint_box(cell.nominal);
  LaserTracker tracker;
  tracker.sigma_mm = Eigen::Vector3d::Constant(sigma_mm);
  TrackerValidation v;
  v.measured.resize(3, count);
  for (int k = 0; k < count; ++k) {
    Vector6d q;
    for (int i = 0; i < kJointCount; ++i)
      q[i] = std::uniform_real_distribution<double>(box[i].lower, box[i].upper)(rng);
    v.joints.push_back(q);
    v.measured.col(k) =
        cell.world_T_sim * read_point(tracker, true_flange_pose(cell.truth, q) * point_flange, rng);
  }
  return v;
}

std::optional<LegLengths<double>> simulate_legs(const SimulatedHexapodCell& cell,
                                                const HexapodPose& pose, const Vector6d& joints,
                                                std::mt19937_64& rng, int* out_of_range) {
  const Pose<double> sim_T_flange = true_flange_pose(cell.truth, joints);  // once for six legs
  LegLengths<double> legs{};
  for (size_t i = 0; i < kDesignLegs.size(); ++i) {
    const std::optional<double> r = read_leg(cell, pose.legs[i], sim_T_flange, rng);
    if (!r) {
      if (out_of_range != nullptr) *out_of_range = static_cast<int>(i);
      return std::nullopt;
    }
    legs[i] = *r;
  }
  return legs;
}

std::optional<LegReadings> simulate_pose_readings(const SimulatedHexapodCell& cell,
                                                  const HexapodPose& pose, std::string config,
                                                  const Vector6d& joints, std::mt19937_64& rng) {
  const std::optional<LegLengths<double>> design = simulate_legs(cell, pose, joints, rng);
  if (!design) return std::nullopt;
  LegReadings r{std::move(config), joints, pose.design, pose.mode, *design, {}};
  const Pose<double> sim_T_flange = true_flange_pose(cell.truth, joints);
  for (size_t i = kDesignLegs.size(); i < pose.legs.size(); ++i) {
    const std::optional<double> reading = read_leg(cell, pose.legs[i], sim_T_flange, rng);
    if (!reading) return std::nullopt;
    r.extra_legs.push_back({pose.legs[i].base, pose.legs[i].tool, *reading});
  }
  return r;
}

}  // namespace robcal::hexapod
