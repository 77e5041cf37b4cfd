// Python bindings of the ballbar hexapod (include/robcal/hexapod/): fixture triangles, the tripod
// function, the direct kinematics, the 72 poses, the uncertainty and the world frame. mm outside.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <nlohmann/json.hpp>
#include <random>

#include "module_registry.hpp"
#include "py_measurements.hpp"
#include "py_session_io.hpp"
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
#include "robcal/hexapod/poses.hpp"
#include "robcal/hexapod/replan.hpp"
#include "robcal/hexapod/session_calibration.hpp"
#include "robcal/hexapod/session_workflow.hpp"
#include "robcal/hexapod/simulated_readings.hpp"
#include "robcal/hexapod/uncertainty.hpp"
#include "robcal/hexapod/world_frame.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

using namespace robcal::hexapod;

/// Rows of a 3×3 array as three cups; ValueError for any other shape.
Cups<double> cups_from_rows(const Eigen::MatrixXd& rows, const char* what) {
  if (rows.rows() != 3 || rows.cols() != 3)
    throw py::value_error(std::string(what) + ": expected a 3×3 array (one cup per row, mm)");
  return {rows.row(0).transpose(), rows.row(1).transpose(), rows.row(2).transpose()};
}

Eigen::Matrix3d rows_from_cups(const Cups<double>& cups) {
  Eigen::Matrix3d rows;
  for (int i = 0; i < 3; ++i) rows.row(i) = cups[i].transpose();
  return rows;
}

TriangleSides sides(const std::array<double, 3>& d) {
  return {d[0], d[1], d[2]};
}

/// The plan settings `hexapod.plan` and `hexapod.place` share (placement and tilt are theirs).
HexapodPlanRequest plan_request(const std::string& robot,
                                const std::array<double, 3>& base_sides_mm,
                                const std::array<double, 3>& tool_sides_mm, double leg_mm,
                                double tool_offset_mm, double ball_offset_mm, double table_z_mm,
                                double angle_deg, double distance_mm, double gauge_range_mm,
                                double gauge_sigma_mm, double cup_diameter_mm,
                                const std::optional<std::string>& cell) {
  HexapodPlanRequest r{.robot = robot,
                       .geometry = {sides(base_sides_mm), sides(tool_sides_mm), leg_mm},
                       .tool_offset_mm = tool_offset_mm,
                       .ball_offset_mm = ball_offset_mm,
                       .table_z_mm = table_z_mm,
                       .angle_deg = angle_deg,
                       .distance_mm = distance_mm,
                       .gauge = {gauge_range_mm, gauge_sigma_mm},
                       .cups = {cup_diameter_mm}};
  if (cell) r.workcell = campaign::load_cell(*cell);
  return r;
}

/// d12, d23, d31 of a fixture, followed by d14, d24, d34 when it has a fourth cup.
FixtureDistances fixture_distances(const std::vector<double>& d, const char* key) {
  if (d.size() == 3) return {sides({d[0], d[1], d[2]}), std::nullopt};
  if (d.size() == 6) return {sides({d[0], d[1], d[2]}), std::array<double, 3>{d[3], d[4], d[5]}};
  throw InputError({"<arrays>", 0, 0, key},
                   "expected 3 distances (d12, d23, d31) or 6 with a fourth cup (… d14, d24, d34)");
}

const bool registered = register_bindings(60, [](py::module_& m) {
  auto h = m.def_submodule("hexapod", "The ballbar hexapod of docs/method/07-hexapod.md (mm)");
  h.def(
      "triangle_from_sides",
      [](const std::array<double, 3>& d) {
        return rows_from_cups(fixture_cups(sides(d), "sides"));
      },
      py::arg("sides_mm"),
      "Cup positions (rows) from d12, d23, d31: c1 at the origin, c2 on x, c3 in the xy plane");
  h.def(
      "tripod",
      [](const Eigen::Vector3d& v1, const Eigen::Vector3d& v2, const Eigen::Vector3d& v3, double l1,
         double l2, double l3, int sign) -> std::optional<Eigen::Vector3d> {
        if (sign != 1 && sign != -1) throw py::value_error("sign must be +1 or -1");
        return tripod(v1, v2, v3, l1, l2, l3, sign);
      },
      py::arg("v1"), py::arg("v2"), py::arg("v3"), py::arg("l1"), py::arg("l2"), py::arg("l3"),
      py::arg("sign"), "Tri of docs/method/07-hexapod.md §2; None when there is no real solution");
  h.def(
      "solve_dkp",
      [](const std::array<double, 3>& base, const std::array<double, 3>& tool,
         const std::array<double, 6>& legs) {
        const DkpResult r = solve_dkp(sides(base), sides(tool), legs);
        if (r.status != DkpStatus::Ok) throw py::value_error(r.message);
        py::dict out;
        for (const AssemblyModeSolution& s : r.solutions)
          out[py::int_(s.mode)] = rows_from_cups(s.tool);
        return out;
      },
      py::arg("base_sides_mm"), py::arg("tool_sides_mm"), py::arg("legs_mm"),
      "Tool cups (rows, base fixture frame) by assembly mode 1..4 from b_ij, t_ij and the legs "
      "ρ11, ρ12, ρ21, ρ22, ρ23, ρ31; ValueError for ill-posed distances");
  h.def(
      "solve_four_cup_dkp",
      [](const std::vector<double>& base_mm, const std::vector<double>& tool_mm,
         const std::vector<std::tuple<int, int, double>>& legs) {
        FourCupDkpRequest request{
            fixture_distances(base_mm, "base_mm"), fixture_distances(tool_mm, "tool_mm"), {}};
        for (const auto& [b, t, length] : legs) {
          if (b < 1 || b > 4 || t < 1 || t > 4)
            throw InputError({"<arrays>", 0, 0, "legs"},
                             "a leg is (base cup, tool cup, length mm) with cups 1..4");
          request.legs.push_back({b - 1, t - 1, length});
        }
        const FourCupDkpResult r = solve_four_cup_dkp(request);
        if (r.status != FourCupDkpStatus::Ok) {
          const char* key = r.culprit == FourCupInput::BaseFixture   ? "base_mm"
                            : r.culprit == FourCupInput::ToolFixture ? "tool_mm"
                                                                     : "legs";
          throw InputError({"<arrays>", 0, 0, key}, r.message);
        }
        return json_to_python(four_cup_dkp_json(r));
      },
      py::arg("base_mm"), py::arg("tool_mm"), py::arg("legs"),
      "`robcal hexapod dkp` with a fourth cup: the least-squares cup positions (base fixture "
      "frame, mm) from the fixtures' distances (d12, d23, d31, and d14, d24, d34 for a fourth "
      "cup) and the legs as (base cup, tool cup, length mm) with cups 1..4; the CLI's JSON as a "
      "dict (docs/method/07-hexapod.md §7); InputError naming the bad argument");
  h.def(
      "leg_lengths",
      [](const Eigen::MatrixXd& base, const Eigen::MatrixXd& tool) {
        return leg_lengths(cups_from_rows(base, "base"), cups_from_rows(tool, "tool"));
      },
      py::arg("base_cups"), py::arg("tool_cups"), "The six legs of design 1^12 2^123 3^1");
  h.def(
      "enumerate_poses",
      [](const std::array<double, 3>& base, const std::array<double, 3>& tool, double leg_mm,
         double angle_deg, double distance_mm) {
        const std::vector<HexapodPose> all = enumerate_poses({sides(base), sides(tool), leg_mm});
        py::list out;
        for (const HexapodPose& p : prune_redundant(all, deg2rad(angle_deg), distance_mm)) {
          py::dict d;
          d["label"] = p.label;
          d["mode"] = p.mode;
          d["rotation_deg"] = p.rotation_deg;
          d["base_roles"] = p.design.base;
          d["tool_cups"] = rows_from_cups(p.tool_cups);
          out.append(d);
        }
        return out;
      },
      py::arg("base_sides_mm") = std::array<double, 3>{300, 300, 300},
      py::arg("tool_sides_mm") = std::array<double, 3>{150, 150, 150}, py::arg("leg_mm") = 300.0,
      py::arg("angle_deg") = 0.0, py::arg("distance_mm") = 0.0,
      "The poses (72 before pruning) with every leg at leg_mm, pruned at the given distances");
  h.def(
      "uncertainty",
      [](double base_mm, double tool_mm, double leg_mm, double sigma_um, int samples,
         uint64_t seed) {
        const HexapodGeometry g{{base_mm, base_mm, base_mm}, {tool_mm, tool_mm, tool_mm}, leg_mm};
        const UncertaintyStudy study = uncertainty_study(g, sigma_um, seed, samples);
        const auto& analytic = study.analytic;
        const auto& mc = study.monte_carlo;
        py::list out;
        for (size_t m = 0; m < analytic.size(); ++m) {
          py::dict d;
          d["mode"] = analytic[m].mode;
          d["sensitivity"] = Eigen::MatrixXd(analytic[m].sensitivity);
          Eigen::Matrix3d per_axis, mc_axis;
          Eigen::Vector3d norm, mc_norm;
          for (int j = 0; j < 3; ++j) {
            per_axis.row(j) = analytic[m].cups[j].per_axis.transpose();
            mc_axis.row(j) = mc[m].cups[j].per_axis.transpose();
            norm[j] = analytic[m].cups[j].norm;
            mc_norm[j] = mc[m].cups[j].norm;
          }
          d["per_axis_sigma"] = per_axis;
          d["norm_sigma"] = norm;
          d["monte_carlo_per_axis_sigma"] = mc_axis;
          d["monte_carlo_norm_sigma"] = mc_norm;
          out.append(d);
        }
        return out;
      },
      py::arg("base_mm") = 300.0, py::arg("tool_mm") = 150.0, py::arg("leg_mm") = 300.0,
      py::arg("sigma_um") = 0.51, py::arg("samples") = 20000, py::arg("seed") = 1,
      "Per mode: sensitivity (9×12), σ per axis and norm of each tool cup in multiples of σ, "
      "analytic and Monte Carlo");
  h.def(
      "fit_world_frame",
      [](const Eigen::MatrixXd& points, const std::array<double, 3>& measured) {
        const WorldFrameFit fit =
            fit_world_frame(cups_from_rows(points, "points"), sides(measured));
        py::dict d;
        d["corrected"] = rows_from_cups(fit.corrected);
        d["rotation"] = fit.robot_T_fixture.R;
        d["origin_mm"] = fit.robot_T_fixture.p;
        d["planar"] = Eigen::Vector3d(fit.planar[0], fit.planar[1], rad2deg(fit.planar[2]));
        d["rms_mm"] = fit.rms_mm;
        d["converged"] = fit.converged;
        return d;
      },
      py::arg("robot_points"), py::arg("measured_sides_mm"),
      "World frame from the base cups: planar least-squares correction; planar = (x mm, y mm, φ "
      "deg)");

  py::class_<HexapodPlan>(h, "Plan",
                          "A hexapod measurement plan (`robcal hexapod plan`): the session's "
                          "configurations and, when planned here, the cell and the outcome")
      .def_property_readonly(
          "joints_deg",
          [](const HexapodPlan& p) {
            const auto& list = p.session.configurations;
            Eigen::MatrixXd out(static_cast<Eigen::Index>(list.size()), kJointCount);
            for (size_t r = 0; r < list.size(); ++r)
              for (int j = 0; j < kJointCount; ++j)
                out(static_cast<Eigen::Index>(r), j) =
                    list[r].joints_deg.empty() ? NAN : list[r].joints_deg[static_cast<size_t>(j)];
            return out;
          },
          "N×6 controller joints (deg) of the configurations (NaN rows: pose-only plan)")
      .def_property_readonly(
          "poses",
          [](const HexapodPlan& p) {
            std::vector<std::string> out;
            for (const SessionConfiguration& c : p.session.configurations) out.push_back(c.pose);
            return out;
          },
          "Pose label of each configuration")
      .def_property_readonly(
          "labels",
          [](const HexapodPlan& p) {
            std::vector<std::string> out;
            for (const SessionConfiguration& c : p.session.configurations) out.push_back(c.labels);
            return out;
          },
          "Arm configuration label of each configuration")
      .def_property_readonly(
          "setting_ball_mm",
          [](const HexapodPlan& p) -> std::optional<Eigen::MatrixXd> {
            if (!p.session.setting_points) return std::nullopt;
            Eigen::MatrixXd rows(p.session.setting_point4 ? 4 : 3, 3);
            rows.topRows<3>() = rows_from_cups(*p.session.setting_points);
            if (p.session.setting_point4) rows.row(3) = p.session.setting_point4->transpose();
            return rows;
          },
          "Where the robot puts the setting ball for B1..B3, and B4 with a fourth base cup (3×3 "
          "or 4×3, robot frame, mm), or None")
      .def(
          "to_json", [](const HexapodPlan& p) { return hexapod_plan_json(p).dump(2) + "\n"; },
          "The plan file's text (what `robcal hexapod plan --out` writes)")
      .def(
          "save",
          [](const HexapodPlan& p, const std::string& path) { write_hexapod_plan(path, p); },
          py::arg("path"), "Writes the plan file, whole or not at all")
      .def("__len__", [](const HexapodPlan& p) { return p.session.configurations.size(); })
      .def("__repr__", [](const HexapodPlan& p) {
        std::string text =
            "<hexapod.Plan " + std::to_string(p.session.configurations.size()) + " configurations";
        if (p.outcome)
          text += " of " + std::to_string(p.outcome->poses_measurable) + " measurable poses (" +
                  std::to_string(p.outcome->poses_kept) + " kept of " +
                  std::to_string(p.outcome->poses_enumerated) + ")";
        if (p.cell) text += " for " + p.cell->robot;
        return text + ">";
      });
  h.def(
      "plan",
      [](const std::string& robot, const std::array<double, 3>& base_sides_mm,
         const std::array<double, 3>& tool_sides_mm, double leg_mm,
         const std::array<double, 4>& placement, double tilt_deg, double tool_offset_mm,
         double ball_offset_mm, double table_z_mm, double angle_deg, double distance_mm,
         double gauge_range_mm, double gauge_sigma_mm, double cup_diameter_mm,
         const std::optional<std::string>& cell,
         const std::optional<std::array<double, 3>>& tool_cup4_mm,
         const std::optional<std::array<double, 3>>& base_cup4_mm) {
        HexapodPlanRequest r = plan_request(
            robot, base_sides_mm, tool_sides_mm, leg_mm, tool_offset_mm, ball_offset_mm, table_z_mm,
            angle_deg, distance_mm, gauge_range_mm, gauge_sigma_mm, cup_diameter_mm, cell);
        r.placement = placement;
        r.tilt_deg = tilt_deg;
        r.geometry.tool_cup4_mm = tool_cup4_mm;
        r.geometry.base_cup4_mm = base_cup4_mm;
        return plan_hexapod(load_robot(robot), r);
      },
      py::arg("robot") = "fanuc-lrmate200ic",
      py::arg("base_sides_mm") = std::array<double, 3>{300, 300, 300},
      py::arg("tool_sides_mm") = std::array<double, 3>{150, 150, 150}, py::arg("leg_mm") = 300.0,
      py::arg("placement") = std::array<double, 4>{450, 0, 300, 0}, py::arg("tilt_deg") = 0.0,
      py::arg("tool_offset_mm") = 100.0, py::arg("ball_offset_mm") = 100.0,
      py::arg("table_z_mm") = 0.0, py::arg("angle_deg") = 30.0, py::arg("distance_mm") = 50.0,
      py::arg("gauge_range_mm") = LengthGauge{}.range_mm,
      py::arg("gauge_sigma_mm") = LengthGauge{}.sigma_mm,
      py::arg("cup_diameter_mm") = CupClearance{}.cup_diameter_mm, py::arg("cell") = py::none(),
      py::arg("tool_cup4_mm") = py::none(), py::arg("base_cup4_mm") = py::none(),
      "Plans a hexapod measurement (`robcal hexapod plan`): placement = (x, y, z mm, yaw deg) of "
      "the base cups' centroid in the robot frame, tilt_deg of the pivoting platform, the gauge's "
      "range and σ, the cup diameter (colliding poses refused), a cell file (its floor and "
      "keep-out boxes respected), a fourth tool cup by its distances (d14, d24, d34) to T1..T3 "
      "(`--tool-cup4-mm`) and a fourth base cup by its distances to B1..B3 (`--base-cup4-mm`)");
  h.def(
      "place",
      [](const std::string& robot, const std::vector<double>& x_mm, const std::vector<double>& y_mm,
         const std::vector<double>& z_mm, const std::vector<double>& yaw_deg,
         const std::vector<double>& tilt_deg, const std::string& level, int validation,
         uint64_t seed, int best, const std::vector<std::string>& measured,
         const std::array<double, 3>& base_sides_mm, const std::array<double, 3>& tool_sides_mm,
         double leg_mm, double tool_offset_mm, double ball_offset_mm, double table_z_mm,
         double angle_deg, double distance_mm, double gauge_range_mm, double gauge_sigma_mm,
         double cup_diameter_mm, const std::optional<std::string>& cell,
         const std::optional<std::array<double, 3>>& tool_cup4_mm,
         const std::vector<std::string>& identify,
         const std::optional<std::array<double, 3>>& base_cup4_mm,
         const std::optional<std::string>& task_box) {
        PlacementSearchRequest r;
        r.plan = plan_request(robot, base_sides_mm, tool_sides_mm, leg_mm, tool_offset_mm,
                              ball_offset_mm, table_z_mm, angle_deg, distance_mm, gauge_range_mm,
                              gauge_sigma_mm, cup_diameter_mm, cell);
        r.plan.geometry.tool_cup4_mm = tool_cup4_mm;
        r.plan.geometry.base_cup4_mm = base_cup4_mm;
        check_geometry(r.plan.geometry);  // as the CLI: the fixtures before the measured plans
        if (task_box) r.task_box = parse_task_box(*task_box, "task_box");
        for (const std::string& plan : measured)
          r.measured.push_back(measured_placement(read_hexapod_plan(plan), plan));
        r.x_mm = x_mm;
        r.y_mm = y_mm;
        r.z_mm = z_mm;
        r.yaw_deg = yaw_deg;
        r.tilt_deg = tilt_deg;
        r.level = parse_calibration_level(level);
        r.identify = identify;
        r.validation_configurations = validation;
        r.seed = seed;
        r.best = best;
        const RobotModel model = load_robot(robot);
        PlacementSearchResult result;
        {
          py::gil_scoped_release release;
          result = search_placements(model, r);
        }
        return json_to_python(placement_search_json(result));
      },
      py::arg("robot") = "fanuc-lrmate200ic", py::arg("x_mm") = std::vector<double>{350, 450, 550},
      py::arg("y_mm") = std::vector<double>{-200, 0, 200},
      py::arg("z_mm") = std::vector<double>{200, 300}, py::arg("yaw_deg") = std::vector<double>{0},
      py::arg("tilt_deg") = std::vector<double>{0}, py::arg("level") = "kinematic",
      py::arg("validation") = 2000, py::arg("seed") = 1, py::arg("best") = 5,
      py::arg("measured") = std::vector<std::string>{},
      py::arg("base_sides_mm") = std::array<double, 3>{300, 300, 300},
      py::arg("tool_sides_mm") = std::array<double, 3>{150, 150, 150}, py::arg("leg_mm") = 300.0,
      py::arg("tool_offset_mm") = 100.0, py::arg("ball_offset_mm") = 100.0,
      py::arg("table_z_mm") = 0.0, py::arg("angle_deg") = 30.0, py::arg("distance_mm") = 50.0,
      py::arg("gauge_range_mm") = LengthGauge{}.range_mm,
      py::arg("gauge_sigma_mm") = LengthGauge{}.sigma_mm,
      py::arg("cup_diameter_mm") = CupClearance{}.cup_diameter_mm, py::arg("cell") = py::none(),
      py::arg("tool_cup4_mm") = py::none(), py::arg("identify") = std::vector<std::string>{},
      py::arg("base_cup4_mm") = py::none(), py::arg("task_box") = py::none(),
      "Placement search (`robcal hexapod place`): the grid's placements ranked by predicted "
      "accuracy, and the best pairs; with `measured` (plan files of the placements already "
      "measured) the grid's placements ranked as the next one ('next'); the fixtures, offsets, "
      "pruning, gauge (range and σ, mm), cup diameter, cell file and fourth cups as `plan`'s "
      "(the CLI's flags); `identify`: opt-in groups or patterns predicted for too (`--identify`); "
      "`task_box` \"xmin,xmax,ymin,ymax,zmin,zmax\" (mm, robot frame): the task region the "
      "predictions are over (`--task-box`; default the whole workspace); the CLI's JSON as a dict");
  h.def(
      "design",
      [](const std::vector<std::string>& plans, int count, const std::string& level, int validation,
         uint64_t seed, const std::vector<std::string>& out,
         const std::vector<std::string>& identify, const std::optional<std::string>& task_box) {
        PlacementsDesignRequest r;
        if (task_box) r.task_box = parse_task_box(*task_box, "task_box");
        r.plan_files = plans;
        r.count = count;
        r.level = parse_calibration_level(level);
        r.identify = identify;
        r.validation_configurations = validation;
        r.seed = seed;
        r.out_files = out;
        PlacementsDesignResult result;
        {
          py::gil_scoped_release release;
          result = design_placements(r);
        }
        return json_to_python(placements_design_json(r, result));
      },
      py::arg("plans"), py::arg("count") = 0, py::arg("level") = "kinematic",
      py::arg("validation") = 2000, py::arg("seed") = 1,
      py::arg("out") = std::vector<std::string>{}, py::arg("identify") = std::vector<std::string>{},
      py::arg("task_box") = py::none(),
      "Which configurations to measure at each of several planned placements (`robcal hexapod "
      "design`): plans = plan files written by `plan`, count = configurations in all (0: as many "
      "as the first plan offers); `out` = one reduced plan file per plan (none written for a "
      "placement with nothing chosen); `identify` and `task_box` as `place`'s; the CLI's JSON as "
      "a dict");
  h.def(
      "device_validation",
      [](const std::array<double, 3>& base_sides_mm, const std::array<double, 3>& tool_sides_mm,
         double leg_mm, double gauge_range_mm, double gauge_sigma_mm, double reference_sigma_mm,
         int poses, uint64_t seed) {
        DeviceValidationRequest r;
        r.geometry = {sides(base_sides_mm), sides(tool_sides_mm), leg_mm};
        r.gauge = {gauge_range_mm, gauge_sigma_mm};
        r.reference_sigma_mm = reference_sigma_mm;
        r.poses_per_mode = poses;
        r.seed = seed;
        return json_to_python(device_validation_json(validate_device(r), r));
      },
      py::arg("base_sides_mm") = std::array<double, 3>{300, 300, 300},
      py::arg("tool_sides_mm") = std::array<double, 3>{150, 150, 150}, py::arg("leg_mm") = 300.0,
      py::arg("gauge_range_mm") = 1.0, py::arg("gauge_sigma_mm") = 0.00051,
      py::arg("reference_sigma_mm") = 0.005, py::arg("poses") = 2000, py::arg("seed") = 1,
      "The hexapod against an independent instrument (`robcal hexapod device-validation`): per "
      "assembly mode, GUM and simulated scatter; the CLI's JSON as a dict");
  h.def(
      "simulate",
      [](const std::string& robot, const std::array<double, 4>& placement, double tool_offset_mm,
         double ball_offset_mm, double table_z_mm, double angle_deg, double distance_mm,
         uint64_t seed, int validation, int threads, bool leg_fit, bool relative,
         const std::optional<std::array<double, 3>>& tool_cup4_mm,
         const std::optional<std::array<double, 3>>& base_cup4_mm) {
        HexapodGeometry geometry;
        geometry.tool_cup4_mm = tool_cup4_mm;
        geometry.base_cup4_mm = base_cup4_mm;
        const HexapodPlanRequest cell{.geometry = geometry,
                                      .placement = placement,
                                      .tool_offset_mm = tool_offset_mm,
                                      .ball_offset_mm = ball_offset_mm,
                                      .table_z_mm = table_z_mm,
                                      .angle_deg = angle_deg,
                                      .distance_mm = distance_mm};
        const EndToEndOptions settings{.validation_configurations = validation,
                                       .threads = threads,
                                       .leg_fit = leg_fit,
                                       .relative_pose_fit = relative};
        const EndToEndOptions o = end_to_end_options(cell, settings);
        const RobotModel model = load_robot(robot);
        std::mt19937_64 rng(seed);
        EndToEndReport report;
        {
          py::gil_scoped_release release;
          report = run_end_to_end(model, o, rng);
        }
        return json_to_python(end_to_end_json(report, o, seed));
      },
      py::arg("robot") = "fanuc-lrmate200ic",
      py::arg("placement") = std::array<double, 4>{450, 0, 300, 0},
      py::arg("tool_offset_mm") = 100.0, py::arg("ball_offset_mm") = 100.0,
      py::arg("table_z_mm") = 0.0, py::arg("angle_deg") = 30.0, py::arg("distance_mm") = 50.0,
      py::arg("seed") = 1, py::arg("validation") = 10000, py::arg("threads") = 2,
      py::arg("leg_fit") = true, py::arg("relative") = false, py::arg("tool_cup4_mm") = py::none(),
      py::arg("base_cup4_mm") = py::none(),
      "Simulated end to end (`robcal hexapod simulate`): placement, planning, ballbar readings, "
      "preliminary and final calibration, laser-tracker validation; a fourth tool cup by its "
      "distances (d14, d24, d34) to T1..T3 (`--tool-cup4-mm`), a fourth base cup by its distances "
      "to B1..B3 (`--base-cup4-mm`); the CLI's JSON as a dict");
  h.def(
      "calibrate",
      [](const std::vector<std::string>& sessions, const std::string& robot,
         const std::optional<std::string>& tool, const std::string& level, const std::string& fit,
         bool relative, double orientation_weight_mm, uint64_t seed,
         const std::optional<std::string>& plan, const std::optional<std::string>& out,
         const std::vector<std::string>& identify) {
        SessionCalibrationRequest request;
        request.fit = parse_session_fit(fit);
        request.level = parse_calibration_level(level);
        request.identify = identify;
        check_identify_patterns(request.level, request.identify);
        request.relative = relative;
        request.orientation_weight_mm = orientation_weight_mm;
        request.seed = seed;
        const RobotModel model = load_robot(robot);
        const std::vector<SessionData> placements = load_placements(sessions, plan.value_or(""));
        const PointMass payload = tool ? load_tool(*tool).payload : PointMass{};
        SessionCalibration c;
        {
          py::gil_scoped_release release;
          c = calibrate_sessions(placements, model, payload, request);
        }
        if (out) write_file_atomically(*out, c.model_file);
        py::object d =
            json_to_python(session_calibration_json(placements, model, c, out.value_or("")));
        d["model"] = c.robot;
        d["tool"] = c.tool;
        d["poses"] = Measurements{c.poses, c.tool, {}};
        return d;
      },
      py::arg("sessions"), py::arg("robot") = "fanuc-lrmate200ic", py::arg("tool") = py::none(),
      py::arg("level") = "full", py::arg("fit") = "poses", py::arg("relative") = false,
      py::arg("orientation_weight_mm") = kDefaultOrientationWeightMm, py::arg("seed") = 1,
      py::arg("plan") = py::none(), py::arg("out") = py::none(),
      py::arg("identify") = std::vector<std::string>{},
      "Calibrates from measured sessions (`robcal hexapod calibrate`; sessions of several "
      "base-fixture placements together with fit='legs'): the CLI's JSON as a dict "
      "plus model (CalibratedRobot), tool (the tool fixture) and poses (Measurements); with `out` "
      "the calibrated model file is written");
  h.def(
      "replan",
      [](const std::vector<std::string>& sessions, const std::string& model, const std::string& out,
         const std::optional<std::string>& plan) {
        const Replan r = replan_retries(load_sessions(sessions, plan.value_or("")),
                                        load_calibrated_robot(model), model);
        write_hexapod_plan(out, r.plan);
        return json_to_python(replan_json(r, out));
      },
      py::arg("sessions"), py::arg("model"), py::arg("out"), py::arg("plan") = py::none(),
      "Re-plans the configurations to retry of measured sessions on a preliminary calibrated "
      "model (`robcal hexapod replan`), writes the new plan to `out`, returns the CLI's JSON");
  h.def(
      "simulate_readings",
      [](const HexapodPlan& plan, const std::string& robot, const std::optional<Tool>& payload,
         uint64_t seed, int validation) {
        SimulatedReadingsRequest request{"<plan>", std::nullopt, seed, validation};
        if (payload) request.payload = payload->payload;
        const SimulatedReadings r = simulate_readings(plan, load_robot(robot), request);
        py::object d = json_to_python(simulated_readings_json(r, "", "", ""));
        d["text"] = readings_text(r);
        d["tool"] = r.tool;
        d["validation"] = Measurements{r.validation, r.tool, {}};
        return d;
      },
      py::arg("plan"), py::arg("robot") = "fanuc-lrmate200ic", py::arg("payload") = py::none(),
      py::arg("seed") = 1, py::arg("validation") = 1000,
      "Simulated readings of a planned session (`robcal hexapod simulate-readings`): the CLI's "
      "JSON as a dict (seed, readings, legs_out_of_range) with text (the session's input), tool "
      "(the tool fixture as a Tool) and validation (tracker Measurements on cup T1) in place of "
      "the files; `payload` is a Tool whose payload the robot carries (default 2.6 kg at (50, "
      "25, 100) mm)");
  h.def(
      "session",
      [](const std::string& plan, const std::string& journal,
         const std::vector<std::string>& answers, bool resume,
         const std::optional<std::string>& out) {
        ListedAnswers operator_side{answers};
        const HexapodSessionRun run =
            run_hexapod_session({plan, journal, resume, out.value_or("")}, operator_side.io());
        py::object d = json_to_python(hexapod_session_json(run));
        d["transcript"] = operator_side.transcript;
        d["refused"] = operator_side.refused;
        return d;
      },
      py::arg("plan"), py::arg("journal"), py::arg("answers"), py::arg("resume") = false,
      py::arg("out") = py::none(),
      "The guided session (`robcal hexapod session`) fed `answers` (lines: a reading in mm, "
      "'out', 'quit'; e.g. simulate_readings' text.splitlines()) instead of a terminal; every "
      "reading journalled at once, `resume` continues a journal. The CLI's JSON as a dict "
      "(status complete or paused-…, replayed, answered, result when complete: also written to "
      "`out`) plus transcript (the prompts and messages) and refused (answers asked again)");
  h.def(
      "export_poses",
      [](const std::vector<std::string>& sessions, const std::string& out,
         const std::optional<std::string>& legs_out, const std::optional<std::string>& tool_out,
         const std::optional<std::string>& tool, const std::optional<std::string>& plan) {
        const SessionData data = load_sessions(sessions, plan.value_or(""));
        const SessionExportPaths paths{out, legs_out.value_or(""), tool_out.value_or("")};
        const SessionExport exported =
            export_session(data, tool ? load_tool(*tool).payload : PointMass{}, paths);
        for (const auto& [path, text] : exported.files) write_file_atomically(path, text);
        py::object d = json_to_python(session_export_json(data, exported, paths));
        d["tool_fixture"] = exported.tool;
        d["measurements"] = Measurements{session_pose_measurements(data), exported.tool, {}};
        return d;
      },
      py::arg("sessions"), py::arg("out"), py::arg("legs_out") = py::none(),
      py::arg("tool_out") = py::none(), py::arg("tool") = py::none(), py::arg("plan") = py::none(),
      "Writes a session's readings as a poses measurement CSV `out` (for calibrate), and the raw "
      "legs CSV and the tool file when given (`robcal hexapod export-poses`); `tool`: the tool "
      "file whose payload the robot carried. The CLI's JSON as a dict plus tool_fixture (Tool) "
      "and measurements (the poses as Measurements)");
  h.def(
      "read_plan", [](const std::string& path) { return read_hexapod_plan(path); }, py::arg("path"),
      "Reads a plan file (written by `robcal hexapod plan` or `replan`, or by hand)");
  h.def(
      "setup",
      [](const std::string& robot, const std::array<double, 4>& placement, double tilt_deg,
         double side_mm, double ball_offset_mm,
         const std::optional<std::array<double, 3>>& base_cup4_mm) {
        HexapodGeometry base;
        base.base = {side_mm, side_mm, side_mm};
        base.leg_mm = side_mm;
        base.base_cup4_mm = base_cup4_mm;
        check_geometry(base);  // as the CLI: a bad B4 named
        return json_to_python(
            setup_json(robot, side_mm,
                       plan_setting_ball(load_robot(robot), placement_pose(placement, tilt_deg),
                                         side_mm, ball_offset_mm, base_cup4_mm)));
      },
      py::arg("robot") = "fanuc-lrmate200ic",
      py::arg("placement") = std::array<double, 4>{450, 0, 300, 0}, py::arg("tilt_deg") = 0.0,
      py::arg("side_mm") = 300.0, py::arg("ball_offset_mm") = 100.0,
      py::arg("base_cup4_mm") = py::none(),
      "Where to put the setting ball for each base cup (`robcal hexapod setup`): the CLI's JSON "
      "as a dict, setting_ball holding per cup its position (robot frame, mm) and the "
      "configurations reaching it (labels, joints_deg); B4 too with a fourth base cup by its "
      "distances to B1..B3 (`--base-cup4-mm`)");
});

}  // namespace
}  // namespace robcal::python
