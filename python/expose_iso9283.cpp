// Python binding of ISO 9283 (include/robcal/validate/iso9283.hpp): the test cube, its poses,
// the cycles (and the multi-directional test's approaches), and the analysis of measured cycles;
// the same results and JSON as `robcal iso9283 plan|analyse`. Also the other validation tests'
// file workflows (validate/test_workflows.hpp): axis test, ballbar path.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "module_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/report/report.hpp"
#include "robcal/validate/iso9283.hpp"
#include "robcal/validate/test_workflows.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

py::dict planned_pose_dict(const Iso9283PlannedPose& p) {
  py::dict d;
  d["name"] = p.name;
  d["position_mm"] = p.world_T_tcp.p;
  d["joints_deg"] = Vector6d(p.joints * kRadToDeg);
  return d;
}

py::dict plan_dict(const Iso9283Plan& plan, const ArmConfig& config) {
  py::dict d;
  d["cube_centre_mm"] = plan.cube_centre_mm;
  d["cube_edge_mm"] = plan.cube_edge_mm;
  py::list corners, poses, sequence, approaches, vap_sequence;
  for (const Eigen::Vector3d& c : plan.corners_mm) corners.append(c);
  for (const Iso9283PlannedPose& p : plan.poses) poses.append(planned_pose_dict(p));
  for (const auto& [cycle, pose] : plan.sequence) sequence.append(py::make_tuple(cycle, pose));
  for (const auto& from : plan.approaches) {
    py::list three;
    for (const Iso9283PlannedPose& p : from) three.append(planned_pose_dict(p));
    approaches.append(three);
  }
  for (const Iso9283Move& m : plan.vap_sequence) {
    py::dict move;
    move["cycle"] = m.cycle;
    move["pose"] = m.pose;
    move["direction"] = m.direction;
    move["approach"] = m.approach;
    vap_sequence.append(move);
  }
  d["corners_mm"] = corners;
  d["poses"] = poses;
  d["sequence"] = sequence;
  d["approaches"] = approaches;
  d["vap_sequence"] = vap_sequence;
  d["pose_list_csv"] = iso9283_pose_list_csv(plan, config);
  d["cycles_csv"] = iso9283_cycles_csv(plan);
  d["vap_cycles_csv"] = iso9283_vap_cycles_csv(plan);
  return d;
}

/// The arm configuration named by `label` (ArmConfig::label()); InputError at `key` otherwise.
ArmConfig arm_config_of(const std::string& label, const char* key) {
  const std::optional<ArmConfig> arm = parse_arm_config(label);
  if (!arm) throw InputError({"", 0, 0, key}, "unknown configuration '" + label + "'");
  return *arm;
}

/// A tool orientation from a quaternion w, x, y, z; the tests' default (pointing down) for None.
Eigen::Matrix3d orientation_of(const std::optional<Eigen::Vector4d>& quaternion_wxyz) {
  if (!quaternion_wxyz) return iso9283_default_orientation();
  return pose_from_position_quaternion(Eigen::Vector3d::Zero(), *quaternion_wxyz).R;
}

/// The test's request from the arguments of iso9283_plan and iso9283_plan_files (no robot yet).
Iso9283PlanRequest test_of(const Eigen::Vector3d& region_min_mm,
                           const Eigen::Vector3d& region_max_mm,
                           const std::optional<Eigen::Vector4d>& quaternion_wxyz,
                           const std::string& config, int cycles, double vap_approach_mm) {
  Iso9283PlanRequest request;
  request.region_min_mm = region_min_mm;
  request.region_max_mm = region_max_mm;
  request.world_R_tcp = orientation_of(quaternion_wxyz);
  request.config = arm_config_of(config, "config");
  request.cycles = cycles;
  request.vap_approach_mm = vap_approach_mm;
  return request;
}

const bool registered = register_bindings(72, [](py::module_& m) {
  m.def(
      "iso9283_plan",
      [](const CalibratedRobot& robot, const Eigen::Vector3d& region_min_mm,
         const Eigen::Vector3d& region_max_mm,
         const std::optional<Eigen::Vector4d>& quaternion_wxyz, const std::string& config,
         int cycles, double vap_approach_mm) {
        Iso9283PlanRequest request =
            test_of(region_min_mm, region_max_mm, quaternion_wxyz, config, cycles, vap_approach_mm);
        request.robot = robot;
        return plan_dict(iso9283_plan(request), request.config);
      },
      py::arg("robot"), py::arg("region_min_mm"), py::arg("region_max_mm"),
      py::arg("quaternion_wxyz") = py::none(), py::arg("config") = "front-up-noflip",
      py::arg("cycles") = kIso9283Cycles, py::arg("vap_approach_mm") = 0.0,
      "The ISO 9283 test cube in a workspace region (world, mm), its poses P1-P5 (tool "
      "orientation quaternion_wxyz, default 0,0,1,0: pointing down) with joint targets from the "
      "robot's compensation IK, the cycles and, with vap_approach_mm > 0, the "
      "multi-directional test's pre-poses and moves (`robcal iso9283 plan`); also the pose-list "
      "and cycle CSVs as text");
  m.def(
      "iso9283_analyse",
      [](const std::string& poses, const std::string& measurements, int min_cycles) {
        return json_to_python(iso9283_json(iso9283_analyse_files(poses, measurements, min_cycles)));
      },
      py::arg("poses"), py::arg("measurements"), py::arg("min_cycles") = kIso9283Cycles,
      "AP, RP (position, orientation), vAP, AD, RD of measured cycles (`robcal iso9283 "
      "analyse`): the commanded poses' pose list and the measurements CSV; the same JSON as "
      "the CLI's --json");

  m.def(
      "iso9283_plan_files",
      [](const std::string& robot, const Eigen::Vector3d& region_min_mm,
         const Eigen::Vector3d& region_max_mm, const std::string& tool, const std::string& model,
         const std::optional<Eigen::Vector4d>& quaternion_wxyz, const std::string& config,
         int cycles, double vap_approach_mm, const std::string& out_poses,
         const std::string& out_cycles, const std::string& out_vap_cycles,
         const std::string& program, const std::string& program_dir) {
        Iso9283PlanFilesRequest request;
        request.robot = robot;
        request.tool = tool;
        request.model = model;
        request.test =
            test_of(region_min_mm, region_max_mm, quaternion_wxyz, config, cycles, vap_approach_mm);
        request.out_poses = out_poses;
        request.out_cycles = out_cycles;
        request.out_vap_cycles = out_vap_cycles;
        request.program = program;
        request.program_dir = program_dir;
        return json_to_python(iso9283_plan_json(iso9283_plan_files(request)));
      },
      py::arg("robot"), py::arg("region_min_mm"), py::arg("region_max_mm"), py::arg("tool") = "",
      py::arg("model") = "", py::arg("quaternion_wxyz") = py::none(),
      py::arg("config") = "front-up-noflip", py::arg("cycles") = kIso9283Cycles,
      py::arg("vap_approach_mm") = 0.0, py::arg("out_poses") = "iso9283-poses.csv",
      py::arg("out_cycles") = "iso9283-cycles.csv",
      py::arg("out_vap_cycles") = "iso9283-vap-cycles.csv", py::arg("program") = "",
      py::arg("program_dir") = "iso9283-programs",
      "`robcal iso9283 plan` on files: robot (name or file), tool file, calibrated model file; "
      "writes the pose list, the cycles (the vAP cycles, the robot programs with `program`: "
      "rapid, krl, ls, urscript) and returns the CLI's --json document");

  m.def(
      "axis_test_plan",
      [](int joint, const Eigen::Matrix<double, 6, 1>& home_deg, double from_deg, double to_deg,
         int steps, double approach_deg, const std::string& out) {
        AxisTestPlanRequest request;
        request.home = home_deg * kDegToRad;
        request.joint = joint - 1;
        request.from_rad = deg2rad(from_deg);
        request.to_rad = deg2rad(to_deg);
        request.steps = steps;
        request.approach_rad = deg2rad(approach_deg);
        const std::vector<AxisTestMove> moves =
            out.empty() ? axis_test_moves(request) : axis_test_plan_file(request, out);
        py::dict d;
        d["csv"] = axis_test_moves_csv(moves);
        d["moves"] = moves.size();
        return d;
      },
      py::arg("joint"), py::arg("home_deg"), py::arg("from_deg"), py::arg("to_deg"),
      py::arg("steps") = 12, py::arg("approach_deg") = 5.0, py::arg("out") = "",
      "`robcal axis-test plan`: joint 1..6 moved from from_deg to to_deg in `steps` positions, "
      "each approached from approach_deg below and above, the others at home_deg; {'csv': the "
      "moves file's text, 'moves'}; written to `out` when given");
  m.def(
      "axis_test_analyse",
      [](const std::string& measurements) {
        py::dict d = json_to_python(axis_test_json(axis_test_analyse_file(measurements)));
        d["measurements"] = measurements;
        return d;
      },
      py::arg("measurements"),
      "`robcal axis-test analyse` of a CSV joint_deg,side,x,y,z: circle, backlash, tangential/"
      "radial/axial errors; the CLI's --json document");

  m.def(
      "ballbar_path",
      [](const std::string& robot, const std::string& tool, const std::string& target,
         const Eigen::Vector3d& centre_mm, double length_mm, const std::string& out,
         const std::string& model, const std::string& reading_model, double range_mm,
         const std::optional<Eigen::Vector3d>& axis,
         const std::optional<std::vector<double>>& elevations_deg, int points,
         const std::optional<Eigen::Vector4d>& quaternion_wxyz, const std::string& config) {
        BallbarPathFilesRequest request;
        request.robot = robot;
        request.tool = tool;
        request.target = target;
        request.model = model;
        request.reading_model = reading_model;
        BallbarPathRequest& path = request.path;
        path.centre_mm = centre_mm;
        path.length_mm = length_mm;
        path.range_mm = range_mm;
        if (axis) path.axis = *axis;
        if (elevations_deg) path.elevations_deg = *elevations_deg;
        path.points_per_ring = points;
        path.world_R_tcp = orientation_of(quaternion_wxyz);
        path.config = arm_config_of(config, "config");
        request.out = out;
        const BallbarPathFiles files = ballbar_path_files(request);
        py::dict d = json_to_python(ballbar_path_json(files));
        Eigen::MatrixXd joints(static_cast<Eigen::Index>(files.path.points.size()), kJointCount);
        Eigen::VectorXd offsets(joints.rows());
        for (Eigen::Index i = 0; i < joints.rows(); ++i) {
          const BallbarPathPoint& p = files.path.points[static_cast<size_t>(i)];
          joints.row(i) = (p.joints * kRadToDeg).transpose();
          offsets[i] = p.predicted_offset_mm;
        }
        d["joints_deg"] = joints;
        d["predicted_offsets_mm"] = offsets;
        return d;
      },
      py::arg("robot"), py::arg("tool"), py::arg("target"), py::arg("centre_mm"),
      py::arg("length_mm"), py::arg("out"), py::arg("model") = "", py::arg("reading_model") = "",
      py::arg("range_mm") = 1.0, py::arg("axis") = py::none(),
      py::arg("elevations_deg") = py::none(), py::arg("points") = 12,
      py::arg("quaternion_wxyz") = py::none(), py::arg("config") = "front-up-noflip",
      "`robcal ballbar-path`: the path around a taught centre checked (reachable, predicted "
      "readings within the bar's range) and written to `out` (axis: the circle's normal, default "
      "world z; elevations_deg: the rings, default [0]); the CLI's --json document plus "
      "every point's joints (N×6, deg) and predicted reading − length (mm)");
});

}  // namespace
}  // namespace robcal::python
