// ISO 9283 pose characteristics: the library's AP, RP, vAP, AD and RD against a separate
// straightforward implementation (scalar loops over the formulas as the standard writes them)
// on a small hand-made data set, to 1e-9; the test cube and its poses; bad input.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/pose_list_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/programs/measurement_program.hpp"
#include "robcal/validate/iso9283.hpp"

namespace robcal {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

/// Hand-made measurements: commanded P1..P5 (tool pointing down), 4 cycles each with small
/// offsets and rotations about the tool axes; P1 also from directions 2 and 3.
struct HandMade {
  std::vector<Pose<double>> commanded;
  std::vector<Iso9283Sample> samples;
  /// The rotation vector (deg, tool axes) applied to each sample: the a, b, c deviations.
  std::vector<Eigen::Vector3d> deviation_deg;
  HandMade() {
    const Eigen::Matrix3d down =
        Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const double c[5][3] = {
        {400, 0, 500}, {320, -80, 420}, {480, -80, 420}, {480, 80, 580}, {320, 80, 580}};
    for (const auto& p : c) commanded.push_back({down, Eigen::Vector3d(p[0], p[1], p[2])});
    const auto add = [&](int pose, int cycle, int direction) {
      const double k = pose * 10 + cycle + 3 * direction;  // distinct, irregular offsets
      const Eigen::Vector3d offset(0.01 * std::sin(k), 0.02 * std::cos(1.3 * k),
                                   0.015 * std::sin(0.7 * k + 1));
      const Eigen::Vector3d deviation(0.002 * std::cos(k), -0.003 * std::sin(2 * k),
                                      0.001 * (cycle - 2));
      Iso9283Sample s;
      s.pose = pose;
      s.cycle = cycle;
      s.direction = direction;
      s.position_mm = commanded[static_cast<size_t>(pose - 1)].p + offset;
      const Eigen::Vector3d rv = deviation / kRadToDeg;
      s.world_R_tcp = commanded[static_cast<size_t>(pose - 1)].R *
                      Eigen::AngleAxisd(rv.norm(), rv.normalized()).toRotationMatrix();
      samples.push_back(s);
      deviation_deg.push_back(deviation);
    };
    for (int cycle = 1; cycle <= 4; ++cycle)
      for (int pose : {1, 5, 4, 3, 2}) add(pose, cycle, 0);
    for (int direction : {2, 3})
      for (int cycle = 1; cycle <= 4; ++cycle) add(1, cycle, direction);
  }
};

/// The standard's formulas, written out with scalar loops.
struct Reference {
  double ap, rp, ap_abc[3], rp_abc[3];
};
Reference reference_pose(const HandMade& d, int pose, int direction) {
  std::vector<size_t> rows;
  for (size_t i = 0; i < d.samples.size(); ++i)
    if (d.samples[i].pose == pose && d.samples[i].direction == direction) rows.push_back(i);
  const double n = static_cast<double>(rows.size());
  double mean[3] = {0, 0, 0}, mean_abc[3] = {0, 0, 0};
  for (size_t i : rows)
    for (int a = 0; a < 3; ++a) {
      mean[a] += d.samples[i].position_mm[a] / n;
      mean_abc[a] += d.deviation_deg[i][a] / n;
    }
  const Eigen::Vector3d& c = d.commanded[static_cast<size_t>(pose - 1)].p;
  Reference r{};
  r.ap = std::sqrt((mean[0] - c.x()) * (mean[0] - c.x()) + (mean[1] - c.y()) * (mean[1] - c.y()) +
                   (mean[2] - c.z()) * (mean[2] - c.z()));
  std::vector<double> l;
  for (size_t i : rows) {
    double sq = 0;
    for (int a = 0; a < 3; ++a)
      sq += (d.samples[i].position_mm[a] - mean[a]) * (d.samples[i].position_mm[a] - mean[a]);
    l.push_back(std::sqrt(sq));
  }
  double l_mean = 0;
  for (double v : l) l_mean += v / n;
  double s = 0;
  for (double v : l) s += (v - l_mean) * (v - l_mean);
  r.rp = l_mean + 3 * std::sqrt(s / (n - 1));
  for (int a = 0; a < 3; ++a) {
    r.ap_abc[a] = mean_abc[a];
    double sa = 0;
    for (size_t i : rows)
      sa += (d.deviation_deg[i][a] - mean_abc[a]) * (d.deviation_deg[i][a] - mean_abc[a]);
    r.rp_abc[a] = 3 * std::sqrt(sa / (n - 1));
  }
  return r;
}

Eigen::Vector3d barycentre(const HandMade& d, int pose, int direction, bool orientation) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (size_t i = 0; i < d.samples.size(); ++i)
    if (d.samples[i].pose == pose && d.samples[i].direction == direction) {
      sum += orientation ? d.deviation_deg[i] : d.samples[i].position_mm;
      ++n;
    }
  return sum / n;
}

TEST(Iso9283Analyse, MatchesTheFormulasWrittenOut) {
  const HandMade d;
  const Iso9283Result result = iso9283_analyse({"hand.csv", d.commanded, d.samples, 4});
  ASSERT_EQ(result.poses.size(), 5u);
  for (const Iso9283PoseFigures& f : result.poses) {
    SCOPED_TRACE(f.pose);
    const Reference r = reference_pose(d, f.pose, 0);
    EXPECT_EQ(f.cycles, 4);
    EXPECT_NEAR(f.ap_mm, r.ap, 1e-9);
    EXPECT_NEAR(f.rp_mm, r.rp, 1e-9);
    ASSERT_TRUE(f.has_orientation);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(f.ap_abc_deg[a], r.ap_abc[a], 1e-9);
      EXPECT_NEAR(f.rp_abc_deg[a], r.rp_abc[a], 1e-9);
    }
    EXPECT_GT(f.rp_mm, 0.005);  // the data do scatter
  }
  // vAP of P1 from directions 2 and 3 alone: the unidirectional cycles (direction 0) never
  // enter vAP.
  const Iso9283PoseFigures& p1 = result.poses[0];
  ASSERT_TRUE(p1.vap_mm.has_value());
  EXPECT_EQ(p1.directions, 2);  // directions 2 and 3; direction 0 is the unidirectional test
  const Eigen::Vector3d b2 = barycentre(d, 1, 2, false), b3 = barycentre(d, 1, 3, false);
  EXPECT_NEAR(
      *p1.vap_mm,
      std::sqrt((b2.x() - b3.x()) * (b2.x() - b3.x()) + (b2.y() - b3.y()) * (b2.y() - b3.y()) +
                (b2.z() - b3.z()) * (b2.z() - b3.z())),
      1e-9);
  const Eigen::Vector3d o2 = barycentre(d, 1, 2, true), o3 = barycentre(d, 1, 3, true);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR((*p1.vap_abc_deg)[a], std::abs(o2[a] - o3[a]), 1e-9);
  EXPECT_FALSE(result.poses[1].vap_mm.has_value());

  // AD, RD between P2 and P4, cycle by cycle.
  ASSERT_TRUE(result.distance.has_value());
  const Iso9283DistanceFigures& ad = *result.distance;
  const double dc = (d.commanded[1].p - d.commanded[3].p).norm();
  std::vector<double> D, Da;
  for (int cycle = 1; cycle <= 4; ++cycle) {
    Eigen::Vector3d p2 = Eigen::Vector3d::Constant(NAN), p4 = p2, a2 = p2, a4 = p2;
    for (size_t i = 0; i < d.samples.size(); ++i) {
      const Iso9283Sample& s = d.samples[i];
      if (s.cycle != cycle || s.direction != 0) continue;
      if (s.pose == 2) p2 = s.position_mm, a2 = d.deviation_deg[i];
      if (s.pose == 4) p4 = s.position_mm, a4 = d.deviation_deg[i];
    }
    D.push_back(std::sqrt((p2 - p4).dot(p2 - p4)));
    Da.push_back(a2.x() - a4.x());
  }
  double mean = 0, mean_a = 0;
  for (int j = 0; j < 4; ++j) mean += D[j] / 4, mean_a += Da[j] / 4;
  double s = 0, sa = 0;
  for (int j = 0; j < 4; ++j)
    s += (D[j] - mean) * (D[j] - mean), sa += (Da[j] - mean_a) * (Da[j] - mean_a);
  EXPECT_EQ(ad.cycles, 4);
  EXPECT_NEAR(ad.commanded_mm, dc, 1e-9);
  EXPECT_NEAR(ad.ad_mm, mean - dc, 1e-9);
  EXPECT_NEAR(ad.rd_mm, 3 * std::sqrt(s / 3), 1e-9);
  EXPECT_NEAR(ad.ad_abc_deg.x(), mean_a, 1e-9);
  EXPECT_NEAR(ad.rd_abc_deg.x(), 3 * std::sqrt(sa / 3), 1e-9);
}

TEST(Iso9283Analyse, TooFewCyclesIsAClearError) {
  const HandMade d;
  try {
    (void)iso9283_analyse({"hand.csv", d.commanded, d.samples});  // the standard's 30 cycles
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("P1 has 4 cycles: at least 30 are needed"),
              std::string::npos)
        << e.what();
  }
  EXPECT_REFUSED((void)iso9283_analyse({"hand.csv", d.commanded, d.samples, 1}), InputError,
                 "--min-cycles: at least 2 cycles are needed for a standard deviation");
  // Each approach direction of vAP needs the cycles too: one reading per direction is refused.
  std::vector<Iso9283Sample> short_direction;
  for (const Iso9283Sample& s : d.samples)
    if (s.direction != 3 || s.cycle <= 2) short_direction.push_back(s);
  EXPECT_REFUSED((void)iso9283_analyse({"hand.csv", d.commanded, short_direction, 3}), InputError,
                 "hand.csv: P1 has 2 cycles from direction 3: at least 3 are needed for vAP");
  EXPECT_NO_THROW((void)iso9283_analyse({"hand.csv", d.commanded, short_direction, 2}));
  std::vector<Iso9283Sample> twice = d.samples;
  twice.push_back(twice.front());
  EXPECT_REFUSED((void)iso9283_analyse({"hand.csv", d.commanded, twice, 4}), InputError,
                 "hand.csv: cycle 1 of P1 (direction 0) is given twice");
}

TEST(Iso9283File, ReadsAndNamesBadCells) {
  const std::vector<Iso9283Sample> s = parse_iso9283_samples(
      "pose,cycle,x,y,z,qw,qx,qy,qz,direction\nP2,3,1,2,3,0,0,1,0,2\n", "m.csv");
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].pose, 2);
  EXPECT_EQ(s[0].cycle, 3);
  EXPECT_EQ(s[0].direction, 2);
  EXPECT_EQ(s[0].position_mm, Eigen::Vector3d(1, 2, 3));
  ASSERT_TRUE(s[0].world_R_tcp.has_value());
  EXPECT_NEAR((*s[0].world_R_tcp)(0, 0), -1.0, 1e-15);
  EXPECT_FALSE(parse_iso9283_samples("pose,cycle,x,y,z\n1,1,0,0,0\n", "m.csv")[0].world_R_tcp);
  try {
    (void)parse_iso9283_samples("pose,cycle,x,y,z\nP7,1,0,0,0\n", "m.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 2);
    EXPECT_EQ(e.where().column, 1);
  }
  try {
    (void)parse_iso9283_samples("pose,cycle,x,y,z\nP1,1,0,zero,0\n", "m.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "y");
    EXPECT_EQ(e.where().column, 8);
  }
  EXPECT_REFUSED((void)parse_iso9283_samples("pose,x,y,z\n", "m.csv"), InputError,
                 "m.csv:1:1: expected the header pose,cycle,x,y,z");
}

/// The nominal IRB 120, a region where a 200 mm cube fits, the tool pointing down.
Iso9283PlanRequest irb120_cube_request() {
  Iso9283PlanRequest request;
  request.robot = CalibratedRobot::nominal(load_robot("abb-irb120"), Tool{});
  request.region_min_mm = Eigen::Vector3d(300, -150, 300);
  request.region_max_mm = Eigen::Vector3d(500, 150, 520);
  request.world_R_tcp = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return request;
}

TEST(Iso9283Plan, CubePosesAndJointTargets) {
  Iso9283PlanRequest request = irb120_cube_request();  // a 200 mm cube fits
  request.cycles = 3;
  const Iso9283Plan plan = iso9283_plan(request);
  EXPECT_DOUBLE_EQ(plan.cube_edge_mm, 200);
  EXPECT_TRUE(plan.cube_centre_mm.isApprox(Eigen::Vector3d(400, 0, 410)));
  ASSERT_EQ(plan.poses.size(), 5u);
  // P2..P5 at 10 % of the plane's diagonal from C1, C2, C7, C8: the diagonal of the plane
  // C1-C2-C7-C8 is √(200² + 2·200²) = 200√3 long, so 20√3 mm from the corner.
  const std::array<int, 4> corner = {0, 1, 6, 7};
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d& c = plan.corners_mm[static_cast<size_t>(corner[static_cast<size_t>(k)])];
    EXPECT_NEAR((plan.poses[static_cast<size_t>(k + 1)].world_T_tcp.p - c).norm(),
                0.1 * 200 * std::sqrt(3.0), 1e-9);
  }
  EXPECT_TRUE(plan.poses[0].world_T_tcp.p.isApprox(plan.cube_centre_mm));
  // Joints reach the poses on the model (nominal FK, base at the origin).
  for (const Iso9283PlannedPose& p : plan.poses) {
    const Pose<double> f = flange_pose(request.robot.model, request.robot.tool.payload,
                                       request.robot.params, p.joints);
    EXPECT_LT((f.p - p.world_T_tcp.p).norm(), 1e-6) << p.name;
    EXPECT_LT((f.R - p.world_T_tcp.R).norm(), 1e-8) << p.name;
  }
  // Cycles: P1 → P5 → P4 → P3 → P2, three times; the pose list reads back.
  ASSERT_EQ(plan.sequence.size(), 15u);
  EXPECT_EQ(plan.sequence[1], std::make_pair(1, 4));
  EXPECT_EQ(plan.sequence[14], std::make_pair(3, 1));
  const std::vector<ListedPose> list =
      parse_pose_list(iso9283_pose_list_csv(plan, request.config), "plan.csv");
  ASSERT_EQ(list.size(), 5u);
  EXPECT_EQ(list[3].name, "P4");
  EXPECT_LT((list[3].world_T_tcp.p - plan.poses[3].world_T_tcp.p).norm(), 1e-6);
  const std::string cycles = iso9283_cycles_csv(plan);
  EXPECT_EQ(std::count(cycles.begin(), cycles.end(), '\n'), 16);

  // Unreachable: a region beyond the arm's reach is named.
  request.region_min_mm = Eigen::Vector3d(2000, 0, 0);
  request.region_max_mm = Eigen::Vector3d(2100, 100, 100);
  try {
    (void)iso9283_plan(request);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("P1 at (2050.000"), std::string::npos) << e.what();
  }
  request.region_max_mm = request.region_min_mm;
  EXPECT_REFUSED((void)iso9283_plan(request), InputError,
                 "--region: the workspace region must be a box min < max on every axis (mm)");
}

/// The multi-directional test as planned: every pose approached along +x, +y, +z from a
/// pre-pose 50 mm back, on a simulated arm that stops 0.05 mm short along the approach (with
/// scatter). vAP against the formula written out; the unidirectional cycles (direction 0) alone
/// give AP and RP although the direction-1 rows are in the same file.
TEST(Iso9283Plan, MultiDirectionalApproachesAndTheirAnalysis) {
  Iso9283PlanRequest request = irb120_cube_request();
  request.cycles = 4;
  request.vap_approach_mm = 50;
  const Iso9283Plan plan = iso9283_plan(request);
  ASSERT_EQ(plan.approaches.size(), 5u);
  for (size_t k = 0; k < 5; ++k)
    for (int h = 0; h < 3; ++h) {
      const Iso9283PlannedPose& from = plan.approaches[k][static_cast<size_t>(h)];
      Eigen::Vector3d back = Eigen::Vector3d::Zero();
      back[h] = -50;
      EXPECT_LT((from.world_T_tcp.p - plan.poses[k].world_T_tcp.p - back).norm(), 1e-12);
      const Pose<double> f = flange_pose(request.robot.model, request.robot.tool.payload,
                                         request.robot.params, from.joints);
      EXPECT_LT((f.p - from.world_T_tcp.p).norm(), 1e-6) << from.name;
      // Same turn of the joints as the pose: a short move, not a flip.
      EXPECT_LT((from.joints - plan.poses[k].joints).cwiseAbs().maxCoeff(), 0.5) << from.name;
    }
  // 3 directions × 4 cycles × 5 poses, each move pair approach → measure.
  ASSERT_EQ(plan.vap_sequence.size(), 120u);
  EXPECT_EQ(plan.vap_sequence[0], (Iso9283Move{1, 0, 1, true}));
  EXPECT_EQ(plan.vap_sequence[1], (Iso9283Move{1, 0, 1, false}));
  EXPECT_EQ(plan.vap_sequence[3], (Iso9283Move{1, 4, 1, false}));
  EXPECT_EQ(plan.vap_sequence.back(), (Iso9283Move{4, 1, 3, false}));
  const std::string csv = iso9283_vap_cycles_csv(plan);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 121);
  EXPECT_EQ(csv.substr(csv.find('\n') + 1, 16), "1,P1,1,approach,");

  // The attained positions of the simulated arm: commanded − 0.05 u_h + scatter.
  std::vector<Iso9283Sample> samples;
  std::vector<Pose<double>> commanded;
  for (const Iso9283PlannedPose& p : plan.poses) commanded.push_back(p.world_T_tcp);
  const auto scatter = [](int k) {
    return Eigen::Vector3d(0.004 * std::sin(1.7 * k), 0.003 * std::cos(2.3 * k),
                           0.005 * std::sin(0.9 * k + 0.4));
  };
  int k = 0;
  for (const auto& [cycle, pose] : plan.sequence)
    samples.push_back({pose + 1, cycle, 0, commanded[static_cast<size_t>(pose)].p + scatter(++k),
                       std::nullopt, 0});
  for (const Iso9283Move& m : plan.vap_sequence) {
    if (m.approach) continue;
    samples.push_back({m.pose + 1, m.cycle, m.direction,
                       commanded[static_cast<size_t>(m.pose)].p -
                           0.05 * Eigen::Vector3d::Unit(m.direction - 1) + scatter(++k),
                       std::nullopt, 0});
  }
  const Iso9283Result result = iso9283_analyse({"vap.csv", commanded, samples, 4});
  ASSERT_EQ(result.poses.size(), 5u);
  for (const Iso9283PoseFigures& f : result.poses) {
    SCOPED_TRACE(f.pose);
    // vAP written out: barycentre of each direction, largest distance between two of them.
    double bary[3][3] = {};
    for (const Iso9283Sample& s : samples)
      if (s.pose == f.pose && s.direction > 0)
        for (int a = 0; a < 3; ++a) bary[s.direction - 1][a] += s.position_mm[a] / 4;
    double vap = 0;
    for (int h = 0; h < 3; ++h)
      for (int g = h + 1; g < 3; ++g) {
        double sq = 0;
        for (int a = 0; a < 3; ++a) sq += (bary[h][a] - bary[g][a]) * (bary[h][a] - bary[g][a]);
        vap = std::max(vap, std::sqrt(sq));
      }
    EXPECT_EQ(f.directions, 3);
    ASSERT_TRUE(f.vap_mm.has_value());
    EXPECT_NEAR(*f.vap_mm, vap, 1e-9);
    EXPECT_NEAR(*f.vap_mm, 0.05 * std::sqrt(2.0), 0.01);  // the stop-short offsets' spread
    // AP from the unidirectional rows only: their mean offset is the scatter's, < 0.005 mm.
    double mean[3] = {};
    for (const Iso9283Sample& s : samples)
      if (s.pose == f.pose && s.direction == 0)
        for (int a = 0; a < 3; ++a)
          mean[a] += (s.position_mm[a] - commanded[static_cast<size_t>(f.pose - 1)].p[a]) / 4;
    EXPECT_NEAR(f.ap_mm, std::sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]),
                1e-9);
    EXPECT_LT(f.ap_mm, 0.01);
    EXPECT_EQ(f.cycles, 4);
  }
}

/// The cycles through the programs layer: one configuration per move, named by cycle and pose,
/// joints read back from the URScript written.
TEST(Iso9283Plan, CyclesWrittenThroughTheProgramsLayer) {
  Iso9283PlanRequest request = irb120_cube_request();
  request.cycles = 2;
  MeasurementProgramRequest base;
  base.language = ProgramLanguage::UrScript;
  base.approach_deg = 0;
  EXPECT_REFUSED(
      (void)iso9283_program_request(iso9283_plan(request), base, true), InputError,
      "--vap-approach: the plan has no multi-directional test: give the approach distance (mm)");
  request.vap_approach_mm = 40;
  const Iso9283Plan plan = iso9283_plan(request);
  for (const bool multidirectional : {false, true}) {
    SCOPED_TRACE(multidirectional);
    const MeasurementProgramRequest r = iso9283_program_request(plan, base, multidirectional);
    ASSERT_EQ(r.names.size(), multidirectional ? 60u : 10u);
    EXPECT_EQ(r.names[1], multidirectional ? "V01-P1-D1" : "C01-P5");
    if (multidirectional) {
      EXPECT_EQ(r.names[2], "V01-P5-D1-from");
    }
    const std::vector<ProgramFile> files = write_measurement_program(r);
    ASSERT_EQ(files.size(), 1u);
    const std::vector<JointMove> moves =
        read_joint_moves(files[0].text, ProgramLanguage::UrScript, files[0].name);
    ASSERT_EQ(moves.size(), r.joints.size());  // no joint approach: the cycle's own moves
    for (size_t i = 0; i < r.joints.size(); ++i)
      EXPECT_LT((moves[i].joints_deg - r.joints[i] * kRadToDeg).norm(), 1e-6) << i;
    // The hook only at the measured poses: 10 cycle poses, or 30 of the 60 vAP moves.
    const std::string& text = files[0].text;
    size_t hooks = 0;
    for (size_t at = text.find("get_standard_digital_in"); at != std::string::npos;
         at = text.find("get_standard_digital_in", at + 1))
      ++hooks;
    EXPECT_EQ(hooks, multidirectional ? 30u : 10u);
    // The unidirectional program visits P1 → P5 → P4 → P3 → P2.
    if (!multidirectional) {
      EXPECT_LT((r.joints[1] - plan.poses[4].joints).norm(), 1e-15);
    }
  }
  request.vap_approach_mm = -1;
  EXPECT_REFUSED((void)iso9283_plan(request), InputError,
                 "--vap-approach: expected 0 (no multi-directional test) to 1000 mm, found -1");
}

}  // namespace
}  // namespace robcal
