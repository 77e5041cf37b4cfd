// The cell file and feasibility in a cell (issue 16 items 1 and 2): the shipped default cell is
// the simulator's; hand-built configurations are rejected for the reason built into them; the
// counts per reason over a seeded random set match an independent brute-force geometry check
// (sampled points, no closed-form distances); bad cells are refused with their place.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <random>

#include "robcal/campaign/cell.hpp"
#include "robcal/campaign/cell_planning.hpp"
#include "robcal/campaign/feasibility.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/simulator.hpp"
#include "test_support.hpp"

namespace robcal::campaign {
namespace {

std::string error_of(const std::string& yaml) {
  try {
    parse_cell(yaml, "cell.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

/// A cell with the robot at the world origin and the tracker at `tracker`; target 1's SMR
/// points back along −z of the flange (towards the robot at the home pose).
std::string hand_cell(const std::string& tracker, const std::string& extra = "") {
  return fmt::format(
      "format: robcal-cell\n"
      "robot_base: {{position_mm: [0, 0, 0], rotation_xyz_deg: [0, 0, 0]}}\n"
      "instrument:\n"
      "  kind: laser-tracker\n"
      "  position_mm: [{}]\n"
      "  target_axes_flange: {{\"1\": [0, 0, -1]}}\n"
      "link_radius_mm: 40\n{}",
      tracker, extra);
}

Tool target_one() {
  Tool tool;
  tool.targets = {{"1", Eigen::Vector3d(0, 0, 125), true}};
  return tool;
}

TEST(CampaignCell, DefaultCellIsTheSimulatorsCell) {
  const Cell cell = load_cell(test::data_path("../../data/cells/default-tracker.yaml"));
  const auto base = default_base_placement();
  for (int i = 0; i < 6; ++i)
    EXPECT_DOUBLE_EQ(cell.robot_base[static_cast<size_t>(i)],
                     i < 3 ? base[static_cast<size_t>(i)] : deg2rad(base[static_cast<size_t>(i)]));
  const RobotModel model = load_robot("abb-irb120");
  const TrueRobot truth = published_irb120_truth(model, default_simulation_tool());
  const LaserTracker tracker = standard_instrument(InstrumentKind::LaserTracker, truth).tracker;
  EXPECT_EQ(cell.instrument.kind, InstrumentKind::LaserTracker);
  EXPECT_EQ(cell.instrument.position_mm, tracker.position_mm);
  EXPECT_EQ(cell.instrument.cone_half_angle_deg, tracker.cone_half_angle_deg);
  EXPECT_EQ(cell.instrument.max_range_mm, tracker.max_range_mm);

  // Where the cell says a target is facing and in range (occluded or not), the simulator's own
  // visibility test agrees, over 500 random configurations of the published box.
  const Tool tool = default_simulation_tool();
  std::mt19937_64 rng(3);
  const auto box = published_joint_box(model);
  int compared = 0;
  for (int k = 0; k < 500; ++k) {
    Vector6d q;
    for (int j = 0; j < kJointCount; ++j)
      q[j] = std::uniform_real_distribution<double>(box[j].lower, box[j].upper)(rng);
    const Pose<double> flange = flange_pose(model, PointMass{}, cell.robot_params(model), q);
    for (int t = 0; t < 3; ++t) {
      const Feasibility f = check_configuration(cell, model, tool, q, t);
      if (f.reason == Rejection::BelowFloor || f.reason == Rejection::Collision) continue;
      const bool cell_sees = f.reason == Rejection::None || f.reason == Rejection::Occluded;
      const bool simulator_sees =
          smr_visible(tracker, flange * tool.targets[static_cast<size_t>(t)].position_mm,
                      flange.R * smr_axis_flange(tracker, tool, t));
      EXPECT_EQ(cell_sees, simulator_sees) << "configuration " << k << " target " << t;
      ++compared;
    }
  }
  EXPECT_GT(compared, 800);
}

TEST(CampaignCell, HandBuiltConfigurationsAreRejectedForTheirReason) {
  // The IRB 120 at home: flange at (374, 0, 630) with its z along +x, so target 1 is at
  // (499, 0, 630) and its SMR (flange −z) points along −x, back over the robot. The forearm
  // runs from the elbow (0, 0, 630) to the wrist (302, 0, 630).
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = target_one();
  const Vector6d home = Vector6d::Zero();
  const auto reason = [&](const std::string& yaml) {
    return check_configuration(parse_cell(yaml, "cell.yaml"), model, tool, home, 0);
  };
  // Behind and above: the line of sight rises 23.5° over the forearm (≥ 49 mm from every link
  // axis, capsules 40 mm): measurable.
  Feasibility f = reason(hand_cell("-1500, 0, 1500"));
  EXPECT_EQ(f.reason, Rejection::None) << f.detail;
  // Behind at the forearm's height: the line of sight runs along the forearm.
  f = reason(hand_cell("-1500, 0, 630"));
  EXPECT_EQ(f.reason, Rejection::Occluded) << f.detail;
  EXPECT_NE(f.detail.find("link 3"), std::string::npos) << f.detail;
  // In front: the SMR faces away (180°).
  f = reason(hand_cell("1500, 0, 630"));
  EXPECT_EQ(f.reason, Rejection::NotFacing) << f.detail;
  // A box around the wrist.
  f = reason(hand_cell(
      "-1500, 0, 1500",
      "keep_out: [{name: fixture, min_mm: [250, -100, 550], max_mm: [450, 100, 700]}]\n"));
  EXPECT_EQ(f.reason, Rejection::Collision) << f.detail;
  EXPECT_NE(f.detail.find("fixture"), std::string::npos);
  // A box on the line of sight only: at x = −950 the sight line is at z = 1260.6.
  f = reason(hand_cell(
      "-1500, 0, 1500",
      "keep_out: [{name: lamp, min_mm: [-1000, -100, 1200], max_mm: [-900, 100, 1300]}]\n"));
  EXPECT_EQ(f.reason, Rejection::Occluded) << f.detail;
  EXPECT_NE(f.detail.find("lamp"), std::string::npos);
  // The same box 100 mm lower misses it (the line falls to z = 1238.9 at the box's x = −900
  // face, the box top is at 1200).
  f = reason(hand_cell(
      "-1500, 0, 1500",
      "keep_out: [{name: lamp, min_mm: [-1000, -100, 1100], max_mm: [-900, 100, 1200]}]\n"));
  EXPECT_EQ(f.reason, Rejection::None) << f.detail;
  // A table top above the wrist.
  f = reason(hand_cell("-1500, 0, 1500", "floor_z_mm: 600\n"));
  EXPECT_EQ(f.reason, Rejection::BelowFloor) << f.detail;
  // A tracker whose range ends before the target (2180 mm away).
  f = reason(hand_cell("-1500, 0, 1500")
                 .replace(hand_cell("-1500, 0, 1500").find("  target_axes"), 0,
                          "  range_mm: [0, 2000]\n"));
  EXPECT_EQ(f.reason, Rejection::OutOfRange) << f.detail;
  // Outside the joint limits.
  Vector6d far = home;
  far[0] = deg2rad(170);
  EXPECT_EQ(
      check_configuration(parse_cell(hand_cell("-1500, 0, 1500"), "c"), model, tool, far, 0).reason,
      Rejection::JointLimits);
}

/// The independent check: every distance by sampling points (0.5 mm apart on sight lines, 1 mm
/// on links), every angle by acos; `ambiguous` when a sampled quantity is within the sampling
/// error of its threshold.
struct BruteForce {
  Rejection reason = Rejection::None;
  bool ambiguous = false;
};

BruteForce brute_force(const Cell& cell, const RobotModel& model, const Tool& tool,
                       const Vector6d& q) {
  BruteForce out;
  if (!model.within_limits(q)) return {Rejection::JointLimits, false};
  const ParameterVector params = cell.robot_params(model);
  const auto frames = link_frames(model, PointMass{}, params.data(), q.data());
  // Link axes as polylines of points: base origin, then per link its origin, the point a_{i+1}
  // along its x axis, the next origin.
  std::vector<std::vector<Eigen::Vector3d>> links;
  const auto sample = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, double step) {
    std::vector<Eigen::Vector3d> pts;
    const int n = std::max(1, static_cast<int>((b - a).norm() / step));
    for (int k = 0; k <= n; ++k) pts.push_back(a + (b - a) * (static_cast<double>(k) / n));
    return pts;
  };
  links.push_back(sample(Eigen::Vector3d(params[0], params[1], params[2]), frames[0].p, 1.0));
  for (int i = 0; i < 5; ++i) {
    Pose<double> to_elbow;
    to_elbow.p = Eigen::Vector3d(params[link_param(i + 2, 1)], 0, 0);
    const Eigen::Vector3d elbow = (frames[static_cast<size_t>(i)] * to_elbow).p;
    auto pts = sample(frames[static_cast<size_t>(i)].p, elbow, 1.0);
    const auto rest = sample(elbow, frames[static_cast<size_t>(i + 1)].p, 1.0);
    pts.insert(pts.end(), rest.begin(), rest.end());
    links.push_back(pts);
  }
  const double r = cell.link_radius_mm;
  const auto near = [&](double value, double threshold, double tolerance) {
    if (std::abs(value - threshold) < tolerance) out.ambiguous = true;
  };
  double lowest = 1e300;
  for (size_t l = 1; l < links.size(); ++l)
    for (const auto& p : links[l]) lowest = std::min(lowest, p.z());
  const Eigen::Vector3d target = frames[5] * tool.targets[0].position_mm;
  near(lowest - r, cell.floor_z_mm, 1e-6);
  if (lowest - r < cell.floor_z_mm || target.z() < cell.floor_z_mm)
    return {Rejection::BelowFloor, out.ambiguous};
  const auto box_distance = [](const KeepOutBox& b, const Eigen::Vector3d& p) {
    Eigen::Vector3d d;
    for (int k = 0; k < 3; ++k) d[k] = std::max({b.min_mm[k] - p[k], 0.0, p[k] - b.max_mm[k]});
    return d.norm();
  };
  for (const KeepOutBox& b : cell.keep_out) {
    double closest = 1e300;
    for (const auto& link : links)
      for (const auto& p : link) closest = std::min(closest, box_distance(b, p));
    near(closest, r, 0.2);
    if (closest < r || box_distance(b, target) == 0) return {Rejection::Collision, out.ambiguous};
  }
  const Eigen::Vector3d los = cell.instrument.position_mm - target;
  if (los.norm() > cell.instrument.max_range_mm) return {Rejection::OutOfRange, out.ambiguous};
  const Eigen::Vector3d axis =
      frames[5].R * (cell.instrument.target_axes_flange.empty()
                         ? Eigen::Vector3d(tool.targets[0].position_mm.normalized())
                         : cell.instrument.target_axes_flange[0].second);
  const double angle = rad2deg(std::acos(std::clamp(axis.dot(los) / los.norm(), -1.0, 1.0)));
  near(angle, cell.instrument.cone_half_angle_deg, 1e-6);
  if (angle > cell.instrument.cone_half_angle_deg) return {Rejection::NotFacing, out.ambiguous};
  const auto sight = sample(target, cell.instrument.position_mm, 0.5);
  double closest = 1e300, box_closest = 1e300;
  for (const auto& s : sight) {
    for (const auto& link : links)
      for (size_t k = 0; k + 1 < link.size(); k += 8)
        closest = std::min(closest, (link[k] - s).norm());
    for (const KeepOutBox& b : cell.keep_out)
      box_closest = std::min(box_closest, box_distance(b, s));
  }
  near(closest, r, 3.0);  // link points every 8 mm: up to 4 mm of sampling error
  near(box_closest, 0, 0.3);
  if (closest < r || box_closest == 0) return {Rejection::Occluded, out.ambiguous};
  return out;
}

TEST(CampaignCell, RejectionCountsMatchAnIndependentBruteForceCheck) {
  // Tracker behind the robot, a fixture box in front of it on the table; the SMR looks back
  // over the tool (flange (0, 0.6, −0.8)), so the arm often stands in the line of sight.
  const Cell cell = parse_cell(
      "format: robcal-cell\n"
      "robot_base: {position_mm: [0, 0, 0], rotation_xyz_deg: [0, 0, 0]}\n"
      "instrument: {kind: laser-tracker, position_mm: [-1200, 200, 500], range_mm: [0, 1900],\n"
      "             target_axes_flange: {'1': [0, 0.6, -0.8]}}\n"
      "floor_z_mm: 0\n"
      "link_radius_mm: 50\n"
      "keep_out:\n"
      "  - {name: fixture, min_mm: [300, -300, 0], max_mm: [700, 300, 200]}\n",
      "hand.yaml");
  const RobotModel model = load_robot("abb-irb120");
  Tool tool;
  tool.targets = {{"1", Eigen::Vector3d(0, 0, 125), true}};
  std::mt19937_64 rng(5);
  std::vector<Vector6d> configs;
  for (int k = 0; k < 1000; ++k) {
    Vector6d q;
    for (int j = 0; j < kJointCount; ++j)
      q[j] = std::uniform_real_distribution<double>(1.02 * model.limits[j].lower,
                                                    1.02 * model.limits[j].upper)(rng);
    configs.push_back(q);
  }
  const RejectionCounts counts =
      count_rejections(cell, model, tool, configs, std::vector<int>(configs.size(), 0));
  std::array<long, kRejectionCount> brute{};
  int ambiguous = 0;
  for (size_t k = 0; k < configs.size(); ++k) {
    const BruteForce b = brute_force(cell, model, tool, configs[k]);
    const Feasibility f = check_configuration(cell, model, tool, configs[k], 0);
    if (b.ambiguous) {
      ++ambiguous;
      ++brute[static_cast<size_t>(f.reason)];  // too close to call by sampling
      continue;
    }
    ++brute[static_cast<size_t>(b.reason)];
    EXPECT_EQ(f.reason, b.reason) << "configuration " << k << ": " << f.detail;
  }
  std::string line;
  for (int r = 0; r < kRejectionCount; ++r)
    line += fmt::format(" {}={}", rejection_name(static_cast<Rejection>(r)),
                        counts.count[static_cast<size_t>(r)]);
  std::printf("1000 configurations (seed 5):%s; %d too close to call by sampling\n", line.c_str(),
              ambiguous);
  EXPECT_EQ(counts.count, brute);
  EXPECT_LE(ambiguous, 10);
  // The hand-built case, seeded: the counts per reason.
  const std::array<long, kRejectionCount> expected = {53, 113, 102, 44, 4, 665, 0, 19, 0};
  EXPECT_EQ(counts.count, expected);
  // Every reason of a tracker cell occurs in this set (the check is not vacuous).
  for (Rejection r :
       {Rejection::None, Rejection::JointLimits, Rejection::BelowFloor, Rejection::Collision,
        Rejection::OutOfRange, Rejection::NotFacing, Rejection::Occluded})
    EXPECT_GT(counts.of(r), 0) << rejection_name(r);
}

TEST(CampaignCell, BadCellsAreRefusedWithTheirPlace) {
  const std::string base =
      "format: robcal-cell\n"
      "robot_base: {position_mm: [0, 0, 0], rotation_xyz_deg: [0, 0, 0]}\n";
  std::string e =
      error_of(base +
               "instrument: {kind: laser-tracker, position_mm: [1000, 0, 500]}\n"
               "keep_out:\n"
               "  - {name: cabinet, min_mm: [900, -100, 0], max_mm: [1100, 100, 1000]}\n");
  EXPECT_NE(e.find("cell.yaml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("inside keep-out box 'cabinet'"), std::string::npos) << e;
  e = error_of(base + "instrument: {kind: laser-tracker, position_mm: [0, 0, 0], cone_deg: 30}\n");
  EXPECT_NE(e.find("cell.yaml:3:"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key 'cone_deg'"), std::string::npos) << e;
  e = error_of(base + "instrument: {kind: laser-tracker, position_mm: [0, 0]}\n");
  EXPECT_NE(e.find("instrument.position_mm"), std::string::npos) << e;
  e = error_of(base + "instrument: {kind: interferometer, position_mm: [0, 0, 0]}\n");
  EXPECT_NE(e.find("unknown instrument 'interferometer'"), std::string::npos) << e;
  e = error_of(base +
               "instrument: {kind: laser-tracker, position_mm: [0, 0, 0]}\n"
               "keep_out: [{min_mm: [0, 0, 0], max_mm: [1, -1, 1]}]\n");
  EXPECT_NE(e.find("min_mm < max_mm"), std::string::npos) << e;
  e = error_of(base +
               "instrument: {kind: laser-tracker, position_mm: [0, 0, -10]}\nfloor_z_mm: 0\n");
  EXPECT_NE(e.find("below the floor"), std::string::npos) << e;
}

TEST(CampaignCell, InstrumentPlacedFromThreeTableNests) {
  // The tracker at (-900, 1200, 300) turned 30° about z: nests at known world coordinates as
  // the tracker reads them.
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(deg2rad(30), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d at(-900, 1200, 300);
  const std::vector<Eigen::Vector3d> world = {{0, 0, 0}, {500, 0, 0}, {0, 400, 0}};
  std::string measured;
  for (const auto& w : world) {
    const Eigen::Vector3d m = R.transpose() * (w - at);
    measured += fmt::format("{}[{:.17g}, {:.17g}, {:.17g}]", measured.empty() ? "" : ", ", m.x(),
                            m.y(), m.z());
  }
  const Cell cell = parse_cell(
      fmt::format(
          "format: robcal-cell\n"
          "robot_base: {{position_mm: [0, 0, 0], rotation_xyz_deg: [0, 0, 0]}}\n"
          "instrument:\n"
          "  kind: laser-tracker\n"
          "  from_nests: {{measured_mm: [{}], world_mm: [[0, 0, 0], [500, 0, 0], [0, 400, 0]]}}\n"
          "floor_z_mm: -100\n",
          measured),
      "nests.yaml");
  EXPECT_LT((cell.instrument.position_mm - at).norm(), 1e-9);
}

TEST(CampaignCell, OpticalCmmNeedsEnoughTargetsInViewAndFacingIt) {
  // The IRB 120 at home, its flange z along +x; the camera bar 2.5 m in front looking back.
  // Targets 1 and 3 face along the flange z; target 2 is tilted 30° (beyond a 20° limit).
  const RobotModel model = load_robot("abb-irb120");
  Tool tool;
  tool.targets = {{"1", Eigen::Vector3d(40, 0, 100), true},
                  {"2", Eigen::Vector3d(0, 40, 100), true},
                  {"3", Eigen::Vector3d(-40, 0, 100), true}};
  const auto cmm = [](const std::string& view, int min_targets) {
    return parse_cell(
        fmt::format("format: robcal-cell\n"
                    "robot_base: {{position_mm: [0, 0, 0], rotation_xyz_deg: [0, 0, 0]}}\n"
                    "instrument:\n"
                    "  kind: optical-cmm\n"
                    "  position_mm: [2500, 0, 600]\n"
                    "  view_direction: [{}]\n"
                    "  field_of_view_deg: 30\n"
                    "  facing_limit_deg: 20\n"
                    "  min_visible_targets: {}\n"
                    "  target_axes_flange: {{'1': [0, 0, 1], '2': [0, 0.5, 0.8660254037844386], "
                    "'3': [0, 0, 1]}}\n",
                    view, min_targets),
        "cmm.yaml");
  };
  const Vector6d home = Vector6d::Zero();
  Feasibility f = check_configuration(cmm("-1, 0, 0", 2), model, tool, home);
  EXPECT_EQ(f.reason, Rejection::None) << f.detail;
  EXPECT_EQ(f.visible_targets, (std::vector<int>{0, 2}));
  f = check_configuration(cmm("-1, 0, 0", 3), model, tool, home);
  EXPECT_EQ(f.reason, Rejection::TooFewTargets) << f.detail;
  EXPECT_NE(f.detail.find("2 of the tool's targets visible, 3 needed"), std::string::npos)
      << f.detail;
  f = check_configuration(cmm("0, 1, 0", 2), model, tool, home);  // the bar looks aside
  EXPECT_EQ(f.reason, Rejection::OutsideView) << f.detail;
  Vector6d tilted = home;
  tilted[4] = deg2rad(45);  // the flange turns 45° away from the bar: nothing faces it
  f = check_configuration(cmm("-1, 0, 0", 2), model, tool, tilted);
  EXPECT_EQ(f.reason, Rejection::NotFacing) << f.detail;
}

TEST(CampaignCell, FeasibleCandidatesAreMeasurableAndSeenByTheSimulator) {
  const Cell cell = load_cell(test::data_path("../../data/cells/default-tracker.yaml"));
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  CellCandidateOptions options;
  options.box = published_joint_box(model);
  options.count = 200;
  std::mt19937_64 rng(9);
  const CellCandidates set = feasible_candidates(cell, model, tool, options, rng);
  ASSERT_EQ(set.joints.size(), 200u);
  long total = 0;
  for (long c : set.rejected.count) total += c;
  EXPECT_EQ(total, set.draws);
  EXPECT_EQ(set.rejected.of(Rejection::None), 200);
  LaserTracker tracker;
  for (size_t k = 0; k < set.joints.size(); ++k) {
    const Pose<double> flange =
        flange_pose(model, PointMass{}, cell.robot_params(model), set.joints[k]);
    const int t = set.targets[k];
    EXPECT_EQ(check_configuration(cell, model, tool, set.joints[k], t).reason, Rejection::None);
    EXPECT_TRUE(smr_visible(tracker, flange * tool.targets[static_cast<size_t>(t)].position_mm,
                            flange.R * smr_axis_flange(tracker, tool, t)));
  }
  // A tracker whose range cannot reach the robot: refused, with the counts per reason.
  const Cell blind = parse_cell(
      "format: robcal-cell\n"
      "robot_base: {position_mm: [-812.25, 1503.5, -95], rotation_xyz_deg: [0.25, -0.4, -57]}\n"
      "instrument: {kind: laser-tracker, position_mm: [0, 0, 0], range_mm: [0, 100]}\n",
      "blind.yaml");
  options.count = 5;
  options.draws_per_candidate = 20;
  try {
    feasible_candidates(blind, model, tool, options, rng);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("blind.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find("no measurable configuration in 100 random draws"), std::string::npos)
        << what;
    EXPECT_NE(what.find("out of range"), std::string::npos) << what;
  }
}

TEST(CampaignCell, DefaultCellGivesTheSimulatorsInstrumentAndPlacement) {
  const Cell cell = load_cell(test::data_path("../../data/cells/default-tracker.yaml"));
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  const TrueRobot truth = published_irb120_truth(model, tool);
  const VirtualInstrument simulator = standard_instrument(InstrumentKind::LaserTracker, truth);
  const VirtualInstrument from_cell = virtual_instrument(cell, tool);
  EXPECT_EQ(from_cell.tracker.position_mm, simulator.tracker.position_mm);
  EXPECT_EQ(from_cell.tracker.sigma_mm, simulator.tracker.sigma_mm);
  EXPECT_EQ(from_cell.tracker.cone_half_angle_deg, simulator.tracker.cone_half_angle_deg);
  EXPECT_EQ(from_cell.tracker.max_range_mm, simulator.tracker.max_range_mm);
  for (int t = 0; t < 3; ++t)  // the default SMR axes, now listed per target
    EXPECT_LT(
        (smr_axis_flange(from_cell.tracker, tool, t) - smr_axis_flange(simulator.tracker, tool, t))
            .norm(),
        1e-15);
  const auto base = default_base_placement();
  const Eigen::Matrix<double, 6, 1> params = base_parameters(cell);
  for (int i = 0; i < 6; ++i)
    EXPECT_DOUBLE_EQ(params[i],
                     i < 3 ? base[static_cast<size_t>(i)] : deg2rad(base[static_cast<size_t>(i)]));

  CellCandidateOptions options;
  options.box = published_joint_box(model);
  options.count = 50;
  std::mt19937_64 rng(2);
  const CellCandidates found = feasible_candidates(cell, model, tool, options, rng);
  const CandidateSet set = candidate_set(found);
  ASSERT_EQ(set.candidates.size(), 50u);
  EXPECT_EQ(set.draws, set.below_floor + set.not_visible + 50);
  EXPECT_EQ(set.candidates[7].joints, found.joints[7]);
}

}  // namespace
}  // namespace robcal::campaign
