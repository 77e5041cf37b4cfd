// From a measurement session on disk (plan + journal) to the calibration's records: every pose
// row must be the true tool fixture pose (noise-free ballbar), whatever the leg design and
// assembly mode — no label or cup-permutation mix-up — and sessions combine as the two-stage
// procedure needs.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/hexapod/session_data.hpp"
#include "robcal/hexapod/simulation.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal::hexapod {
namespace {

TEST(HexapodSessionData, LegDesignFromItsSixLegs) {
  for (const LegDesign& d : all_leg_designs()) {
    std::vector<PhysicalLeg> legs(kDesignLegs.size());
    for (size_t i = 0; i < kDesignLegs.size(); ++i)
      legs[i] = {d.base[kDesignLegs[i].base], d.tool[kDesignLegs[i].tool]};
    const std::optional<LegDesign> back = design_of_legs(legs);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->base, d.base);
    EXPECT_EQ(back->tool, d.tool);
    std::swap(legs[1], legs[3]);  // B1-T2 and B2-T2 exchanged: not design 1^12 2^123 3^1
    EXPECT_FALSE(design_of_legs(legs));
  }
}

struct Cell {
  RobotModel model = load_robot("fanuc-lrmate200ic");
  SimulatedHexapodCell cell;
  std::filesystem::path dir;
};

/// A noise-free simulated cell, its plan written as `robcal hexapod plan` does and a session
/// over it journaled to disk.
Cell write_session(const std::string& name) {
  Cell c;
  auto rng = test::seeded_rng(23);
  HexapodCellOptions o;
  o.placement.p = Eigen::Vector3d(450, 0, 300);
  o.sigma_mm = 0;
  c.cell = set_up_simulated_cell(
      levelled_random_truth(c.model, PointMass{}, ErrorBounds{0.3, 0.1, 0, 1.0, 0.1}, rng), c.model,
      o, rng);
  const PlanSummary summary = plan_poses(c.model, c.cell.cell, fixture_cups(o.design.base, "base"),
                                         enumerate_poses(o.design));
  nlohmann::json plan;
  plan["configurations"] = nlohmann::json::array();
  for (const PosePlan& p : summary.poses)
    for (const PoseConfiguration& pc : p.configurations) {
      nlohmann::json legs = nlohmann::json::array(), joints = nlohmann::json::array();
      for (const PhysicalLeg& l : p.pose.legs)
        legs.push_back("B" + std::to_string(l.base + 1) + "-T" + std::to_string(l.tool + 1));
      for (int i = 0; i < kJointCount; ++i) joints.push_back(rad2deg(pc.joints[i]));
      plan["configurations"].push_back({{"pose", p.pose.label},
                                        {"mode", p.pose.mode},
                                        {"labels", pc.config.label()},
                                        {"joints_deg", joints},
                                        {"legs", legs}});
    }
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d& b = c.cell.setting_points[i];
    plan["setting_ball"].push_back({{"ball_position_mm", {b.x(), b.y(), b.z()}}});
  }
  const Eigen::Quaterniond q(c.cell.cell.flange_T_tool.R);
  const Eigen::Vector3d& t = c.cell.cell.flange_T_tool.p;
  plan["tool_mount"] = {{"position_mm", {t.x(), t.y(), t.z()}},
                        {"quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
  c.dir = std::filesystem::temp_directory_path() / ("robcal_test_" + name);
  std::filesystem::remove_all(c.dir);
  std::filesystem::create_directories(c.dir);
  std::ofstream(c.dir / "plan.json") << plan.dump();
  // The journal's format, written without SessionJournal's per-line fsync (tested elsewhere).
  Session session(load_session_plan(c.dir / "plan.json"));
  std::ofstream journal(c.dir / "journal.jsonl");
  while (const std::optional<SessionStep> step = session.next_step()) {
    const std::optional<double> r = simulate_session_reading(c.cell, session.plan(), *step, rng);
    session.record(r);
    journal << nlohmann::json{{"key", step->key},
                              {"reading", r ? nlohmann::json(*r) : nlohmann::json()}}
                   .dump()
            << "\n";
  }
  return c;
}

TEST(HexapodSessionData, PoseRowsAreTheTrueToolFixturePoses) {
  const Cell c = write_session("session_data");
  const SessionData data = load_session_data(c.dir);
  ASSERT_GT(data.readings.size(), 20u);
  ASSERT_GT(data.retry.size(), 5u);  // the uncalibrated robot puts some legs out of range
  EXPECT_EQ(data.pending, 0);
  const MeasurementSet poses = session_pose_measurements(data);
  ASSERT_EQ(poses.size(), data.readings.size());
  const Pose<double> fixture_T_robot = session_world_frame(data).robot_T_fixture.inverse();
  std::set<int> modes;
  std::set<std::array<int, 3>> base_roles;
  double worst_mm = 0, worst_rad = 0;
  for (size_t k = 0; k < poses.size(); ++k) {
    modes.insert(data.readings[k].mode);
    base_roles.insert(data.readings[k].design.base);
    // The true tool fixture frame in the true base fixture frame.
    const Pose<double> truth = c.cell.world_T_sim *
                               true_flange_pose(c.cell.truth, poses.poses[k].joints) *
                               c.cell.cell.flange_T_tool;
    const Pose<double> measured = fixture_T_robot * poses.poses[k].world_T_tcp;
    worst_mm = std::max(worst_mm, (measured.p - truth.p).norm());
    worst_rad = std::max(worst_rad, Eigen::AngleAxisd(measured.R.transpose() * truth.R).angle());
  }
  EXPECT_GE(modes.size(), 2u);
  EXPECT_GE(base_roles.size(), 4u);
  // Noise-free readings; the true fixture sides differ from the design by up to 0.05 mm, which
  // the DKP uses as measured: the poses are exact up to rounding.
  EXPECT_LT(worst_mm, 1e-8);
  EXPECT_LT(worst_rad, 1e-10);
  // The raw legs file: a header and six rows per measured configuration.
  const std::string csv = session_legs_csv(data);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5 + 6 * static_cast<long>(poses.size()));
  std::printf("%zu poses (%zu modes, %zu base orders) from the session: worst %.1e mm, %.1e rad\n",
              poses.size(), modes.size(), base_roles.size(), worst_mm, worst_rad);

  // A second session measuring one retry: merged, it is no longer a retry; measuring a
  // configuration twice is refused; a journal without its plan is refused.
  SessionData second = data;
  second.source = "second";
  second.readings = {data.readings.front()};
  second.readings.front().config = data.retry.front().config;
  second.retry = {data.retry.back()};  // out of range again: still one retry
  const SessionData merged = merge_sessions({data, second});
  EXPECT_EQ(merged.readings.size(), data.readings.size() + 1);
  EXPECT_EQ(merged.retry.size(), data.retry.size() - 1);
  EXPECT_REFUSED(merge_sessions({data, data}), InputError, "is measured in two sessions");
  SessionData elsewhere = second;
  elsewhere.setting_points[0].x() += 1;
  EXPECT_REFUSED(merge_sessions({data, elsewhere}), InputError,
                 "(setting_ball): the base cups were placed elsewhere than in");
  EXPECT_REFUSED(load_session_data(c.dir / "journal.jsonl"), InputError,
                 "(--plan): a journal file needs its plan (--plan)");
  EXPECT_NO_THROW(load_session_data(c.dir / "journal.jsonl", c.dir / "plan.json"));
  std::filesystem::remove_all(c.dir);
}

TEST(HexapodSessionData, KnownSidesAreNotAskedAgainAndReadOnlyReplayKeepsTheJournal) {
  SessionPlan plan;
  SessionConfiguration config;
  config.id = 1;
  config.pose = "P01";
  for (size_t i = 0; i < kDesignLegs.size(); ++i)
    config.legs.push_back({kDesignLegs[i].base, kDesignLegs[i].tool});
  plan.configurations.push_back(config);
  plan.tool_sides = TriangleSides{150, 150.1, 149.9};
  plan.base_sides = TriangleSides{300, 300.1, 299.9};
  Session s(plan);
  ASSERT_TRUE(s.next_step());
  EXPECT_EQ(s.next_step()->key, "leg/1/B1-T1");
  const auto path = std::filesystem::temp_directory_path() / "robcal_test_readonly.jsonl";
  std::filesystem::remove(path);
  {
    SessionJournal j = SessionJournal::create(path);
    j.append("leg/1/B1-T1", 300.01);
  }
  std::ofstream(path, std::ios::app) << "{\"key\": \"leg/1/B1";  // cut short by a crash
  const auto size = std::filesystem::file_size(path);
  Session replayed(plan);
  EXPECT_EQ(SessionJournal::replay_read_only(path, replayed), 1);
  EXPECT_EQ(std::filesystem::file_size(path), size);
  EXPECT_EQ(replayed.next_step()->key, "leg/1/B1-T2");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace robcal::hexapod
