#include "robcal/hexapod/session_data.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/hexapod/cup_collision.hpp"

namespace robcal::hexapod {
namespace {

/// A configuration's label in the files: its pose and arm configuration (unique in a plan: one
/// configuration per arm branch and pose), else its number in the session.
std::string config_label(const SessionConfiguration& c) {
  return c.labels.empty() ? fmt::format("{}-c{}", c.pose, c.id) : c.pose + "-" + c.labels;
}

}  // namespace

SessionData load_session_data(const std::filesystem::path& session,
                              const std::filesystem::path& plan_path) {
  std::filesystem::path journal = session, plan_file = plan_path;
  if (!std::filesystem::exists(session))
    throw InputError({session.string(), 0, 0, "--session"},
                     "no such session directory (plan.json + journal.jsonl) or journal file");
  if (std::filesystem::is_directory(session)) {
    journal = session / "journal.jsonl";
    if (plan_file.empty()) plan_file = session / "plan.json";
  }
  if (plan_file.empty())
    throw InputError({session.string(), 0, 0, "--plan"},
                     "a journal file needs its plan (--plan), or give the session directory "
                     "holding plan.json and journal.jsonl");
  SessionData data;
  data.source = session.string();
  data.plan_file = plan_file;
  data.plan = load_session_plan(plan_file);
  const SessionPlan& plan = data.plan;
  const auto missing = [&](const std::string& key, const std::string& what) {
    return InputError({plan_file.string(), 0, 0, key},
                      what + ": write the plan with `robcal hexapod plan --out`");
  };
  if (!plan.setting_points)
    throw missing("setting_ball", "the plan does not say where the robot put the base cups");
  if (!plan.flange_T_tool)
    throw missing("tool_mount", "the plan does not give the tool fixture's mount on the flange");
  data.setting_points = *plan.setting_points;
  data.flange_T_tool = *plan.flange_T_tool;

  Session replay(plan);
  SessionJournal::replay_read_only(journal, replay);
  const SessionState& state = replay.state();
  const auto all_read = [](const auto& sides) {
    return std::all_of(sides.begin(), sides.end(), [](auto& d) { return d.has_value(); });
  };
  if (!all_read(state.tool_sides) || !all_read(state.base_sides))
    throw InputError({journal.string(), 0, 0, "journal"},
                     "the fixture sides were not all measured: continue the session first");
  const std::vector<std::optional<double>>& tool = state.tool_sides;
  const std::vector<std::optional<double>>& base = state.base_sides;
  data.tool_sides = {*tool[0], *tool[1], *tool[2]};
  data.base_sides = {*base[0], *base[1], *base[2]};
  if (tool.size() == 6) data.tool_cup4_mm = std::array<double, 3>{*tool[3], *tool[4], *tool[5]};
  if (base.size() == 6) data.base_cup4_mm = std::array<double, 3>{*base[3], *base[4], *base[5]};
  if (const std::string problem = fixture_problem(data.tool_fixture(), "tool fixture");
      !problem.empty())
    throw InputError({journal.string(), 0, 0, "tool fixture"}, problem);
  fixture_cups(data.base_sides, journal.string() + ": base fixture sides");
  if (const std::string problem = fixture_problem(data.base_fixture(), "base fixture");
      !problem.empty())
    throw InputError({journal.string(), 0, 0, "base fixture"}, problem);

  for (size_t c = 0; c < plan.configurations.size(); ++c) {
    const SessionConfiguration& config = plan.configurations[c];
    const ConfigurationReadings& r = state.configurations[c];
    const bool complete = std::all_of(r.legs.begin(), r.legs.end(), [](auto& l) { return l; });
    if (!r.retry && !complete) {
      ++data.pending;
      continue;
    }
    const std::string key = fmt::format("configurations[{}]", c);
    if (config.mode == 0) throw missing(key + ".mode", "the configuration has no assembly mode");
    if (config.joints_deg.size() != kJointCount)
      throw missing(key + ".joints_deg", "the configuration has no joint values");
    const std::optional<LegDesign> design = design_of_legs(config.legs);
    if (!design)
      throw InputError({plan_file.string(), 0, 0, key + ".legs"},
                       "the first six legs do not follow design 1^12 2^123 3^1 (B1-T1, B1-T2, "
                       "B2-T1, B2-T2, B2-T3, B3-T1 up to a relabelling of the cups)");
    Vector6d q;
    for (int i = 0; i < kJointCount; ++i) q[i] = deg2rad(config.joints_deg[i]);
    if (r.retry) {
      data.retry.push_back(
          {config_label(config), config.pose, config.labels, config.mode, *design, config.legs, q});
      continue;
    }
    LegReadings readings{config_label(config), q, *design, config.mode, {}, {}};
    for (size_t i = 0; i < config.legs.size(); ++i) {
      if (i < kDesignLegs.size())
        readings.legs[i] = *r.legs[i];
      else
        readings.extra_legs.push_back({config.legs[i].base, config.legs[i].tool, *r.legs[i]});
    }
    data.readings.push_back(std::move(readings));
  }
  return data;
}

namespace {

/// The tool fixture mount of `d` against the one of `first` (one tool fixture throughout).
void check_same_tool_mount(const SessionData& d, const SessionData& first) {
  if ((d.flange_T_tool.p - first.flange_T_tool.p).norm() > 1e-6 ||
      (d.flange_T_tool.R - first.flange_T_tool.R).norm() > 1e-9)
    throw InputError(
        {d.source, 0, 0, "tool_mount"},
        fmt::format("the tool fixture mount differs from the one of {}", first.source));
}

/// Where the robot put the setting ball for each base cup: B1..B3, then B4 if any.
std::vector<Eigen::Vector3d> placement_cups(const SessionData& d) {
  std::vector<Eigen::Vector3d> cups(d.setting_points.begin(), d.setting_points.end());
  if (d.plan.setting_point4) cups.push_back(*d.plan.setting_point4);
  return cups;
}

bool same_placement(const SessionData& a, const SessionData& b) {
  for (int i = 0; i < 3; ++i)
    if ((a.setting_points[i] - b.setting_points[i]).norm() > 1e-6) return false;
  return true;
}

}  // namespace

SessionData merge_sessions(const std::vector<SessionData>& sessions) {
  if (sessions.empty()) throw InputError({"", 0, 0, "--session"}, "expected at least one session");
  SessionData out = sessions.front();
  std::set<std::string> measured;
  for (const LegReadings& r : out.readings) measured.insert(r.config);
  for (size_t s = 1; s < sessions.size(); ++s) {
    const SessionData& d = sessions[s];
    if (!same_placement(d, out))
      throw InputError({d.source, 0, 0, "setting_ball"},
                       fmt::format("the base cups were placed elsewhere than in {}: sessions of "
                                   "different placements are calibrated together by `hexapod "
                                   "calibrate`, not merged",
                                   out.source));
    check_same_tool_mount(d, out);
    out.source += ", " + d.source;
    out.pending += d.pending;
    for (const LegReadings& r : d.readings) {
      if (!measured.insert(r.config).second)
        throw InputError({d.source, 0, 0, r.config},
                         "configuration " + r.config + " is measured in two sessions");
      out.readings.push_back(r);
    }
    out.retry.insert(out.retry.end(), d.retry.begin(), d.retry.end());
  }
  // A configuration out of range in several sessions is one retry; a measured one is none.
  std::set<std::string> seen;
  std::erase_if(out.retry, [&](const RetryConfiguration& r) {
    return measured.count(r.config) > 0 || !seen.insert(r.config).second;
  });
  return out;
}

std::vector<SessionData> group_placements(const std::vector<SessionData>& sessions) {
  if (sessions.empty()) throw InputError({"", 0, 0, "--session"}, "expected at least one session");
  std::vector<std::vector<SessionData>> groups;
  for (const SessionData& s : sessions) {
    check_same_tool_mount(s, sessions.front());
    auto group = std::find_if(groups.begin(), groups.end(),
                              [&](const auto& g) { return same_placement(g.front(), s); });
    if (group != groups.end()) {
      group->push_back(s);
      continue;
    }
    // A new placement: its cups must stand apart from every earlier placement's.
    const double clearance = CupClearance{}.cup_diameter_mm;
    const std::vector<Eigen::Vector3d> mine = placement_cups(s);
    for (size_t g = 0; g < groups.size(); ++g) {
      const std::vector<Eigen::Vector3d> theirs = placement_cups(groups[g].front());
      for (size_t a = 0; a < mine.size(); ++a)
        for (size_t b = 0; b < theirs.size(); ++b) {
          const double gap = (mine[a] - theirs[b]).norm();
          if (gap < clearance)
            throw InputError(
                {s.source, 0, 0, "setting_ball"},
                fmt::format(
                    "placement {} overlaps placement {} ({}): its base cup B{} is {:.1f} mm "
                    "from their B{} (cups stand at least {} mm apart); give each "
                    "placement once, or re-plan this one elsewhere",
                    groups.size() + 1, g + 1, groups[g].front().source, a + 1, gap, b + 1,
                    clearance));
        }
    }
    groups.push_back({s});
  }
  std::vector<SessionData> out;
  out.reserve(groups.size());
  for (const std::vector<SessionData>& g : groups) out.push_back(merge_sessions(g));
  return out;
}

std::vector<SessionData> load_placements(const std::vector<std::string>& sessions,
                                         const std::filesystem::path& plan) {
  if (!plan.empty() && sessions.size() != 1)
    throw InputError({"", 0, 0, "--plan"},
                     "--plan goes with one journal; give several sessions as directories");
  std::vector<SessionData> all;
  all.reserve(sessions.size());
  for (const std::string& s : sessions) all.push_back(load_session_data(s, plan));
  return group_placements(all);
}

WorldFrameFit session_world_frame(const SessionData& data) {
  return fit_world_frame(data.setting_points, data.base_sides);
}

MeasurementSet session_pose_measurements(const SessionData& data) {
  return pose_measurements(data.base_fixture(), data.tool_fixture(), data.readings,
                           session_world_frame(data).robot_T_fixture, data.source);
}

std::string session_legs_csv(const SessionData& data) {
  const auto sides = [](const TriangleSides& s) {
    return fmt::format("{}, {}, {}", s.d12, s.d23, s.d31);
  };
  std::string out = fmt::format(
      "# raw ballbar legs of {}\n# tool sides t12, t23, t31 = {} mm (set-up {} mm)\n{}"
      "# base sides b12, b23, b31 = {} mm (set-up {} mm)\n{}"
      "# leg = design role (rho11 … rho31, extra: beyond the design), base_cup/tool_cup = the "
      "physical cups\n"
      "config,pose,mode,j1,j2,j3,j4,j5,j6,leg,base_cup,tool_cup,length\n",
      data.source, sides(data.tool_sides), data.plan.tool_nominal_mm,
      data.tool_cup4_mm ? fmt::format("# tool cup T4 t14, t24, t34 = {} mm\n",
                                      fmt::join(*data.tool_cup4_mm, ", "))
                        : "",
      sides(data.base_sides), data.plan.leg_mm,
      data.base_cup4_mm ? fmt::format("# base cup B4 b14, b24, b34 = {} mm\n",
                                      fmt::join(*data.base_cup4_mm, ", "))
                        : "");
  static constexpr std::array<const char*, 6> kRoles{"rho11", "rho12", "rho21",
                                                     "rho22", "rho23", "rho31"};
  for (const LegReadings& r : data.readings) {
    const std::string pose = r.config.substr(0, r.config.find('-'));
    std::string joints;
    for (int i = 0; i < kJointCount; ++i) joints += fmt::format(",{}", rad2deg(r.joints[i]));
    for (size_t i = 0; i < kDesignLegs.size(); ++i)
      out += fmt::format("{},{},{}{},{},B{},T{},{}\n", r.config, pose, r.mode, joints, kRoles[i],
                         r.design.base[kDesignLegs[i].base] + 1,
                         r.design.tool[kDesignLegs[i].tool] + 1, r.legs[i]);
    for (const MeasuredLeg& leg : r.extra_legs)
      out += fmt::format("{},{},{}{},extra,B{},T{},{}\n", r.config, pose, r.mode, joints,
                         leg.base + 1, leg.tool + 1, leg.length_mm);
  }
  return out;
}

Pose<double> required_flange_pose(const SessionData& data, const WorldFrameFit& world,
                                  const RetryConfiguration& retry) {
  const std::optional<Cups<double>> cups =
      planned_tool_cups(fixture_cups(data.base_sides, "base fixture sides"),
                        fixture_cups(data.tool_sides, "tool fixture sides"), retry.design,
                        retry.mode, data.plan.leg_mm);
  if (!cups)
    throw InputError({data.source, 0, 0, retry.config},
                     fmt::format("configuration {}: assembly mode {} has no real solution for "
                                 "the measured fixtures",
                                 retry.config, retry.mode));
  return world.robot_T_fixture * frame_from_cups(*cups) * data.flange_T_tool.inverse();
}

SessionData load_sessions(const std::vector<std::string>& sessions,
                          const std::filesystem::path& plan) {
  const std::vector<SessionData> placements = load_placements(sessions, plan);
  if (placements.size() > 1)
    throw InputError({placements[1].source, 0, 0, "setting_ball"},
                     fmt::format("the base cups were placed elsewhere than in {}: give the "
                                 "sessions of one placement",
                                 placements[0].source));
  return placements.front();
}

}  // namespace robcal::hexapod
