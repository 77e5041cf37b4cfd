// Python binding of ISO 9283 (include/robcal/validate/iso9283.hpp): the test cube, its poses,
// the cycles (and the multi-directional test's approaches), and the analysis of measured cycles;
// the same results and JSON as `robcal iso9283 plan|analyse`.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "module_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/report/report.hpp"
#include "robcal/validate/iso9283.hpp"

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

const bool registered = register_bindings(72, [](py::module_& m) {
  m.def(
      "iso9283_plan",
      [](const CalibratedRobot& robot, const Eigen::Vector3d& region_min_mm,
         const Eigen::Vector3d& region_max_mm,
         const std::optional<Eigen::Vector4d>& quaternion_wxyz, const std::string& config,
         int cycles, double vap_approach_mm) {
        const std::optional<ArmConfig> arm = parse_arm_config(config);
        if (!arm) throw InputError({"", 0, 0, "config"}, "unknown configuration '" + config + "'");
        Iso9283PlanRequest request;
        request.robot = robot;
        request.region_min_mm = region_min_mm;
        request.region_max_mm = region_max_mm;
        request.world_R_tcp =
            pose_from_position_quaternion(Eigen::Vector3d::Zero(),
                                          quaternion_wxyz.value_or(Eigen::Vector4d(0, 0, 1, 0)))
                .R;
        request.config = *arm;
        request.cycles = cycles;
        request.vap_approach_mm = vap_approach_mm;
        return plan_dict(iso9283_plan(request), *arm);
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
        return json_to_python(
            iso9283_json(iso9283_analyse(read_iso9283_request(poses, measurements, min_cycles))));
      },
      py::arg("poses"), py::arg("measurements"), py::arg("min_cycles") = kIso9283Cycles,
      "AP, RP (position, orientation), vAP, AD, RD of measured cycles (`robcal iso9283 "
      "analyse`): the commanded poses' pose list and the measurements CSV; the same JSON as "
      "the CLI's --json");
});

}  // namespace
}  // namespace robcal::python
