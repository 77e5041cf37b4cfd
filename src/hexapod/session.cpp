#include "robcal/hexapod/session.hpp"

#include "json_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal::hexapod {
namespace {

/// A leg "Bi-Tj" between cups the plan's fixtures have: B1..B`base_cups`, T1..T`tool_cups`.
PhysicalLeg parse_leg(const std::string& text, int base_cups, int tool_cups,
                      const SourceLocation& where) {
  int b = 0, t = 0;
  char extra = 0;
  if (std::sscanf(text.c_str(), "B%d-T%d%c", &b, &t, &extra) != 2 || b < 1 || b > base_cups ||
      t < 1 || t > tool_cups)
    throw InputError(
        where,
        fmt::format("leg '{}': expected Bi-Tj with i in 1..{}, j in 1..{}{}{}", text, base_cups,
                    tool_cups,
                    tool_cups == 3 ? " (T4 only with a fourth tool cup, tool_cup4_mm)" : "",
                    base_cups == 3 ? " (B4 only with a fourth base cup, base_cup4_mm)" : ""));
  return {b - 1, t - 1};
}

double positive(const nlohmann::json& node, const SourceLocation& where) {
  // A ballbar is centimetres to a metre or two: 10 m is a unit slip, not a bar.
  if (!node.is_number() || !(node.get<double>() > 0 && node.get<double>() <= 10000))
    throw InputError(where, "expected a length in (0, 10000] mm");
  return node.get<double>();
}

/// A list of three numbers, else an InputError saying what was `expected`.
std::array<double, 3> three_numbers(const nlohmann::json& node, const SourceLocation& where,
                                    const char* expected) {
  if (!node.is_array() || node.size() != 3 || !node[0].is_number() || !node[1].is_number() ||
      !node[2].is_number())
    throw InputError(where, std::string("expected ") + expected);
  for (int i = 0; i < 3; ++i)
    if (!(std::abs(node[i].get<double>()) <= 20000))
      throw InputError(where, fmt::format("{} is outside the plausible range [-20000, 20000] mm",
                                          node[i].dump()));
  return {node[0].get<double>(), node[1].get<double>(), node[2].get<double>()};
}

Eigen::Vector3d point3(const nlohmann::json& node, const SourceLocation& where) {
  const std::array<double, 3> v = three_numbers(node, where, "three numbers [x, y, z] (mm)");
  return {v[0], v[1], v[2]};
}

TriangleSides sides(const nlohmann::json& node, const SourceLocation& where) {
  const std::array<double, 3> v =
      three_numbers(node, where, "three side lengths [d12, d23, d31] (mm)");
  const TriangleSides s{v[0], v[1], v[2]};
  if (const std::string problem = triangle_problem(s); !problem.empty())
    throw InputError(where, problem);
  return s;
}

/// Three positive distances d14, d24, d34 of a fourth cup, else an InputError at `where`.
std::array<double, 3> fourth_cup_distances(const nlohmann::json& node,
                                           const SourceLocation& where) {
  const std::array<double, 3> d = three_numbers(node, where, "three distances d14, d24, d34");
  for (const double v : d)
    if (!(v > 0)) throw InputError(where, "expected three positive distances (mm)");
  return d;
}

/// Measured fixture distances: three sides, or six with the plan's fourth cup.
FixtureDistances measured_fixture(const nlohmann::json& node, bool fourth_cup,
                                  const SourceLocation& where, const char* fixture) {
  if (fourth_cup && node.is_array() && node.size() == 6)
    return {sides(nlohmann::json{node[0], node[1], node[2]}, where),
            three_numbers(nlohmann::json{node[3], node[4], node[5]}, where,
                          "six distances [d12, d23, d31, d14, d24, d34] (mm)")};
  const TriangleSides s = sides(node, where);
  if (fourth_cup)
    throw InputError(where,
                     fmt::format("expected six distances [d12, d23, d31, d14, d24, d34] (mm): the "
                                 "plan has a fourth {} cup",
                                 fixture));
  return s;
}

/// The optional cell fields of a plan written by `robcal hexapod plan` or `replan`.
template <typename At>
void parse_plan_cell(const nlohmann::json& root, const At& at, SessionPlan& plan) {
  if (root.contains("setting_ball")) {
    const nlohmann::json& list = root["setting_ball"];
    const size_t cups = plan.base_cup4_mm ? 4 : 3;
    if (!list.is_array() || list.size() != cups)
      throw InputError(at("setting_ball"),
                       cups == 4 ? "expected the four setting-ball points B1..B4 (the plan has a "
                                   "fourth base cup)"
                                 : "expected the three setting-ball points B1..B3");
    std::vector<Eigen::Vector3d> points;
    for (size_t i = 0; i < cups; ++i) {
      const std::string key = fmt::format("setting_ball[{}].ball_position_mm", i);
      if (!list[i].is_object() || !list[i].contains("ball_position_mm"))
        throw InputError(at(key), "expected the ball position (robot frame, mm)");
      points.push_back(point3(list[i]["ball_position_mm"], at(key)));
    }
    plan.setting_points = Cups<double>{points[0], points[1], points[2]};
    if (cups == 4) plan.setting_point4 = points[3];
  }
  if (root.contains("tool_mount")) {
    const nlohmann::json& m = root["tool_mount"];
    if (!m.is_object() || !m.contains("position_mm") || !m.contains("quaternion_wxyz") ||
        !m["quaternion_wxyz"].is_array() || m["quaternion_wxyz"].size() != 4)
      throw InputError(at("tool_mount"),
                       "expected {\"position_mm\": [x, y, z], \"quaternion_wxyz\": [w, x, y, z]}");
    std::array<double, 4> q{};
    for (int i = 0; i < 4; ++i) {
      if (!m["quaternion_wxyz"][i].is_number())
        throw InputError(at("tool_mount.quaternion_wxyz"), "expected four numbers");
      q[i] = m["quaternion_wxyz"][i].get<double>();
    }
    const Eigen::Quaterniond quat(q[0], q[1], q[2], q[3]);
    if (std::abs(quat.norm() - 1) > 1e-6)
      throw InputError(at("tool_mount.quaternion_wxyz"), "expected a unit quaternion");
    Pose<double> pose;
    pose.R = quat.normalized().toRotationMatrix();
    pose.p = point3(m["position_mm"], at("tool_mount.position_mm"));
    plan.flange_T_tool = pose;
  }
  if (root.contains("measured_sides")) {
    const nlohmann::json& m = root["measured_sides"];
    if (!m.is_object() || !m.contains("tool_mm") || !m.contains("base_mm"))
      throw InputError(at("measured_sides"), "expected {\"tool_mm\": [...], \"base_mm\": [...]}");
    plan.tool_sides = measured_fixture(m["tool_mm"], plan.tool_cup4_mm.has_value(),
                                       at("measured_sides.tool_mm"), "tool");
    plan.base_sides = measured_fixture(m["base_mm"], plan.base_cup4_mm.has_value(),
                                       at("measured_sides.base_mm"), "base");
  }
}

}  // namespace

SessionPlan parse_session_plan(const nlohmann::json& root, const std::string& file) {
  const auto at = [&](const std::string& key) { return SourceLocation{file, 0, 0, key}; };
  SessionPlan plan;
  if (!root.is_object()) throw InputError(at(""), "expected a JSON object (a hexapod plan)");
  if (root.contains("ballbar")) {
    const nlohmann::json& b = root["ballbar"];
    if (b.contains("tool_mm")) plan.tool_nominal_mm = positive(b["tool_mm"], at("ballbar.tool_mm"));
    if (b.contains("leg_mm")) plan.leg_mm = positive(b["leg_mm"], at("ballbar.leg_mm"));
    if (b.contains("range_mm")) plan.range_mm = positive(b["range_mm"], at("ballbar.range_mm"));
    if (b.contains("recheck_every")) {
      const nlohmann::json& every = b["recheck_every"];
      if (!every.is_number_integer() || every.get<int64_t>() < 0 || every.get<int64_t>() > 100000)
        throw InputError(at("ballbar.recheck_every"), "expected an integer 0..100000");
      plan.recheck_every = every.get<int>();
    }
  }
  if (root.contains("tool_cup4_mm"))
    plan.tool_cup4_mm = fourth_cup_distances(root["tool_cup4_mm"], at("tool_cup4_mm"));
  if (root.contains("base_cup4_mm"))
    plan.base_cup4_mm = fourth_cup_distances(root["base_cup4_mm"], at("base_cup4_mm"));
  const int tool_cups = plan.tool_cup4_mm ? 4 : 3;
  const int base_cups = plan.base_cup4_mm ? 4 : 3;
  if (!root.contains("configurations") || !root["configurations"].is_array())
    throw InputError(at("configurations"), "expected a list of configurations");
  const nlohmann::json& list = root["configurations"];
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string key = fmt::format("configurations[{}]", i);
    const nlohmann::json& c = list[i];
    SessionConfiguration config;
    config.id = static_cast<int>(i) + 1;
    if (!c.is_object() || !c.contains("pose") || !c["pose"].is_string())
      throw InputError(at(key + ".pose"), "expected the pose label (a string)");
    config.pose = c["pose"].get<std::string>();
    if (c.contains("labels") && c["labels"].is_string())
      config.labels = c["labels"].get<std::string>();
    if (c.contains("mode")) {
      if (!c["mode"].is_number_integer() || c["mode"].get<int64_t>() < 1 ||
          c["mode"].get<int64_t>() > 4)
        throw InputError(at(key + ".mode"), "expected the assembly mode, an integer 1..4");
      config.mode = c["mode"].get<int>();
    }
    if (c.contains("joints_deg")) {
      if (!c["joints_deg"].is_array() || c["joints_deg"].size() != 6)
        throw InputError(at(key + ".joints_deg"), "expected six joint values (deg)");
      for (const auto& q : c["joints_deg"]) {
        // Beyond three turns a joint value is a unit slip (radians, or a typo), never a pose.
        if (!q.is_number() || !(std::abs(q.get<double>()) <= 1080))
          throw InputError(at(key + ".joints_deg"), "expected joint values in [-1080, 1080] deg");
        config.joints_deg.push_back(q.get<double>());
      }
    }
    // The six of the design, then at most one leg between each pair of cups not both among
    // B1..B3 and T1..T3.
    const size_t max_legs = kDesignLegs.size() + base_cups * tool_cups - 9;
    const std::string expected = fmt::format(
        "expected six legs like \"B1-T1\"{}{}",
        tool_cups > 3 ? (base_cups > 3 ? " and up to four to T4" : " and up to three to T4") : "",
        base_cups > 3 ? " and up to three from B4 to T1..T3" : "");
    if (!c.contains("legs") || !c["legs"].is_array()) throw InputError(at(key + ".legs"), expected);
    for (const nlohmann::json& leg : c["legs"]) {
      if (!leg.is_string()) throw InputError(at(key + ".legs"), "expected strings");
      config.legs.push_back(
          parse_leg(leg.get<std::string>(), base_cups, tool_cups, at(key + ".legs")));
    }
    if (config.legs.size() < kDesignLegs.size() || config.legs.size() > max_legs)
      throw InputError(at(key + ".legs"), expected);
    plan.configurations.push_back(config);
  }
  parse_plan_cell(root, at, plan);
  return plan;
}

/// Parses JSON text (a plan, or one journal line `line`), refusing with the line and column:
/// a syntax error at the byte the parser stopped on, a number beyond the double range (which
/// the parser reports without a place) at the number.
nlohmann::json parse_json(const std::string& text, const std::string& file, int line,
                          const char* expected) {
  const auto at_offset = [&](size_t offset) {
    offset = std::min(offset, text.size());
    const size_t newlines =
        static_cast<size_t>(std::count(text.begin(), text.begin() + offset, '\n'));
    const size_t line_start = text.rfind('\n', offset == 0 ? 0 : offset - 1);
    const size_t column =
        line_start == std::string::npos || newlines == 0 ? offset + 1 : offset - line_start;
    return SourceLocation{file, line + static_cast<int>(newlines), static_cast<int>(column), ""};
  };
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(at_offset(e.byte == 0 ? 0 : e.byte - 1),
                     fmt::format("{}: not valid JSON ({})", expected, e.what()));
  } catch (const nlohmann::json::exception& e) {
    // "number overflow parsing '1e999'": the quoted text is the number.
    const std::string what = e.what();
    const size_t open = what.find('\''), close = what.rfind('\'');
    const std::string number =
        open != std::string::npos && close > open ? what.substr(open + 1, close - open - 1) : "";
    const size_t offset = number.empty() ? std::string::npos : text.find(number);
    throw InputError(
        offset == std::string::npos ? SourceLocation{file, line, 0, ""} : at_offset(offset),
        number.empty() ? fmt::format("{}: {}", expected, what)
                       : fmt::format("the number {} is outside the range of "
                                     "double-precision numbers",
                                     number));
  }
}

SessionPlan load_session_plan(const std::filesystem::path& path) {
  const std::string text = read_text_file(path);
  return parse_session_plan(parse_json(text, path.string(), 1, "expected a hexapod plan"),
                            path.string());
}

Session::Session(SessionPlan plan) : plan_(std::move(plan)) {
  state_.configurations.resize(plan_.configurations.size());
  for (size_t c = 0; c < plan_.configurations.size(); ++c)
    state_.configurations[c].legs.resize(plan_.configurations[c].legs.size());
  state_.tool_sides.resize(plan_.tool_cup4_mm ? 6 : 3);
  state_.base_sides.resize(plan_.base_cup4_mm ? 6 : 3);
  // Measured earlier: the sides, and a fourth cup's distances when both have it.
  for (const auto& [measured, state] : {std::pair{&plan_.tool_sides, &state_.tool_sides},
                                        std::pair{&plan_.base_sides, &state_.base_sides}})
    if (*measured) {
      const std::vector<double> known = (*measured)->values();
      if (known.size() == state->size()) std::copy(known.begin(), known.end(), state->begin());
    }
}

bool Session::configuration_done(size_t c) const {
  const ConfigurationReadings& r = state_.configurations[c];
  if (r.retry) return true;
  for (const auto& leg : r.legs)
    if (!leg) return false;
  return true;
}

bool Session::recheck_due_after(size_t c) const {
  if (plan_.recheck_every <= 0 || (c + 1) % plan_.recheck_every != 0 ||
      c + 1 >= plan_.configurations.size())
    return false;
  const int id = plan_.configurations[c].id;
  for (const auto& check : state_.calibrator_checks)
    if (check.first == id) return false;
  return true;
}

std::optional<SessionStep> Session::next_step() const {
  for (size_t i = 0; i < state_.tool_sides.size(); ++i)
    if (!state_.tool_sides[i]) {
      // The sides at the tool set-up; each distance to T4 at its own (its design length).
      const double setup = i < 3 ? plan_.tool_nominal_mm : (*plan_.tool_cup4_mm)[i - 3];
      const auto [a, b] = kFixtureDistancePairs[i];
      return SessionStep{
          StepKind::ToolSide,
          fmt::format("tool/T{}-T{}", a + 1, b + 1),
          fmt::format("{}Attach the ballbar between tool cups T{} and T{}, then enter the reading "
                      "(mm)",
                      i == 0 || i >= 3 ? fmt::format("Set the ballbar up at {} mm. ", setup) : "",
                      a + 1, b + 1),
          -1,
          static_cast<int>(i),
          setup};
    }
  for (size_t i = 0; i < state_.base_sides.size(); ++i)
    if (!state_.base_sides[i]) {
      // The sides at the leg set-up; each distance to B4 at its own (its design length).
      const double setup = i < 3 ? plan_.leg_mm : (*plan_.base_cup4_mm)[i - 3];
      const auto [a, b] = kFixtureDistancePairs[i];
      std::string intro;
      if (i == 0)
        intro = fmt::format(
            "The robot has placed and locked the base cups. Set the ballbar up at {} mm. ", setup);
      else if (i >= 3)
        intro = fmt::format("Set the ballbar up at {} mm. ", setup);
      return SessionStep{StepKind::BaseSide,
                         fmt::format("base/B{}-B{}", a + 1, b + 1),
                         fmt::format("{}Attach the ballbar between base cups B{} and B{}, then "
                                     "enter the reading (mm)",
                                     intro, a + 1, b + 1),
                         -1,
                         static_cast<int>(i),
                         setup};
    }
  for (size_t c = 0; c < plan_.configurations.size(); ++c) {
    const SessionConfiguration& config = plan_.configurations[c];
    if (configuration_done(c)) {
      if (recheck_due_after(c))
        return SessionStep{StepKind::CalibratorCheck,
                           fmt::format("check/{}", config.id),
                           fmt::format("Re-check the ballbar on its calibrator (set-up {} mm: "
                                       "magnetic snaps accumulate), then enter its reading (mm)",
                                       plan_.leg_mm),
                           static_cast<int>(c),
                           0,
                           plan_.leg_mm};
      continue;
    }
    const ConfigurationReadings& r = state_.configurations[c];
    int leg = 0;
    while (r.legs[leg]) ++leg;
    SessionStep step{StepKind::Leg,
                     fmt::format("leg/{}/{}", config.id, config.legs[leg].name()),
                     "",
                     static_cast<int>(c),
                     leg,
                     plan_.leg_mm};
    std::string move;
    if (leg == 0) {
      std::string joints;
      if (!config.joints_deg.empty())
        joints = fmt::format("; joints {:.3f}", fmt::join(config.joints_deg, ", "));
      move = fmt::format("Move to configuration {} ({}{}{}). ", config.id, config.pose,
                         config.labels.empty() ? "" : ", " + config.labels, joints);
    }
    step.prompt = fmt::format(
        "{}Attach the ballbar between B{} and T{}, then enter the reading (mm, or 'out' if it does "
        "not fit the ±{} mm range)",
        move, config.legs[leg].base + 1, config.legs[leg].tool + 1, plan_.range_mm);
    return step;
  }
  return std::nullopt;
}

std::string Session::record(const std::optional<double>& reading) {
  const std::optional<SessionStep> step = next_step();
  if (!step) throw InputError("the session is complete: no reading is expected");
  if (reading && !std::isfinite(*reading))
    throw InputError({"", 0, 0, step->key}, "expected a finite reading");
  switch (step->kind) {
    case StepKind::ToolSide:
    case StepKind::BaseSide:
    case StepKind::CalibratorCheck:
      if (!reading || !(*reading > 0))
        throw InputError({"", 0, 0, step->key}, "expected a positive length in mm");
      break;
    case StepKind::Leg:
      break;
  }
  switch (step->kind) {
    case StepKind::ToolSide:
      state_.tool_sides[step->item] = reading;
      return {};
    case StepKind::BaseSide:
      state_.base_sides[step->item] = reading;
      return {};
    case StepKind::CalibratorCheck: {
      const int id = plan_.configurations[step->configuration].id;
      state_.calibrator_checks.emplace_back(id, *reading);
      const double drift_um = (*reading - state_.calibrator_checks.front().second) * 1e3;
      if (std::abs(drift_um) > 2)
        return fmt::format(
            "The ballbar has drifted {:+.1f} µm since the first check: re-seat it "
            "on the calibrator and reset it before going on.",
            drift_um);
      return {};
    }
    case StepKind::Leg:
      break;
  }
  const SessionConfiguration& config = plan_.configurations[step->configuration];
  ConfigurationReadings& r = state_.configurations[step->configuration];
  if (!reading || std::abs(*reading - plan_.leg_mm) > plan_.range_mm) {
    r.retry = true;
    return fmt::format(
        "Leg {} is out of the ballbar's ±{} mm range: configuration {} ({}) is "
        "marked 'retry after preliminary calibration'.",
        config.legs[step->item].name(), plan_.range_mm, config.id, config.pose);
  }
  r.legs[step->item] = reading;
  return {};
}

nlohmann::json Session::result_json() const {
  const auto optional_list = [](const auto& values) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& v : values) out.push_back(v ? nlohmann::json(*v) : nlohmann::json());
    return out;
  };
  nlohmann::json out;
  out["complete"] = !next_step().has_value();
  out["tool_sides_mm"] = optional_list(state_.tool_sides);
  out["base_sides_mm"] = optional_list(state_.base_sides);
  out["configurations"] = nlohmann::json::array();
  int measured = 0, retry = 0;
  for (size_t c = 0; c < plan_.configurations.size(); ++c) {
    const SessionConfiguration& config = plan_.configurations[c];
    const ConfigurationReadings& r = state_.configurations[c];
    const std::string status = r.retry ? "retry" : configuration_done(c) ? "measured" : "pending";
    measured += status == "measured";
    retry += r.retry;
    nlohmann::json legs = nlohmann::json::array();
    for (const auto& leg : config.legs) legs.push_back(leg.name());
    out["configurations"].push_back({{"id", config.id},
                                     {"pose", config.pose},
                                     {"labels", config.labels},
                                     {"joints_deg", config.joints_deg},
                                     {"legs", legs},
                                     {"legs_mm", optional_list(r.legs)},
                                     {"status", status}});
  }
  out["measured"] = measured;
  out["retry_after_preliminary_calibration"] = retry;
  out["calibrator_checks"] = nlohmann::json::array();
  for (const auto& [id, value] : state_.calibrator_checks)
    out["calibrator_checks"].push_back({{"after_configuration", id}, {"reading_mm", value}});
  return out;
}

// ---- journal ---------------------------------------------------------------------------------

SessionJournal SessionJournal::create(const std::filesystem::path& path) {
  return SessionJournal(JournalFile::create(path));
}

SessionJournal SessionJournal::open_for_resume(const std::filesystem::path& path) {
  return SessionJournal(JournalFile::open_for_resume(path));
}

namespace {

/// Applies every complete line of a journal to `session`; returns the entries applied and sets
/// `complete_bytes` to the length of the complete lines (less than the text after a crash).
int replay_text(const std::filesystem::path& path, const std::string& text, Session& session,
                size_t& complete_bytes) {
  size_t start = 0;
  int line = 0, applied = 0;
  while (start < text.size()) {
    const size_t end = text.find('\n', start);
    if (end == std::string::npos) break;
    ++line;
    const std::string entry_text = text.substr(start, end - start);
    start = end + 1;
    if (entry_text.empty()) continue;
    const SourceLocation where{path.string(), line, 0, ""};
    const nlohmann::json entry = parse_json(entry_text, path.string(), line,
                                            "not a journal entry (one JSON object per line)");
    if (!entry.is_object() || !entry.contains("key") || !entry["key"].is_string() ||
        !entry.contains("reading") || !(entry["reading"].is_number() || entry["reading"].is_null()))
      throw InputError(where, "expected {\"key\": …, \"reading\": number or null}");
    const std::optional<SessionStep> step = session.next_step();
    const std::string key = entry["key"].get<std::string>();
    if (!step || step->key != key)
      throw InputError(where, fmt::format("entry '{}' does not match the plan's next step '{}': "
                                          "the journal belongs to another plan",
                                          key, step ? step->key : "(none, complete)"));
    try {
      session.record(entry["reading"].is_null()
                         ? std::nullopt
                         : std::optional<double>(entry["reading"].get<double>()));
    } catch (const InputError& e) {
      throw InputError(where, e.what());  // e names the key
    }
    ++applied;
  }
  complete_bytes = start;
  return applied;
}

}  // namespace

int SessionJournal::replay(Session& session) {
  const std::string text = file_.text();
  size_t complete = 0;
  const int applied = replay_text(file_.path(), text, session, complete);
  if (complete < text.size()) file_.truncate(complete);  // a line cut short by a crash
  return applied;
}

int SessionJournal::replay_read_only(const std::filesystem::path& path, Session& session) {
  if (!std::filesystem::is_regular_file(path))
    throw InputError({path.string(), 0, 0, "journal"}, "no such session journal");
  size_t complete = 0;
  return replay_text(path, read_text_file(path), session, complete);
}

void SessionJournal::append(const std::string& key, const std::optional<double>& reading) {
  const nlohmann::json entry{{"key", key},
                             {"reading", reading ? nlohmann::json(*reading) : nlohmann::json()}};
  file_.append_line(entry.dump() + "\n");
}

}  // namespace robcal::hexapod
