#include "robcal/hexapod/plan_file.hpp"

#include "json_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "json_fields.hpp"
#include "robcal/core/rounding.hpp"
#include "robcal/core/units.hpp"
#include "robcal/hexapod/world_frame.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::hexapod {
namespace {

using nlohmann::json;

json joints_json(const Vector6d& q) {
  json out = json::array();
  for (int i = 0; i < kJointCount; ++i) out.push_back(rounded(rad2deg(q[i]), 6));
  return out;
}

json joints_json(const std::vector<double>& deg) {
  json out = json::array();
  for (const double v : deg) out.push_back(rounded(v, 6));
  return out;
}

/// A value of the plan's cell, `node[key]`, named `key` in errors, which say what was expected.
template <typename T>
T cell_value(const json& node, const std::string& key, const std::string& file,
             const std::string& expected) {
  const SourceLocation where{file, 0, 0, key};
  const std::string leaf = key.substr(key.rfind('.') + 1);
  if (!node.is_object() || !node.contains(leaf))
    throw InputError(where, "a plan written by `robcal hexapod plan` has this field: " + expected);
  try {
    return node[leaf].get<T>();
  } catch (const json::exception&) {
    throw InputError(where, "expected " + expected);
  }
}

TriangleSides cell_sides(const json& geometry, const std::string& key, const std::string& file) {
  const auto v = cell_value<std::vector<double>>(geometry, key, file, "three side lengths (mm)");
  if (v.size() != 3) throw InputError({file, 0, 0, key}, "expected three side lengths (mm)");
  return {v[0], v[1], v[2]};
}

/// The member `key` of `node`, null when `node` is no object or lacks it: nlohmann's const
/// operator[] reads freed memory for a missing key (found by the 10-minute fuzz run).
const json& member(const json& node, const std::string& key) {
  static const json kNull;
  if (!node.is_object()) return kNull;
  const auto it = node.find(key);
  return it == node.end() ? kNull : *it;
}

std::vector<double> joint_list(const json& node, const SourceLocation& where) {
  if (!node.is_array() || node.size() != kJointCount)
    throw InputError(where, "expected six joint values (deg)");
  std::vector<double> out;
  for (const json& v : node) {
    if (!v.is_number()) throw InputError(where, "expected six joint values (deg)");
    out.push_back(v.get<double>());
  }
  return out;
}

/// The cell part of a plan written by `robcal hexapod plan`: present when "geometry" is.
HexapodPlanRequest parse_cell(const json& root, const std::string& file) {
  HexapodPlanRequest cell;
  if (root.contains("robot") && root["robot"].is_string()) cell.robot = root["robot"];
  const json& geometry = root["geometry"];
  cell.geometry.base = cell_sides(geometry, "geometry.base_sides_mm", file);
  cell.geometry.tool = cell_sides(geometry, "geometry.tool_sides_mm", file);
  const std::string placement =
      cell_value<std::string>(root, "placement", file, "the placement \"x,y,z,yaw\" (mm, deg)");
  cell.placement = parse_placement(placement, {file, 0, 0, "placement"});
  cell.tool_offset_mm = cell_value<double>(root, "tool_offset_mm", file, "a number (mm)");
  cell.ball_offset_mm = cell_value<double>(root, "ball_offset_mm", file, "a number (mm)");
  if (root.contains("table_z_mm"))
    cell.table_z_mm = cell_value<double>(root, "table_z_mm", file, "a number (mm)");
  if (root.contains("tilt_deg"))
    cell.tilt_deg = cell_value<double>(root, "tilt_deg", file, "a number (deg)");
  if (root.contains("cup_diameter_mm"))
    cell.cups.cup_diameter_mm = cell_value<double>(root, "cup_diameter_mm", file, "a number (mm)");
  if (root.contains("pruning")) {
    cell.angle_deg = cell_value<double>(root["pruning"], "pruning.angle_deg", file, "deg");
    cell.distance_mm = cell_value<double>(root["pruning"], "pruning.distance_mm", file, "mm");
  }
  return cell;
}

PlanOutcome parse_outcome(const json& root, const std::string& file) {
  PlanOutcome o;
  o.poses_enumerated = cell_value<int>(root, "poses_enumerated", file, "a count");
  o.poses_kept = cell_value<int>(root, "poses_kept", file, "a count");
  o.poses_measurable = cell_value<int>(root, "poses_measurable", file, "a count");
  o.configurations_measurable = cell_value<int>(root, "configurations_measurable", file, "a count");
  if (root.contains("poses_refused")) {
    if (!root["poses_refused"].is_array())
      throw InputError({file, 0, 0, "poses_refused"}, "expected a list");
    for (size_t i = 0; i < root["poses_refused"].size(); ++i) {
      const std::string key = fmt::format("poses_refused[{}].", i);
      const json& r = root["poses_refused"][i];
      o.refused.emplace_back(cell_value<std::string>(r, key + "label", file, "a label"),
                             cell_value<std::string>(r, key + "reason", file, "a text"));
    }
  }
  if (!root.contains("poses")) return o;
  if (!root["poses"].is_array()) throw InputError({file, 0, 0, "poses"}, "expected a list");
  for (size_t i = 0; i < root["poses"].size(); ++i) {
    const json& p = root["poses"][i];
    const std::string key = fmt::format("poses[{}].", i);
    o.poses.push_back({cell_value<std::string>(p, key + "label", file, "a label"),
                       cell_value<std::string>(p, key + "description", file, "a text"),
                       cell_value<std::string>(p, key + "ik", file, "an IK status"),
                       cell_value<int>(p, key + "configurations", file, "a count"),
                       cell_value<int>(p, key + "rejected_table", file, "a count"),
                       cell_value<int>(p, key + "rejected_fixture", file, "a count"),
                       p.contains("rejected_workcell")
                           ? cell_value<int>(p, key + "rejected_workcell", file, "a count")
                           : 0});
  }
  return o;
}

/// The reach of the setting-ball points, when the plan lists it.
void parse_setting_configurations(const json& root, const std::string& file, HexapodPlan& plan) {
  if (!plan.session.setting_points) return;
  plan.setting.assign(plan.session.setting_point4 ? 4 : 3, {});
  for (size_t i = 0; i < plan.setting.size(); ++i) {
    plan.setting[i].ball_position_mm =
        i < 3 ? (*plan.session.setting_points)[i] : *plan.session.setting_point4;
    const json& entry = root["setting_ball"][i];  // 3 or 4 objects: parse_session_plan checked
    if (!entry.contains("configurations")) continue;
    const std::string key = fmt::format("setting_ball[{}].configurations", i);
    if (!entry["configurations"].is_array()) throw InputError({file, 0, 0, key}, "expected a list");
    for (const json& c : entry["configurations"]) {
      const auto labels = cell_value<std::string>(c, key + ".labels", file, "an arm config label");
      const std::optional<ArmConfig> config = parse_arm_config(labels);
      if (!config)
        throw InputError({file, 0, 0, key + ".labels"},
                         fmt::format("'{}': expected a label like front/up/no-flip", labels));
      const std::vector<double> deg =
          joint_list(member(c, "joints_deg"), {file, 0, 0, key + ".joints_deg"});
      PoseConfiguration pc;
      pc.config = *config;
      for (int j = 0; j < kJointCount; ++j) pc.joints[j] = deg2rad(deg[j]);
      plan.setting[i].configurations.push_back(pc);
    }
  }
}

Replanned parse_replanned(const json& root, const std::string& file) {
  Replanned r;
  const json& node = root["replanned"];
  if (node.contains("sessions") && node["sessions"].is_string()) r.sessions = node["sessions"];
  if (node.contains("model") && node["model"].is_string()) r.model = node["model"];
  for (size_t i = 0; i < root["configurations"].size(); ++i) {
    const json& c = root["configurations"][i];
    r.planned_joints_deg.push_back(
        c.contains("planned_joints_deg")
            ? joint_list(member(c, "planned_joints_deg"),
                         {file, 0, 0, fmt::format("configurations[{}].planned_joints_deg", i)})
            : std::vector<double>{});
  }
  return r;
}

}  // namespace

std::array<double, 4> parse_placement(const std::string& text, const SourceLocation& where) {
  std::array<double, 4> v{};
  size_t start = 0;
  for (int i = 0; i < 4; ++i) {
    const size_t end = i < 3 ? text.find(',', start) : text.size();
    bool ok = end != std::string::npos && (i < 3 || text.find(',', start) == std::string::npos);
    if (ok) {
      try {
        size_t used = 0;
        const std::string field = text.substr(start, end - start);
        v[i] = std::stod(field, &used);
        ok = field.find_first_not_of(" \t", used) == std::string::npos && std::isfinite(v[i]);
      } catch (const std::exception&) {
        ok = false;
      }
    }
    if (!ok) throw InputError(where, fmt::format("'{}': expected \"x,y,z,yaw\" (mm, deg)", text));
    start = end + 1;
  }
  return v;
}

std::string placement_text(const std::array<double, 4>& placement) {
  return fmt::format("{},{},{},{}", placement[0], placement[1], placement[2], placement[3]);
}

Pose<double> placement_pose(const std::array<double, 4>& placement, double tilt_deg) {
  Pose<double> pose;
  pose.R = Eigen::AngleAxisd(deg2rad(placement[3]), Eigen::Vector3d::UnitZ()).toRotationMatrix() *
           Eigen::AngleAxisd(deg2rad(tilt_deg), Eigen::Vector3d::UnitX()).toRotationMatrix();
  pose.p = Eigen::Vector3d(placement[0], placement[1], placement[2]);
  return pose;
}

std::vector<SettingBallPoint> plan_setting_ball(
    const RobotModel& model, const Pose<double>& placement, double side_mm, double ball_offset_mm,
    const std::optional<std::array<double, 3>>& base_cup4_mm) {
  if (!(side_mm > 0)) throw InputError({"", 0, 0, "--leg-mm"}, "expected a positive length");
  const Cups<double> triangle = setting_ball_points(placement, side_mm);
  std::vector<Eigen::Vector3d> points(triangle.begin(), triangle.end());
  if (base_cup4_mm) points.push_back(fourth_setting_ball_point(triangle, *base_cup4_mm));
  const auto geometry = analyze_ortho_parallel(model);
  std::vector<SettingBallPoint> out(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    // Flange z pointing down, the ball ball_offset_mm below the flange.
    Pose<double> robot_T_flange;
    robot_T_flange.R =
        Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix() * placement.R;
    robot_T_flange.p = points[i] - robot_T_flange.R * Eigen::Vector3d(0, 0, ball_offset_mm);
    out[i].ball_position_mm = points[i];
    if (geometry)
      for (const IkSolution& s : nominal_ik(*geometry, robot_T_flange))
        out[i].configurations.push_back({s.joints, s.config});
  }
  return out;
}

nlohmann::json setting_ball_json(const std::vector<SettingBallPoint>& points) {
  json out = json::array();
  for (size_t i = 0; i < points.size(); ++i) {
    json entry{{"cup", fmt::format("B{}", i + 1)},
               {"ball_position_mm", vec_json(points[i].ball_position_mm)}};
    entry["configurations"] = json::array();
    for (const PoseConfiguration& c : points[i].configurations)
      entry["configurations"].push_back(
          {{"labels", c.config.label()}, {"joints_deg", joints_json(c.joints)}});
    out.push_back(entry);
  }
  return out;
}

nlohmann::json setup_json(const std::string& robot, double side_mm,
                          const std::vector<SettingBallPoint>& points) {
  return {{"robot", robot}, {"side_mm", side_mm}, {"setting_ball", setting_ball_json(points)}};
}

PoseScreening plannable_poses(const HexapodGeometry& g, double gauge_range_mm, double angle_deg,
                              double distance_mm, const CupClearance& cups, int* enumerated) {
  std::vector<HexapodPose> all = enumerate_poses(g);
  if (enumerated != nullptr) *enumerated = static_cast<int>(all.size());
  add_fourth_cup_legs(all, g, kExtraLegRangeFraction * gauge_range_mm);
  PoseScreening screening = screen_poses(all, g, deg2rad(angle_deg), distance_mm, cups);
  const auto refuse_without_leg = [&](bool has_cup, const char* flag, const char* cup,
                                      const char* circle, auto reaches) {
    if (!has_cup) return;
    for (const HexapodPose& p : screening.kept)
      if (std::any_of(p.legs.begin(), p.legs.end(), reaches)) return;
    throw InputError(
        {"", 0, 0, flag},
        fmt::format("no pose that can be set up has a leg to {} within ±{} mm of the "
                    "ballbar's {} mm: put {} on the circumcircle of {} (every pose "
                    "then has one, docs/method/07-hexapod.md §7)",
                    cup, kExtraLegRangeFraction * gauge_range_mm, g.leg_mm, cup, circle));
  };
  refuse_without_leg(g.tool_cup4_mm.has_value(), "--tool-cup4-mm", "T4", "T1..T3",
                     [](const PhysicalLeg& l) { return l.tool == 3; });
  refuse_without_leg(g.base_cup4_mm.has_value(), "--base-cup4-mm", "B4", "B1..B3",
                     [](const PhysicalLeg& l) { return l.base == 3; });
  return screening;
}

HexapodPlan plan_hexapod(const RobotModel& model, const HexapodPlanRequest& request) {
  const HexapodGeometry& g = request.geometry;
  check_geometry(g);
  const Cups<double> base_cups = fixture_cups(g.base, "--base-mm");
  check_gauge(request.gauge, "--gauge-range-mm", "--gauge-sigma-mm");
  check_fixture_range(g, request.gauge);
  int enumerated = 0;
  const PoseScreening screening = plannable_poses(g, request.gauge.range_mm, request.angle_deg,
                                                  request.distance_mm, request.cups, &enumerated);
  const std::vector<HexapodPose>& kept = screening.kept;
  const Pose<double> placement = placement_pose(request.placement, request.tilt_deg);
  // The base fixture frame (B1 origin, B2 on x) for the rough placement of its cup centroid.
  Pose<double> centroid_T_base;
  centroid_T_base.p = -centroid(base_cups);
  CellSetup cell;
  cell.robot_T_base = placement * centroid_T_base;
  cell.flange_T_tool = default_tool_mount(g.tool, request.tool_offset_mm);
  cell.table_z_mm = request.table_z_mm;
  cell.workcell = request.workcell;
  if (request.workcell) {
    const Cups<double> tool = fixture_cups(g.tool, "--tool-mm");
    for (int j = 0; j < 3; ++j) cell.tool_cups_flange[j] = cell.flange_T_tool * tool[j];
    std::vector<Eigen::Vector3d> cups_robot;
    for (const Eigen::Vector3d& cup : base_cup_positions(g))
      cups_robot.push_back(cell.robot_T_base * cup);
    if (const std::string problem = base_fixture_in_workcell(model, *request.workcell, cups_robot);
        !problem.empty())
      throw InputError({request.workcell->file, 0, 0, "--placement"}, problem);
  }
  const std::optional<Eigen::Vector3d> base_cup4 =
      g.base_cup4_mm ? std::optional(base_cup_positions(g)[3]) : std::nullopt;
  const PlanSummary summary = plan_poses(model, cell, base_cups, kept, base_cup4);

  HexapodPlan plan;
  plan.cell = request;
  plan.setting =
      plan_setting_ball(model, placement, g.leg_mm, request.ball_offset_mm, g.base_cup4_mm);
  // The robot places the base cups itself (docs/method/08-world-frame.md §1), flange down: a
  // setting point it cannot reach makes a plan the operator cannot set up.
  for (size_t cup = 0; cup < plan.setting.size(); ++cup)
    if (plan.setting[cup].configurations.empty()) {
      const Eigen::Vector3d& at = plan.setting[cup].ball_position_mm;
      throw InputError(
          {"", 0, 0, cup == 3 ? "--base-cup4-mm" : "--placement"},
          fmt::format("the robot cannot put the setting ball at base cup B{} ({:.1f}, {:.1f}, "
                      "{:.1f} mm, flange down): choose a placement {}within its reach",
                      cup + 1, at.x(), at.y(), at.z(), cup == 3 ? "or a fourth cup " : ""));
    }
  plan.session.tool_nominal_mm = g.tool.d12;
  plan.session.leg_mm = g.leg_mm;
  plan.session.range_mm = request.gauge.range_mm;
  plan.session.tool_cup4_mm = g.tool_cup4_mm;
  plan.session.base_cup4_mm = g.base_cup4_mm;
  plan.session.flange_T_tool = cell.flange_T_tool;
  plan.session.setting_points =
      Cups<double>{plan.setting[0].ball_position_mm, plan.setting[1].ball_position_mm,
                   plan.setting[2].ball_position_mm};
  if (g.base_cup4_mm) plan.session.setting_point4 = plan.setting[3].ball_position_mm;
  PlanOutcome outcome;
  outcome.poses_enumerated = enumerated;
  outcome.poses_kept = static_cast<int>(kept.size());
  outcome.poses_measurable = summary.measurable_poses;
  outcome.configurations_measurable = summary.configurations;
  for (const PoseScreening::Refused& r : screening.refused)
    outcome.refused.emplace_back(r.pose.label, r.reason);
  for (const PosePlan& p : summary.poses) {
    outcome.poses.push_back({p.pose.label, p.pose.description(), to_string(p.ik_status),
                             static_cast<int>(p.configurations.size()), p.rejected_table,
                             p.rejected_fixture, p.rejected_workcell});
    for (const PoseConfiguration& c : p.configurations) {
      SessionConfiguration config;
      config.id = static_cast<int>(plan.session.configurations.size()) + 1;
      config.pose = p.pose.label;
      config.labels = c.config.label();
      config.mode = p.pose.mode;
      for (int j = 0; j < kJointCount; ++j) config.joints_deg.push_back(rad2deg(c.joints[j]));
      config.legs = p.pose.legs;
      plan.session.configurations.push_back(config);
    }
  }
  plan.outcome = outcome;
  return plan;
}

nlohmann::json hexapod_plan_json(const HexapodPlan& plan) {
  const SessionPlan& s = plan.session;
  json out;
  if (plan.cell) out["robot"] = plan.cell->robot;
  out["ballbar"] = {{"tool_mm", s.tool_nominal_mm},
                    {"leg_mm", s.leg_mm},
                    {"range_mm", s.range_mm},
                    {"recheck_every", s.recheck_every}};
  if (s.tool_cup4_mm) out["tool_cup4_mm"] = *s.tool_cup4_mm;
  if (s.base_cup4_mm) out["base_cup4_mm"] = *s.base_cup4_mm;
  if (plan.cell) {
    const HexapodPlanRequest& c = *plan.cell;
    out["geometry"] = {{"base_sides_mm", c.geometry.base.as_array()},
                       {"tool_sides_mm", c.geometry.tool.as_array()}};
    out["placement"] = placement_text(c.placement);
    if (c.tilt_deg != 0) out["tilt_deg"] = c.tilt_deg;
    out["cup_diameter_mm"] = c.cups.cup_diameter_mm;
    if (c.workcell) out["cell_file"] = c.workcell->file;
    out["tool_offset_mm"] = c.tool_offset_mm;
    out["ball_offset_mm"] = c.ball_offset_mm;
    out["table_z_mm"] = c.table_z_mm;
    out["pruning"] = {{"angle_deg", c.angle_deg}, {"distance_mm", c.distance_mm}};
  }
  if (s.flange_T_tool) out["tool_mount"] = pose_json(*s.flange_T_tool);
  if (s.setting_points) {
    std::vector<SettingBallPoint> setting = plan.setting;
    setting.resize(s.setting_point4 ? 4 : 3);
    for (size_t i = 0; i < setting.size(); ++i)
      setting[i].ball_position_mm = i < 3 ? (*s.setting_points)[i] : *s.setting_point4;
    out["setting_ball"] = setting_ball_json(setting);
  }
  if (plan.outcome) {
    const PlanOutcome& o = *plan.outcome;
    out["poses_enumerated"] = o.poses_enumerated;
    out["poses_kept"] = o.poses_kept;
    out["poses_measurable"] = o.poses_measurable;
    out["configurations_measurable"] = o.configurations_measurable;
    out["poses"] = json::array();
    for (const PlannedPose& p : o.poses)
      out["poses"].push_back({{"label", p.label},
                              {"description", p.description},
                              {"ik", p.ik},
                              {"configurations", p.configurations},
                              {"rejected_table", p.rejected_table},
                              {"rejected_fixture", p.rejected_fixture},
                              {"rejected_workcell", p.rejected_workcell}});
    out["poses_refused"] = json::array();
    for (const auto& [label, reason] : o.refused)
      out["poses_refused"].push_back({{"label", label}, {"reason", reason}});
  }
  out["configurations"] = json::array();
  for (size_t i = 0; i < s.configurations.size(); ++i) {
    const SessionConfiguration& c = s.configurations[i];
    json legs = json::array();
    for (const PhysicalLeg& l : c.legs) legs.push_back(l.name());
    json entry{{"pose", c.pose}, {"labels", c.labels}};
    if (c.mode > 0) entry["mode"] = c.mode;
    if (!c.joints_deg.empty()) entry["joints_deg"] = joints_json(c.joints_deg);
    if (plan.replanned && i < plan.replanned->planned_joints_deg.size() &&
        !plan.replanned->planned_joints_deg[i].empty())
      entry["planned_joints_deg"] = joints_json(plan.replanned->planned_joints_deg[i]);
    entry["legs"] = legs;
    out["configurations"].push_back(entry);
  }
  if (s.tool_sides && s.base_sides)
    out["measured_sides"] = {{"tool_mm", s.tool_sides->values()},
                             {"base_mm", s.base_sides->values()}};
  if (plan.replanned)
    out["replanned"] = {{"sessions", plan.replanned->sessions}, {"model", plan.replanned->model}};
  return out;
}

HexapodPlan parse_hexapod_plan(const nlohmann::json& root, const std::string& file) {
  HexapodPlan plan;
  plan.session = parse_session_plan(root, file);
  if (root.contains("geometry")) {
    plan.cell = parse_cell(root, file);
    plan.cell->geometry.leg_mm = plan.session.leg_mm;
    plan.cell->geometry.tool_cup4_mm = plan.session.tool_cup4_mm;
    plan.cell->geometry.base_cup4_mm = plan.session.base_cup4_mm;
    for (const auto& [fixture, what, key] :
         {std::tuple{plan.cell->geometry.tool_fixture(), "tool fixture", "tool_cup4_mm"},
          std::tuple{plan.cell->geometry.base_fixture(), "base fixture", "base_cup4_mm"}})
      if (fixture.fourth)
        if (const std::string problem = fixture_problem(fixture, what); !problem.empty())
          throw InputError({file, 0, 0, key}, problem);
  }
  if (root.contains("poses_enumerated")) plan.outcome = parse_outcome(root, file);
  parse_setting_configurations(root, file, plan);
  if (root.contains("replanned")) plan.replanned = parse_replanned(root, file);
  return plan;
}

HexapodPlan read_hexapod_plan(const std::filesystem::path& path) {
  const json root = parse_json(read_text_file(path), path.string(), 1, "expected a hexapod plan");
  return parse_hexapod_plan(root, path.string());
}

std::string hexapod_plan_text(const HexapodPlan& plan) {
  return hexapod_plan_json(plan).dump(2) + "\n";
}

void write_hexapod_plan(const std::filesystem::path& path, const HexapodPlan& plan) {
  write_file_atomically(path, hexapod_plan_text(plan));
}

}  // namespace robcal::hexapod
