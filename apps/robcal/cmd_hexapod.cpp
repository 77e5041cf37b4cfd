/// `robcal hexapod …`: the ballbar hexapod of docs/method/07-hexapod.md — direct kinematics, the 72
/// poses, uncertainty, world frame and set-up, planning, the guided session and the simulated run.

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdio>
#include <sstream>

#include <cmath>
#include <iostream>
#include <memory>
#include <random>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/campaign/cell.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/design/task_region.hpp"
#include "robcal/hexapod/device_validation.hpp"
#include "robcal/hexapod/direct_kinematics.hpp"
#include "robcal/hexapod/end_to_end.hpp"
#include "robcal/hexapod/end_to_end_report.hpp"
#include "robcal/hexapod/four_cup_kinematics.hpp"
#include "robcal/hexapod/geometry_reports.hpp"
#include "robcal/hexapod/placement_search.hpp"
#include "robcal/hexapod/plan_file.hpp"
#include "robcal/hexapod/planning.hpp"
#include "robcal/hexapod/poses.hpp"
#include "robcal/hexapod/session_workflow.hpp"
#include "robcal/hexapod/uncertainty.hpp"
#include "robcal/hexapod/world_frame.hpp"
#include "robcal/identify/unknowns.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::cli {
namespace {

using namespace robcal::hexapod;

/// "300" (equilateral) or "300.01,299.98,300.02" (d12, d23, d31).
TriangleSides parse_sides(const std::string& text, const std::string& flag) {
  const std::vector<double> v = parse_numbers(text, -1, flag);
  if (v.size() == 1) return {v[0], v[0], v[0]};
  if (v.size() == 3) return {v[0], v[1], v[2]};
  throw InputError(
      {"", 0, 0, flag},
      fmt::format("expected one side length or three (d12,d23,d31), got {} values", v.size()));
}

/// The fixture options shared by the geometry commands.
struct GeometryOptions {
  std::string base = "300";
  std::string tool = "150";
  double leg_mm = 300;

  void add_to(CLI::App* cmd) {
    cmd->add_option("--base-mm", base,
                    "Base fixture sides b12,b23,b31 in mm (one value: equilateral)")
        ->capture_default_str();
    cmd->add_option("--tool-mm", tool,
                    "Tool fixture sides t12,t23,t31 in mm (one value: equilateral)")
        ->capture_default_str();
    cmd->add_option("--leg-mm", leg_mm, "Ballbar nominal length: every leg of a planned pose, mm")
        ->capture_default_str();
  }
  [[nodiscard]] HexapodGeometry geometry() const {
    HexapodGeometry g{parse_sides(base, "--base-mm"), parse_sides(tool, "--tool-mm"), leg_mm};
    check_geometry(g);
    return g;
  }
};

/// `--tool-cup4-mm` and `--base-cup4-mm`, each d14,d24,d34 (empty: no fourth cup on that
/// fixture); check_geometry refuses a bad one.
struct FourthCupOptions {
  std::string tool, base;
  void add_to(CLI::App* cmd) {
    cmd->add_option("--tool-cup4-mm", tool,
                    "A fourth tool cup T4 by its distances d14,d24,d34 to T1..T3 (mm): its legs "
                    "within half the gauge range of --leg-mm are measured too (on the circumcircle "
                    "of T1..T3: one in every pose)");
    add_base_to(cmd);
  }
  void add_base_to(CLI::App* cmd) {
    cmd->add_option("--base-cup4-mm", base,
                    "A fourth base cup B4 by its distances d14,d24,d34 to B1..B3 (mm), placed by "
                    "the robot like B1..B3: its legs within half the gauge range of --leg-mm are "
                    "measured too (on the circumcircle of B1..B3: one in every pose)");
  }
  /// Parses both flags into `geometry` and checks it.
  void apply(HexapodGeometry& geometry) const {
    const auto parse = [](const std::string& text, const char* flag) {
      if (text.empty()) return std::optional<std::array<double, 3>>{};
      const std::vector<double> d = parse_numbers(text, 3, flag);
      return std::optional(std::array<double, 3>{d[0], d[1], d[2]});
    };
    geometry.tool_cup4_mm = parse(tool, "--tool-cup4-mm");
    geometry.base_cup4_mm = parse(base, "--base-cup4-mm");
    check_geometry(geometry);
  }
};

/// "kinematic" or "kinematic + periodic, backlash": what the predictions are made for.
std::string parameters_text(const std::string& level, const std::vector<std::string>& identify) {
  return identify.empty() ? level : fmt::format("{} + {}", level, fmt::join(identify, ", "));
}

/// `--identify` as `robcal calibrate` takes it: the placement predictions are made for those
/// parameters too.
void add_identify_option(CLI::App* cmd, std::vector<std::string>& patterns) {
  cmd->add_option("--identify", patterns,
                  "Also identify the parameters matching this glob or opt-in group (repeatable), "
                  "as calibrate --identify takes them, e.g. periodic: joint-dependent errors "
                  "need the joint ranges several placements visit");
}

// ---- dkp -------------------------------------------------------------------------------------

/// A fixture's distances: one side, three (d12,d23,d31), or six with a fourth cup
/// (d12,d23,d31,d14,d24,d34).
FixtureDistances parse_fixture(const std::string& text, const std::string& flag) {
  const std::vector<double> v = parse_numbers(text, -1, flag);
  if (v.size() != 6) return {parse_sides(text, flag), std::nullopt};
  return {{v[0], v[1], v[2]}, std::array<double, 3>{v[3], v[4], v[5]}};
}

/// "B1-T1=300.1,B4-T2=299.8,…": legs between physical cups 1..4.
std::vector<MeasuredLeg> parse_measured_legs(const std::string& text) {
  std::vector<MeasuredLeg> legs;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    int b = 0, t = 0, used = 0;
    double length = 0;
    if (std::sscanf(item.c_str(), "B%d-T%d=%lf%n", &b, &t, &length, &used) != 3 ||
        used != static_cast<int>(item.size()) || b < 1 || b > 4 || t < 1 || t > 4 ||
        !std::isfinite(length))
      throw InputError({"", 0, 0, "--legs"},
                       fmt::format("leg '{}': with a fourth cup, expected Bi-Tj=length (mm) with "
                                   "i, j in 1..4",
                                   item));
    legs.push_back({b - 1, t - 1, length});
  }
  return legs;
}

/// The over-determined DKP of fixtures with a fourth cup (four_cup_kinematics.hpp).
void run_four_cup_dkp(const std::string& base, const std::string& tool,
                      const std::string& legs_text, bool json) {
  FourCupDkpRequest request{parse_fixture(base, "--base-mm"), parse_fixture(tool, "--tool-mm"),
                            parse_measured_legs(legs_text)};
  const FourCupDkpResult r = solve_four_cup_dkp(request);
  if (r.status != FourCupDkpStatus::Ok) {
    const char* flag = r.culprit == FourCupInput::BaseFixture   ? "--base-mm"
                       : r.culprit == FourCupInput::ToolFixture ? "--tool-mm"
                                                                : "--legs";
    throw InputError({"", 0, 0, flag}, r.message);
  }
  if (json) {
    print_json(four_cup_dkp_json(r));
    return;
  }
  fmt::print(
      "tool cups in the base fixture frame (b1 origin, b2 on x), mm; least squares over {} "
      "distances\n",
      r.distance_names.size());
  for (const FourCupSolution& s : r.solutions) {
    fmt::print("start mode {}: rms residual {:.3g} mm\n", s.mode, s.rms_residual_mm);
    for (size_t j = 0; j < s.tool_cups.size(); ++j)
      fmt::print("  T{}  {:12.6f} {:12.6f} {:12.6f}   u = {:.2f} σ\n", j + 1, s.tool_cups[j].x(),
                 s.tool_cups[j].y(), s.tool_cups[j].z(), s.uncertainty[j].norm);
  }
}

void run_dkp(const std::string& base, const std::string& tool, const std::string& legs_text,
             bool json) {
  if (parse_fixture(base, "--base-mm").fourth || parse_fixture(tool, "--tool-mm").fourth) {
    run_four_cup_dkp(base, tool, legs_text, json);
    return;
  }
  const TriangleSides bs = parse_sides(base, "--base-mm");
  const TriangleSides ts = parse_sides(tool, "--tool-mm");
  const std::vector<double> v = parse_numbers(legs_text, 6, "--legs");
  const LegLengths<double> legs{v[0], v[1], v[2], v[3], v[4], v[5]};
  const DkpResult dkp = solve_dkp(bs, ts, legs);
  if (dkp.status != DkpStatus::Ok) throw InputError({"", 0, 0, "--legs"}, dkp.message);
  if (json) {
    print_json(dkp_json(dkp));
    return;
  }
  fmt::print("tool cups in the base fixture frame (b1 origin, b2 on x), mm\n");
  for (const AssemblyModeSolution& s : dkp.solutions) {
    fmt::print("mode {} (signs {:+d} {:+d} {:+d})\n", s.mode, s.signs[0], s.signs[1], s.signs[2]);
    for (int j = 0; j < 3; ++j)
      fmt::print("  T{}  {:12.6f} {:12.6f} {:12.6f}\n", j + 1, s.tool[j].x(), s.tool[j].y(),
                 s.tool[j].z());
  }
}

// ---- poses -----------------------------------------------------------------------------------

void run_poses(const GeometryOptions& options, double angle_deg, double distance_mm, bool json) {
  const PoseSelection s = select_poses(options.geometry(), angle_deg, distance_mm);
  if (json) {
    print_json(pose_selection_json(s));
    return;
  }
  fmt::print("{} poses enumerated, {} kept (redundant: within {}° and {} mm of a kept one)\n",
             s.enumerated.size(), s.kept.size(), angle_deg, distance_mm);
  fmt::print(
      "closest two poses in orientation: {:.3f}° apart, tool-fixture centres {:.1f} mm apart\n",
      s.closest_orientation_deg, s.closest_centres_mm);
  for (const HexapodPose& p : s.kept) {
    const Eigen::Vector3d c = centroid(p.tool_cups);
    fmt::print("{}  {:<32} centroid {:8.2f} {:8.2f} {:8.2f} mm\n", p.label, p.description(), c.x(),
               c.y(), c.z());
  }
}

// ---- uncertainty -----------------------------------------------------------------------------

void run_uncertainty(const GeometryOptions& options, double sigma_um, uint64_t seed, int samples,
                     bool json) {
  const UncertaintyStudy study = uncertainty_study(options.geometry(), sigma_um, seed, samples);
  const nlohmann::json out = uncertainty_study_json(study);
  if (json) {
    print_json(out);
    return;
  }
  const nlohmann::json& modes = out["modes"];
  const double worst = study.worst_norm_sigma;
  fmt::print("σ = {} µm per distance; Monte Carlo {} samples, seed {}\n", sigma_um, samples, seed);
  fmt::print("mode cup   σx/σ    σy/σ    σz/σ   |σ|/σ   |σ| µm  (MC |σ|/σ)\n");
  for (const nlohmann::json& m : modes)
    for (const nlohmann::json& c : m["cups"])
      fmt::print("{:>4} {:>3} {:7.3f} {:7.3f} {:7.3f} {:7.3f} {:8.3f}  ({:.3f})\n",
                 m["mode"].get<int>(), c["cup"].get<std::string>(),
                 c["per_axis_sigma"][0].get<double>(), c["per_axis_sigma"][1].get<double>(),
                 c["per_axis_sigma"][2].get<double>(), c["norm_sigma"].get<double>(),
                 c["norm_um"].get<double>(), c["monte_carlo_norm_sigma"].get<double>());
  fmt::print("worst case {:.3f} σ = {:.3f} µm (±{:.2f} µm at 95%); published ≈ 3.2 σ\n", worst,
             worst * sigma_um, 2 * worst * sigma_um);
}

// ---- device validation -----------------------------------------------------------------------

/// The measuring options of `plan`, `place`, `simulate` and `device-validation`: gauge and cup
/// screening.
struct MeasuringOptions {
  LengthGauge gauge;
  CupClearance cups;

  void add_to(CLI::App* cmd, bool with_cups = true) {
    cmd->add_option("--gauge-range-mm", gauge.range_mm,
                    "The gauge reads within ± this of its set-up length (ballbar ±1, a "
                    "long-range gauge e.g. 5)")
        ->capture_default_str();
    cmd->add_option("--gauge-sigma-mm", gauge.sigma_mm, "Standard uncertainty of one reading")
        ->capture_default_str();
    if (!with_cups) return;
    cmd->add_option("--cup-diameter-mm", cups.cup_diameter_mm,
                    "Outer cup diameter: poses with colliding cups or legs are refused")
        ->capture_default_str();
  }
};

void run_device_validation(const GeometryOptions& options, const MeasuringOptions& m,
                           double reference_sigma_mm, int poses, uint64_t seed, bool json) {
  DeviceValidationRequest request;
  request.geometry = options.geometry();
  request.gauge = m.gauge;
  request.reference_sigma_mm = reference_sigma_mm;
  request.poses_per_mode = poses;
  request.seed = seed;
  const DeviceValidation v = validate_device(request);
  if (json) {
    print_json(device_validation_json(v, request));
    return;
  }
  fmt::print(
      "Device vs reference instrument: gauge σ {} mm (±{} mm), reference σ {} mm per axis, {} "
      "poses per mode (legs within ±{:.2f} mm of {} mm), seed {}\n",
      m.gauge.sigma_mm, m.gauge.range_mm, reference_sigma_mm, poses, 0.8 * m.gauge.range_mm,
      request.geometry.leg_mm, seed);
  fmt::print(
      "mode  centroid µm: GUM  vs truth  vs reference (predicted)   orientation °: vs "
      "truth  vs reference   worst cup\n");
  for (const ModeValidation& r : v.modes)
    fmt::print(
        "{:>4}  {:>15.3f} {:>9.3f} {:>13.3f} ({:>9.3f})   {:>20.5f} {:>13.5f}   {:>6.2f} σ\n",
        r.mode, 1e3 * r.centroid_gum_mm, 1e3 * r.centroid_vs_truth_mm,
        1e3 * r.centroid_vs_reference_mm, 1e3 * r.centroid_predicted_mm, r.orientation_vs_truth_deg,
        r.orientation_vs_reference_deg, r.worst_cup_sigma_multiple);
}

// ---- world frame and set-up -------------------------------------------------------------------

Cups<double> parse_points(const std::string& text, const std::string& flag) {
  const std::vector<double> v = parse_numbers(text, 9, flag);
  return {Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d(v[3], v[4], v[5]),
          Eigen::Vector3d(v[6], v[7], v[8])};
}

void run_world_frame(const std::string& points, const std::string& sides, bool json) {
  const WorldFrameFit fit =
      fit_world_frame(parse_points(points, "--points"), parse_sides(sides, "--sides"));
  if (json) {
    print_json(world_frame_json(fit));
    return;
  }
  fmt::print(
      "planar correction x {:.6f} mm, y {:.6f} mm, φ {:.6f}° ({} Gauss-Newton steps), rms {:.6f} "
      "mm\n",
      fit.planar[0], fit.planar[1], rad2deg(fit.planar[2]), fit.iterations, fit.rms_mm);
  for (int i = 0; i < 3; ++i)
    fmt::print("B{} corrected {:12.6f} {:12.6f} {:12.6f} mm (robot frame)\n", i + 1,
               fit.corrected[i].x(), fit.corrected[i].y(), fit.corrected[i].z());
  const Pose<double>& w = fit.robot_T_fixture;
  fmt::print("world frame: origin {:.6f} {:.6f} {:.6f} mm, z axis {:.9f} {:.9f} {:.9f}\n", w.p.x(),
             w.p.y(), w.p.z(), w.R(0, 2), w.R(1, 2), w.R(2, 2));
}

// ---- set-up and planning ---------------------------------------------------------------------

/// The cell options shared by `setup`, `plan`, `place` and `simulate`: the flags set the plan
/// request's fields; the fixtures and the placement text are parsed by request().
struct CellOptions {
  HexapodPlanRequest plan;
  std::string placement = "450,0,300,0";

  /// `with_placement` false: the command searches placements itself (`place`).
  void add_to(CLI::App* cmd, bool with_placement = true) {
    cmd->add_option("--robot", plan.robot, "Built-in robot name or robot file")
        ->capture_default_str();
    if (with_placement) {
      cmd->add_option("--tilt-deg", plan.tilt_deg,
                      "Tilt of the base fixture's pivoting platform about the placement's x axis")
          ->capture_default_str();
      cmd->add_option("--placement", placement,
                      "Rough base-fixture placement in the robot frame: centroid x,y,z of the "
                      "cups (mm) and yaw about z (deg)")
          ->capture_default_str();
    }
    cmd->add_option("--tool-offset-mm", plan.tool_offset_mm,
                    "Tool fixture centroid along the flange z axis (fixture plane ⟂ flange axis)")
        ->capture_default_str();
    cmd->add_option("--ball-offset-mm", plan.ball_offset_mm,
                    "Setting ball (TCP used to place the base cups) along the flange z axis")
        ->capture_default_str();
    cmd->add_option("--table-z-mm", plan.table_z_mm, "Table plane height in the robot frame")
        ->capture_default_str();
    cmd->add_option("--angle-deg", plan.angle_deg, "Pruning: redundant when closer in orientation…")
        ->capture_default_str();
    cmd->add_option("--distance-mm", plan.distance_mm,
                    "… and closer in position (tool-fixture centroid)")
        ->capture_default_str();
  }
  [[nodiscard]] HexapodPlanRequest request(const HexapodGeometry& geometry) const {
    HexapodPlanRequest r = plan;
    r.geometry = geometry;
    r.placement = parse_placement(placement, {"", 0, 0, "--placement"});
    return r;
  }
  [[nodiscard]] Pose<double> rough_placement() const {
    return placement_pose(parse_placement(placement, {"", 0, 0, "--placement"}), plan.tilt_deg);
  }
};

void run_setup(const CellOptions& o, double side_mm, const FourthCupOptions& fourth, bool json) {
  // The base triangle the setting points make, with B4 by its distances to it.
  HexapodGeometry base;
  base.base = {side_mm, side_mm, side_mm};
  base.leg_mm = side_mm;
  fourth.apply(base);
  const nlohmann::json out =
      setup_json(o.plan.robot, side_mm,
                 plan_setting_ball(load_robot(o.plan.robot), o.rough_placement(), side_mm,
                                   o.plan.ball_offset_mm, base.base_cup4_mm));
  if (json) {
    print_json(out);
    return;
  }
  fmt::print(
      "Put the setting ball (TCP {} mm along the flange z, pointing down) at these points, "
      "{} mm apart by the robot's own model; snap and lock each base cup there:\n",
      o.plan.ball_offset_mm, side_mm);
  for (const nlohmann::json& p : out["setting_ball"]) {
    fmt::print("{}  x {:.3f}  y {:.3f}  z {:.3f} mm\n", p["cup"].get<std::string>(),
               p["ball_position_mm"][0].get<double>(), p["ball_position_mm"][1].get<double>(),
               p["ball_position_mm"][2].get<double>());
    for (const nlohmann::json& c : p["configurations"])
      fmt::print("    {:<18} joints {}\n", c["labels"].get<std::string>(), c["joints_deg"].dump());
  }
}

void run_plan(const GeometryOptions& geometry_options, const CellOptions& o,
              const MeasuringOptions& m, const FourthCupOptions& fourth,
              const std::string& cell_path, const std::string& out_path, bool json) {
  HexapodPlanRequest request = o.request(geometry_options.geometry());
  fourth.apply(request.geometry);
  request.gauge = m.gauge;
  request.cups = m.cups;
  if (!cell_path.empty()) request.workcell = campaign::load_cell(cell_path);
  const RobotModel model = load_robot(o.plan.robot);
  const HexapodPlan plan = plan_hexapod(model, request);
  if (!out_path.empty()) write_hexapod_plan(out_path, plan);
  if (json) {
    print_json(hexapod_plan_json(plan));
    return;
  }
  const PlanOutcome& outcome = *plan.outcome;
  fmt::print(
      "{}: {} poses enumerated, {} refused (cups or legs collide), {} kept after pruning, {} "
      "measurable with {} configurations\n",
      model.name, outcome.poses_enumerated, outcome.refused.size(), outcome.poses_kept,
      outcome.poses_measurable, outcome.configurations_measurable);
  for (const auto& [label, reason] : outcome.refused) fmt::print("{} refused: {}\n", label, reason);
  const auto report_fourth_cup = [&](const char* name, auto reaches) {
    size_t legs = 0, reaching = 0;
    for (const SessionConfiguration& c : plan.session.configurations) {
      const auto n = std::count_if(c.legs.begin(), c.legs.end(), reaches);
      legs += static_cast<size_t>(n);
      reaching += n > 0 ? 1 : 0;
    }
    fmt::print("{}: {} legs to it in {} of {} configurations (within ±{} mm of {} mm)\n", name,
               legs, reaching, plan.session.configurations.size(),
               kExtraLegRangeFraction * request.gauge.range_mm, request.geometry.leg_mm);
  };
  if (request.geometry.tool_cup4_mm)
    report_fourth_cup("tool cup T4", [](const PhysicalLeg& l) { return l.tool == 3; });
  if (request.geometry.base_cup4_mm)
    report_fourth_cup("base cup B4", [](const PhysicalLeg& l) { return l.base == 3; });
  for (const PlannedPose& p : outcome.poses) {
    std::vector<std::string> labels;
    for (const SessionConfiguration& c : plan.session.configurations)
      if (c.pose == p.label) labels.push_back(c.labels);
    fmt::print("{}  {:<30} {:<14} {} config(s) {}  (rejected: table {}, fixture {}{})\n", p.label,
               p.description, p.ik, p.configurations, fmt::join(labels, " "), p.rejected_table,
               p.rejected_fixture,
               request.workcell ? fmt::format(", cell {}", p.rejected_workcell) : "");
  }
  if (!out_path.empty()) fmt::print("plan written to {}\n", out_path);
}

// ---- placement search ------------------------------------------------------------------------

void run_place(const GeometryOptions& geometry_options, const CellOptions& o,
               const MeasuringOptions& m, const FourthCupOptions& fourth,
               const std::string& cell_path, const std::array<std::string, 5>& grid,
               const std::string& level, const std::vector<std::string>& identify, int validation,
               const std::string& task_box, uint64_t seed, int best,
               const std::vector<std::string>& measured, bool json) {
  PlacementSearchRequest request;
  request.plan = o.request(geometry_options.geometry());
  fourth.apply(request.plan.geometry);  // flags before files
  if (!task_box.empty()) request.task_box = parse_task_box(task_box, "--task-box");
  for (const std::string& plan : measured)
    request.measured.push_back(measured_placement(read_hexapod_plan(plan), plan));
  request.plan.gauge = m.gauge;
  request.plan.cups = m.cups;
  if (!cell_path.empty()) request.plan.workcell = campaign::load_cell(cell_path);
  static constexpr std::array<const char*, 5> kFlags{"--x-mm", "--y-mm", "--z-mm", "--yaw-deg",
                                                     "--tilt-deg"};
  std::array<std::vector<double>*, 5> axes{&request.x_mm, &request.y_mm, &request.z_mm,
                                           &request.yaw_deg, &request.tilt_deg};
  for (int i = 0; i < 5; ++i) *axes[i] = parse_numbers(grid[i], -1, kFlags[i]);
  request.level = parse_calibration_level(level);
  request.identify = identify;
  request.validation_configurations = validation;
  request.seed = seed;
  request.best = best;
  const RobotModel model = load_robot(o.plan.robot);
  const PlacementSearchResult r = search_placements(model, request);
  if (json) {
    print_json(placement_search_json(r));
    return;
  }
  fmt::print(
      "{}: {} placements searched; {} of {} {} parameters identifiable from hexapod poses; pose "
      "σ {:.5f} mm; predicted errors over {} {} (seed {})\n",
      model.name, r.ranked.size(), r.identified_parameters.size(), r.parameters,
      parameters_text(level, identify), r.pose_sigma_mm, validation,
      task_region_text(request.task_box), seed);
  fmt::print("{:>4}  {:<22} {:>6}  {:>5} {:>7} {:>6} {:>8} {:>11} {:>10}\n", "rank", "x,y,z,yaw",
             "tilt", "poses", "configs", "undet", "O1", "pred. mean", "pred. max");
  for (int i = 0; i < best && i < static_cast<int>(r.ranked.size()); ++i) {
    const PlacementScore& s = r.ranked[i];
    fmt::print("{:>4}  {:<22} {:>6g}  {:>5} {:>7} {:>6} {:>8.4f} {:>11.6f} {:>10.6f}{}\n", i + 1,
               placement_text(s.placement), s.tilt_deg, s.poses_measurable, s.configurations,
               s.undetermined, s.observability_o1, s.predicted_mean_mm, s.predicted_max_mm,
               s.refused.empty() ? "" : "  refused: " + s.refused);
  }
  if (!request.measured.empty()) {
    fmt::print(
        "measured: {} placement(s), {} configurations, predicted mean {:.6f} mm, max {:.6f} "
        "mm{}\n",
        request.measured.size(), r.measured_configurations, r.measured_mean_mm, r.measured_max_mm,
        r.measured_undetermined > 0
            ? fmt::format(" ({} unknowns undetermined)", r.measured_undetermined)
            : "");
    for (int i = 0; i < best && i < static_cast<int>(r.next.size()); ++i) {
      const NextPlacement& n = r.next[i];
      const PlacementScore& s = r.ranked[n.rank];
      fmt::print(
          "next #{}: placement {} tilt {:g} (rank {}): {} configurations in all, predicted "
          "mean {:.6f} mm, max {:.6f} mm{}\n",
          i + 1, placement_text(s.placement), s.tilt_deg, n.rank + 1, n.configurations,
          n.predicted_mean_mm, n.predicted_max_mm,
          n.undetermined > 0 ? fmt::format(" ({} undetermined)", n.undetermined) : "");
    }
  }
  for (int i = 0; i < best && i < static_cast<int>(r.pairs.size()); ++i) {
    const PlacementPair& p = r.pairs[i];
    fmt::print(
        "pair #{} + #{}: {} configurations, predicted mean {:.6f} mm, max {:.6f} mm; half of "
        "each ({} configurations) {:.6f} mm\n",
        p.first + 1, p.second + 1, p.configurations, p.predicted_mean_mm, p.predicted_max_mm,
        p.equal_count_configurations, p.equal_count_mean_mm);
  }
  fmt::print(
      "Predictions assume gauge noise only (no unmodelled errors); every placement after the "
      "first has its own world frame (six unknowns).\n");
}

void run_design(const PlacementsDesignRequest& request, bool json) {
  const PlacementsDesignResult r = design_placements(request);
  if (json) {
    print_json(placements_design_json(request, r));
    return;
  }
  fmt::print(
      "{}: {} configurations chosen among {} placements ({} level; predicted errors over {} "
      "{}, seed {})\n",
      r.robot, r.count, r.plans.size(),
      parameters_text(level_name(request.level), request.identify),
      request.validation_configurations, task_region_text(request.task_box), request.seed);
  for (size_t p = 0; p < r.plans.size(); ++p)
    fmt::print("  {:<32} placement {} tilt {:g}: {} of {} configurations{}\n",
               request.plan_files[p], placement_text(r.plans[p].cell->placement),
               r.plans[p].cell->tilt_deg, r.design.chosen[p].size(), r.offered[p],
               p >= r.written.size() ? ""
               : r.written[p]        ? " → " + request.out_files[p]
                                     : " (nothing to measure there: no plan written)");
  const auto line = [](const char* what, const PlacementsDesign& d, size_t n) {
    fmt::print(
        "{}: {} configurations, {} of the {} parameters identifiable{}, predicted mean "
        "{:.6f} mm, max {:.6f} mm (of those parameters only)\n",
        what, n, d.identifiable, d.parameters,
        d.undetermined > 0 ? fmt::format(" ({} unknowns undetermined)", d.undetermined) : "",
        d.predicted_mean_mm, d.predicted_max_mm);
  };
  line("design", r.design, static_cast<size_t>(r.count));
  line("first placement alone", r.first_alone, r.first_alone.chosen.front().size());
  fmt::print(
      "Predictions assume gauge noise only (no unmodelled errors); every placement after the "
      "first has its own world frame (six unknowns).\n");
}

// ---- session ---------------------------------------------------------------------------------

void run_session(const HexapodSessionRequest& request, bool json) {
  std::FILE* talk = json ? stderr : stdout;  // prompts never mix with the JSON result
  const campaign::SessionIo io{
      [talk](const std::string& text) {
        fmt::print(talk, "{}", text);
        std::fflush(talk);
      },
      [talk](const std::string& why) { fmt::print(talk, "{}\n", why); },
      [](std::string& line) { return static_cast<bool>(std::getline(std::cin, line)); },
      {}};
  const HexapodSessionRun run = run_hexapod_session(request, io);
  if (json) {
    print_json(hexapod_session_json(run));
    return;
  }
  if (run.stop != HexapodSessionStop::Complete) return;
  const nlohmann::json result = run.session.result_json();
  fmt::print(
      "Session complete: {} configurations measured, {} to retry after the preliminary "
      "calibration.{}\n",
      result["measured"].get<int>(), result["retry_after_preliminary_calibration"].get<int>(),
      request.out.empty() ? "" : " Result: " + request.out);
}

// ---- simulate ------------------------------------------------------------------------------

void run_simulate(const CellOptions& cell_options, const MeasuringOptions& m,
                  const FourthCupOptions& fourth, const EndToEndOptions& settings, uint64_t seed,
                  bool json) {
  HexapodGeometry geometry;
  fourth.apply(geometry);
  HexapodPlanRequest cell = cell_options.request(geometry);
  cell.gauge = m.gauge;
  cell.cups = m.cups;
  const EndToEndOptions o = end_to_end_options(cell, settings);
  std::mt19937_64 rng(seed);
  const EndToEndReport r = run_end_to_end(load_robot(cell.robot), o, rng);
  const nlohmann::json out = end_to_end_json(r, o, seed);
  if (json) {
    print_json(out);
    return;
  }
  fmt::print("Simulated hexapod calibration of a {} (seed {})\n", r.robot, seed);
  fmt::print(
      "poses: {} enumerated, {} refused (cups or legs collide), {} kept, {} measurable; {} "
      "configurations planned\n",
      r.poses_enumerated, r.poses_refused, r.poses_kept, r.poses_measurable,
      r.configurations_planned);
  fmt::print(
      "first pass: {} measured, {} out of the gauge's range (±{} mm); after the preliminary "
      "calibration {} of those measured; {} legs read{}\n",
      r.measured_first, r.retried, m.gauge.range_mm, r.measured_after_replan, r.legs_read,
      fmt::format(
          "{}{}",
          o.cell.design.tool_cup4_mm ? fmt::format(" ({} to T4)", r.legs_read_fourth_cup) : "",
          o.cell.design.base_cup4_mm ? fmt::format(" ({} from B4)", r.legs_read_base_cup4) : ""));
  fmt::print(
      "world frame from the base cups: rms {:.4f} mm; off the true base fixture frame by {:.3f} "
      "mm, "
      "{:.4f}° (the uncalibrated robot placed the cups){}\n",
      r.world_frame_rms_mm, r.world_frame_error_mm, r.world_frame_error_deg,
      o.relative_pose_fit ? "; pose fits hold the base (relative model)"
                          : "; pose fits identify the base");
  fmt::print("validation on {} random configurations (laser tracker), mm:\n",
             r.validation_configurations);
  fmt::print("{:<26} {:>8} {:>8} {:>8}   {:>10} {:>10}\n", "model", "mean", "std", "max",
             "pairs mean", "pairs max");
  const auto row = [](const char* name, const ValidationFigures& f) {
    fmt::print("{:<26} {:8.4f} {:8.4f} {:8.4f}   {:10.4f} {:10.4f}\n", name, f.absolute.mean,
               f.absolute.std, f.absolute.max, f.pairs.mean, f.pairs.max);
  };
  row("nominal", r.nominal);
  row("preliminary (poses)", r.preliminary.validation);
  row("final (poses)", r.final_pose_fit.validation);
  if (o.leg_fit) row("final (raw legs)", r.leg_fit.validation);
  if (r.leg_fit_base_cup4_error_mm && r.leg_fit_base_cup4_distance_error_mm)
    fmt::print(
        "base cup B4 fitted from the raw legs: {:.4f} mm from the true one (B1..B3 frame), its "
        "distances to B1..B3 within {:.4f} mm\n",
        *r.leg_fit_base_cup4_error_mm, *r.leg_fit_base_cup4_distance_error_mm);
  fmt::print(
      "published (LR Mate 200iC, real robot): nominal 1.355 mean; 46 configs 0.517 / 1.223; "
      "61 configs 0.796 / 1.630; pairs 1.062 → 0.400 / 1.666\n");
}

const bool hexapod_registered = register_command(60, [](CLI::App& app) {
  auto* hex = app.add_subcommand(
      "hexapod", "The ballbar hexapod: 6D poses from one ballbar (docs/method/07-hexapod.md)");
  hex->require_subcommand(1);

  {
    auto* cmd = hex->add_subcommand("dkp", "Direct kinematics: tool cups from the 12 distances");
    auto base = std::make_shared<std::string>("300");
    auto tool = std::make_shared<std::string>("150");
    auto legs = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    cmd->add_option("--base-mm", *base,
                    "Measured base sides b12,b23,b31 (mm); with a fourth cup also b14,b24,b34")
        ->capture_default_str();
    cmd->add_option("--tool-mm", *tool,
                    "Measured tool sides t12,t23,t31 (mm); with a fourth cup also t14,t24,t34")
        ->capture_default_str();
    cmd->add_option("--legs", *legs,
                    "Legs ρ11,ρ12,ρ21,ρ22,ρ23,ρ31 (mm); with a fourth cup every leg as "
                    "Bi-Tj=length")
        ->required();
    cmd->add_flag("--json", *json, "Machine-readable output");
    cmd->callback([=] { run_dkp(*base, *tool, *legs, *json); });
  }
  {
    auto* cmd = hex->add_subcommand("poses", "The 72 poses and the ones left after pruning");
    auto geometry = std::make_shared<GeometryOptions>();
    auto angle = std::make_shared<double>(30.0);
    auto distance = std::make_shared<double>(50.0);
    auto json = std::make_shared<bool>(false);
    geometry->add_to(cmd);
    cmd->add_option("--angle-deg", *angle, "Redundant when closer than this in orientation")
        ->capture_default_str();
    cmd->add_option("--distance-mm", *distance,
                    "… and closer than this in position (tool-fixture centroid)")
        ->capture_default_str();
    cmd->add_flag("--json", *json, "Machine-readable output");
    cmd->callback([=] { run_poses(*geometry, *angle, *distance, *json); });
  }
  {
    auto* cmd = hex->add_subcommand(
        "uncertainty", "Tool-cup uncertainty per assembly mode (Guide 98-3, with Monte Carlo)");
    auto geometry = std::make_shared<GeometryOptions>();
    auto sigma = std::make_shared<double>(0.51);
    auto seed = std::make_shared<uint64_t>(1);
    auto samples = std::make_shared<int>(100000);
    auto json = std::make_shared<bool>(false);
    geometry->add_to(cmd);
    cmd->add_option("--sigma-um", *sigma, "Standard uncertainty of one ballbar distance (µm)")
        ->capture_default_str();
    cmd->add_option("--seed", *seed, "Seed of the Monte Carlo draws")->capture_default_str();
    cmd->add_option("--samples", *samples, "Monte Carlo draws per assembly mode")
        ->capture_default_str();
    cmd->add_flag("--json", *json, "Machine-readable output");
    cmd->callback([=] { run_uncertainty(*geometry, *sigma, *seed, *samples, *json); });
  }
  {
    auto* cmd = hex->add_subcommand(
        "device-validation",
        "The hexapod against an independent instrument: pose uncertainty per assembly mode, GUM "
        "and simulated comparison");
    auto geometry = std::make_shared<GeometryOptions>();
    auto measuring = std::make_shared<MeasuringOptions>();
    auto reference = std::make_shared<double>(0.005);
    auto poses = std::make_shared<int>(2000);
    auto seed = std::make_shared<uint64_t>(1);
    auto json = std::make_shared<bool>(false);
    geometry->add_to(cmd);
    measuring->add_to(cmd, false);
    cmd->add_option("--reference-sigma-mm", *reference,
                    "Reference instrument σ per axis of a tool cup (CMM ≈ 0.005, tracker 0.022)")
        ->capture_default_str();
    cmd->add_option("--poses", *poses, "Random poses per assembly mode")->capture_default_str();
    cmd->add_option("--seed", *seed, "Seed of the poses and readings")->capture_default_str();
    cmd->add_flag("--json", *json, "Machine-readable output");
    cmd->callback(
        [=] { run_device_validation(*geometry, *measuring, *reference, *poses, *seed, *json); });
  }
  {
    auto* cmd = hex->add_subcommand(
        "world-frame", "World frame from the base cups: planar least-squares correction");
    auto points = std::make_shared<std::string>();
    auto sides = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    cmd->add_option("--points", *points,
                    "Where the robot put the cups, robot frame: x1,y1,z1,x2,y2,z2,x3,y3,z3 (mm)")
        ->required();
    cmd->add_option("--sides", *sides, "Ballbar-measured b12,b23,b31 (mm)")->required();
    cmd->add_flag("--json", *json, "Machine-readable output");
    cmd->callback([=] { run_world_frame(*points, *sides, *json); });
  }
  {
    auto* cmd = hex->add_subcommand(
        "setup", "Where the robot must put the setting ball to place the base cups");
    auto cell = std::make_shared<CellOptions>();
    auto side = std::make_shared<double>(300.0);
    auto fourth = std::make_shared<FourthCupOptions>();
    auto json = std::make_shared<bool>(false);
    cell->add_to(cmd);
    cmd->add_option("--leg-mm", *side, "Distance between the cups (the ballbar's length)")
        ->capture_default_str();
    fourth->add_base_to(cmd);
    cmd->add_flag("--json", *json, "Machine-readable output");
    cmd->callback([=] { run_setup(*cell, *side, *fourth, *json); });
  }
  {
    auto* cmd = hex->add_subcommand(
        "plan",
        "Robot configurations for every pose, for a base-fixture placement (the session's plan)");
    auto geometry = std::make_shared<GeometryOptions>();
    auto cell = std::make_shared<CellOptions>();
    auto measuring = std::make_shared<MeasuringOptions>();
    auto fourth = std::make_shared<FourthCupOptions>();
    auto cell_file = std::make_shared<std::string>();
    auto out = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    geometry->add_to(cmd);
    fourth->add_to(cmd);
    cell->add_to(cmd);
    measuring->add_to(cmd);
    cmd->add_option("--cell", *cell_file,
                    "Cell file (data/cells/*.yaml): configurations stay above its floor and out of "
                    "its keep-out boxes");
    cmd->add_option("--out", *out, "Write the plan (JSON) for `robcal hexapod session`");
    cmd->add_flag("--json", *json, "Machine-readable output");
    cmd->callback(
        [=] { run_plan(*geometry, *cell, *measuring, *fourth, *cell_file, *out, *json); });
  }
  {
    auto* cmd = hex->add_subcommand(
        "place",
        "Placement search: plan every base-fixture placement of a grid and rank them by the "
        "accuracy their configurations predict; best pairs of placements");
    auto geometry = std::make_shared<GeometryOptions>();
    auto cell = std::make_shared<CellOptions>();
    auto measuring = std::make_shared<MeasuringOptions>();
    auto cell_file = std::make_shared<std::string>();
    auto grid = std::make_shared<std::array<std::string, 5>>(
        std::array<std::string, 5>{"350,450,550", "-200,0,200", "200,300", "0", "0"});
    auto level = std::make_shared<std::string>("kinematic");
    auto identify = std::make_shared<std::vector<std::string>>();
    auto validation = std::make_shared<int>(2000);
    auto task_box = std::make_shared<std::string>();
    auto seed = std::make_shared<uint64_t>(1);
    auto best = std::make_shared<int>(5);
    auto measured = std::make_shared<std::vector<std::string>>();
    auto fourth = std::make_shared<FourthCupOptions>();
    auto json = std::make_shared<bool>(false);
    geometry->add_to(cmd);
    fourth->add_to(cmd);
    cell->add_to(cmd, false);
    measuring->add_to(cmd);
    cmd->add_option("--cell", *cell_file, "Cell file: floor and keep-out boxes respected");
    cmd->add_option("--x-mm", (*grid)[0], "Grid: fixture centroid x values (mm)")
        ->capture_default_str();
    cmd->add_option("--y-mm", (*grid)[1], "Grid: centroid y values (mm)")->capture_default_str();
    cmd->add_option("--z-mm", (*grid)[2], "Grid: centroid z values (mm)")->capture_default_str();
    cmd->add_option("--yaw-deg", (*grid)[3], "Grid: yaw values (deg)")->capture_default_str();
    cmd->add_option("--tilt-deg", (*grid)[4], "Grid: platform tilt values (deg)")
        ->capture_default_str();
    cmd->add_option("--level", *level, "Parameters to identify: base, joints, kinematic")
        ->capture_default_str();
    add_identify_option(cmd, *identify);
    cmd->add_option("--validation", *validation, "Random configurations the error is predicted on")
        ->capture_default_str();
    cmd->add_option("--task-box", *task_box,
                    "Task region xmin,xmax,ymin,ymax,zmin,zmax (mm, robot frame): predict over "
                    "configurations putting the tool fixture there, tool axis down (default: the "
                    "whole workspace)");
    cmd->add_option("--seed", *seed, "Seed of the validation configurations")
        ->capture_default_str();
    cmd->add_option("--best", *best, "How many placements and pairs to list")
        ->capture_default_str();
    cmd->add_option("--measured", *measured,
                    "Plan of a placement already measured (repeat): rank the grid's placements as "
                    "the next one to measure");
    cmd->add_flag("--json", *json, "Machine-readable output");
    cmd->callback([=] {
      run_place(*geometry, *cell, *measuring, *fourth, *cell_file, *grid, *level, *identify,
                *validation, *task_box, *seed, *best, *measured, *json);
    });
  }
  {
    auto* cmd = hex->add_subcommand(
        "design",
        "Which configurations to measure at each of several planned placements (I-optimal over "
        "placements × poses × configurations), each plan written again with only those");
    auto request = std::make_shared<PlacementsDesignRequest>();
    auto level = std::make_shared<std::string>("kinematic");
    auto json = std::make_shared<bool>(false);
    cmd->add_option("--plan", request->plan_files,
                    "Plan of a placement, written by `hexapod plan --out` (repeat)")
        ->required();
    cmd->add_option("--count", request->count,
                    "Configurations in all (default: as many as the first plan offers)");
    cmd->add_option("--level", *level, "Parameters to identify: base, joints, kinematic")
        ->capture_default_str();
    add_identify_option(cmd, request->identify);
    cmd->add_option("--validation", request->validation_configurations,
                    "Random configurations the error is predicted on")
        ->capture_default_str();
    auto task_box = std::make_shared<std::string>();
    cmd->add_option("--task-box", *task_box,
                    "Task region xmin,xmax,ymin,ymax,zmin,zmax (mm, robot frame), as `hexapod "
                    "place --task-box` (default: the whole workspace)");
    cmd->add_option("--seed", request->seed, "Seed of the validation configurations")
        ->capture_default_str();
    cmd->add_option("--out", request->out_files,
                    "Reduced plan file per --plan, in the same order (repeat; written whole or "
                    "not at all)");
    cmd->add_flag("--json", *json, "Machine-readable output");
    cmd->callback([=] {
      request->level = parse_calibration_level(*level);
      if (!task_box->empty()) request->task_box = parse_task_box(*task_box, "--task-box");
      run_design(*request, *json);
    });
  }
  {
    auto* cmd = hex->add_subcommand(
        "simulate",
        "Simulated end to end: placement, planning, ballbar readings, preliminary and final "
        "calibration, laser-tracker validation");
    auto cell = std::make_shared<CellOptions>();
    auto measuring = std::make_shared<MeasuringOptions>();
    auto seed = std::make_shared<uint64_t>(1);
    auto settings = std::make_shared<EndToEndOptions>();
    auto no_leg_fit = std::make_shared<bool>(false);
    auto fourth = std::make_shared<FourthCupOptions>();
    auto json = std::make_shared<bool>(false);
    cell->add_to(cmd);
    measuring->add_to(cmd);
    fourth->add_to(cmd);
    cmd->add_option("--seed", *seed, "Seed of the true robot, the readings and the validation")
        ->capture_default_str();
    cmd->add_option("--validation", settings->validation_configurations,
                    "Random validation configurations")
        ->capture_default_str();
    cmd->add_option("--threads", settings->threads, "Threads of the all-pairs statistics")
        ->capture_default_str();
    cmd->add_flag("--no-leg-fit", *no_leg_fit, "Skip the fit from the raw leg readings");
    cmd->add_flag("--relative", settings->relative_pose_fit,
                  "Pose fits hold the base (the published relative model) instead of identifying "
                  "it");
    cmd->add_flag("--json", *json, "Machine-readable output");
    cmd->callback([=] {
      settings->leg_fit = !*no_leg_fit;
      run_simulate(*cell, *measuring, *fourth, *settings, *seed, *json);
    });
  }
  {
    auto* cmd = hex->add_subcommand(
        "session",
        "Guided measurement: prompts step by step, readings typed or piped on stdin, every "
        "reading journaled at once");
    auto request = std::make_shared<HexapodSessionRequest>();
    auto json = std::make_shared<bool>(false);
    cmd->add_option("--plan", request->plan, "Plan file (JSON, from `robcal hexapod plan --out`)")
        ->required();
    cmd->add_option("--journal", request->journal,
                    "Session journal (created; must not exist unless --resume)")
        ->required();
    cmd->add_flag("--resume", request->resume, "Replay the journal and continue where it stopped");
    cmd->add_option("--out", request->out,
                    "Result file (JSON), written once the session is complete");
    cmd->add_flag("--json", *json,
                  "Print the status and, when complete, the result as JSON (prompts go to "
                  "stderr)");
    cmd->callback([=] { run_session(*request, *json); });
  }
});

}  // namespace
}  // namespace robcal::cli
