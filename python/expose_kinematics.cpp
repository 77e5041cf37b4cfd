// Python bindings of the robot library and the kinematics (include/robcal/io/robot_file.hpp,
// include/robcal/kinematics/). Millimetres and degrees in and out, quaternions (w, x, y, z).

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <optional>

#include "module_registry.hpp"
#include "py_measurements.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_catalogue.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/kinematics_workflow.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

Vector6d joints_from_deg(const Eigen::VectorXd& deg, const char* what) {
  if (deg.size() != kJointCount)
    throw py::value_error(std::string(what) + ": expected 6 joint values (deg), got " +
                          std::to_string(deg.size()));
  Vector6d q;
  for (int i = 0; i < kJointCount; ++i) {
    if (!std::isfinite(deg[i])) throw py::value_error(std::string(what) + ": not finite");
    q[i] = deg2rad(deg[i]);
  }
  return q;
}

Eigen::VectorXd joints_to_deg(const Vector6d& q) {
  Eigen::VectorXd deg(kJointCount);
  for (int i = 0; i < kJointCount; ++i) deg[i] = rad2deg(q[i]);
  return deg;
}

const bool registered = register_bindings(10, [](py::module_& m) {
  py::class_<RobotModel>(m, "RobotModel", "An immutable robot description (MDH table, limits)")
      .def_readonly("name", &RobotModel::name)
      .def_readonly("manufacturer", &RobotModel::manufacturer)
      .def_readonly("source", &RobotModel::source)
      .def_property_readonly(
          "joint_limits_deg",
          [](const RobotModel& r) {
            Eigen::MatrixXd limits(kJointCount, 2);
            for (int i = 0; i < kJointCount; ++i)
              limits.row(i) << rad2deg(r.limits[i].lower), rad2deg(r.limits[i].upper);
            return limits;
          },
          "6×2 array of [lower, upper] controller joint limits, deg")
      .def_property_readonly(
          "is_ortho_parallel",
          [](const RobotModel& r) { return analyze_ortho_parallel(r).has_value(); },
          "True when the closed-form IK applies (otherwise ik() is numeric)")
      .def_static("from_file", &load_robot, py::arg("name_or_path"),
                  "A built-in robot by name or a robot file (YAML) by path")
      .def_static(
          "from_dict", [](const py::dict& d) { return parse_robot(dict_as_file(d)); }, py::arg("d"),
          "A robot from a dict with the robot file's fields (errors name the key)")
      .def("to_yaml", &robot_to_yaml, "The robot file's text")
      .def("__repr__", [](const RobotModel& r) {
        return "<RobotModel " + r.name + " (" + r.manufacturer + "), " +
               (analyze_ortho_parallel(r) ? "closed-form IK" : "numeric IK") + ">";
      });

  m.def("builtin_robots", &builtin_robot_names, "Names of the built-in robots");
  m.def(
      "load_robot", [](const std::string& name_or_path) { return load_robot(name_or_path); },
      py::arg("name_or_path"), "A built-in robot by name or a robot file by path");

  m.def(
      "fk",
      [](const RobotModel& robot, const Eigen::VectorXd& joints_deg, bool check_limits) {
        const FkReport r =
            forward_kinematics({robot, joints_from_deg(joints_deg, "fk"), check_limits});
        const Eigen::Quaterniond q = to_quaternion(r.flange.R);
        const auto labels = euler_labels(r.euler);
        py::dict euler;
        for (int i = 0; i < 3; ++i) euler[py::str(labels[static_cast<size_t>(i)])] = r.euler_deg[i];
        py::dict out;
        out["robot"] = r.robot;
        out["position_mm"] = Eigen::Vector3d(r.flange.p);
        out["quaternion_wxyz"] = Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
        out["euler_deg"] = euler;
        return out;
      },
      py::arg("robot"), py::arg("joints_deg"), py::arg("check_limits") = false,
      "`robcal fk`: flange pose of the nominal robot, {'robot', 'position_mm': [x,y,z], "
      "'quaternion_wxyz': [w,x,y,z], 'euler_deg': {label: value}} in the robot's Euler "
      "convention; check_limits refuses joints outside the limits as the CLI does");

  m.def(
      "fk_batch",
      [](const RobotModel& robot, const Eigen::MatrixXd& joints_deg) {
        if (joints_deg.cols() != kJointCount)
          throw InputError({"<arrays>", 0, 0, "joints_deg"}, "expected N×6 joints (deg)");
        return pose_arrays(joints_deg.rows(), [&](Eigen::Index r) {
          return flange_pose(robot, PointMass{}, robot.nominal(),
                             joints_from_deg(joints_deg.row(r).transpose(), "fk_batch"));
        });
      },
      py::arg("robot"), py::arg("joints_deg"),
      "fk over the rows of an N×6 array: {'position_mm': N×3, 'quaternion_wxyz': N×4}");

  m.def(
      "ik",
      [](const RobotModel& robot, const Eigen::Vector3d& position_mm,
         const Eigen::Vector4d& quaternion_wxyz, std::optional<Eigen::VectorXd> seed_deg,
         bool require_solution) {
        IkRequest request{robot, pose_from_position_quaternion(position_mm, quaternion_wxyz),
                          Vector6d::Zero(), require_solution};
        if (seed_deg) request.seed = joints_from_deg(*seed_deg, "ik seed");
        const IkReport result = inverse_kinematics(request);
        // ik_json's document (the CLI's), each solution's joints as an unrounded array.
        py::dict out = json_to_python(ik_json(result));
        py::list solutions = out["solutions"];
        for (size_t k = 0; k < result.ik.solutions.size(); ++k)
          solutions[k]["joints_deg"] = joints_to_deg(result.ik.solutions[k].joints);
        return out;
      },
      py::arg("robot"), py::arg("position_mm"), py::arg("quaternion_wxyz"),
      py::arg("seed_joints_deg") = py::none(), py::arg("require_solution") = false,
      "`robcal ik`: every IK solution of the nominal robot, {'robot', 'status', 'method', "
      "'solutions': [{'joints_deg', 'config', 'wrist_singular'}]}; an unreachable pose gives "
      "status 'unreachable' and no solutions (an InputError with require_solution=True, as the "
      "CLI)");

  m.def(
      "ik_batch",
      [](const RobotModel& robot, const Eigen::MatrixXd& position_mm,
         const Eigen::MatrixXd& quaternion_wxyz, std::optional<Eigen::VectorXd> seed_deg) {
        if (position_mm.cols() != 3 || quaternion_wxyz.cols() != 4 ||
            position_mm.rows() != quaternion_wxyz.rows())
          throw InputError({"<arrays>", 0, 0, "position_mm/quaternion_wxyz"},
                           "expected N×3 positions (mm) and N×4 quaternions (w, x, y, z)");
        std::vector<Pose<double>> poses;
        for (Eigen::Index r = 0; r < position_mm.rows(); ++r)
          poses.push_back(pose_from_position_quaternion(position_mm.row(r).transpose(),
                                                        quaternion_wxyz.row(r).transpose()));
        const IkPath path = inverse_kinematics_path(
            robot, poses, seed_deg ? joints_from_deg(*seed_deg, "ik seed") : Vector6d::Zero());
        Eigen::MatrixXd joints(position_mm.rows(), kJointCount);
        std::vector<std::string> configs, status;
        for (size_t r = 0; r < poses.size(); ++r) {
          const auto& chosen = path.chosen[r];
          joints.row(static_cast<Eigen::Index>(r)) =
              chosen ? Eigen::RowVectorXd(joints_to_deg(chosen->joints).transpose())
                     : Eigen::RowVectorXd::Constant(kJointCount, NAN);
          configs.push_back(chosen ? chosen->config.label() : "");
          status.push_back(to_string(path.status[r]));
        }
        py::dict out;
        out["joints_deg"] = joints;
        out["config"] = configs;
        out["status"] = status;
        return out;
      },
      py::arg("robot"), py::arg("position_mm"), py::arg("quaternion_wxyz"),
      py::arg("seed_joints_deg") = py::none(),
      "ik over the rows of N×3 positions (mm) and N×4 quaternions (w, x, y, z), the inverse of "
      "fk_batch: per pose the solution nearest the previous pose's (the first nearest the seed), "
      "{'joints_deg': N×6 (NaN rows: unreachable or outside the limits), 'config': labels, "
      "'status': per pose}");

  m.def(
      "robot_catalogue", [] { return json_to_python(robot_catalogue_json(robot_catalogue())); },
      "`robcal robots`: [{'name', 'model', 'manufacturer', 'reach_mm'}] of the built-in robots");
  m.def(
      "robot_description",
      [](const RobotModel& robot) { return json_to_python(robot_description_json(robot)); },
      py::arg("robot"),
      "`robcal robot show`: name, manufacturer, source, MDH table (deg, mm), joint limits (deg), "
      "link masses (kg)");
});

}  // namespace
}  // namespace robcal::python
