// Python bindings of compensation (include/robcal/compensate/): calibrated inverse
// kinematics, corrected targets and program filtering. Degrees and mm outside.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "module_registry.hpp"
#include "py_measurements.hpp"
#include "robcal/compensate/corrected_targets.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/programs/program_filter.hpp"
#include "robcal/sim/true_robot.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

/// A calibrated robot and its compensator, kept together (the corrector refers to both).
struct PyCompensator {
  CalibratedRobot robot;
  Compensator comp;
};

PyCompensator make(CalibratedRobot robot, const std::optional<std::string>& tool,
                   const std::optional<double>& payload_mass_kg,
                   const std::optional<Eigen::Vector3d>& payload_cog_mm) {
  if (tool) {
    const Tool t = load_tool(*tool);
    robot.tool.flange_T_tcp = t.flange_T_tcp;
    robot.tool.payload = t.payload;
  }
  if (payload_mass_kg.has_value() != payload_cog_mm.has_value())
    throw py::value_error("give both payload_mass_kg and payload_cog_mm");
  std::optional<PointMass> payload;
  if (payload_mass_kg) {
    if (!(*payload_mass_kg >= 0)) throw py::value_error("payload_mass_kg must be 0 or more");
    payload = PointMass{*payload_mass_kg, *payload_cog_mm};
  }
  PyCompensator out{robot, make_compensator(robot, payload)};
  return out;
}

Pose<double> pose_of(const Eigen::Vector3d& position_mm, const Eigen::Vector4d& quaternion_wxyz) {
  return pose_from_position_quaternion(position_mm, quaternion_wxyz);
}

py::dict pose_dict(const Pose<double>& pose) {
  const Eigen::Quaterniond q = to_quaternion(pose.R);
  py::dict d;
  d["position_mm"] = Eigen::Vector3d(pose.p);
  d["quaternion_wxyz"] = Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
  return d;
}

const bool registered = register_bindings(70, [](py::module_& m) {
  py::class_<PyCompensator>(m, "Compensator",
                            "Calibrated inverse kinematics and corrected targets for one "
                            "calibrated robot, tool and payload (docs/method/10-compensation.md)")
      .def_static(
          "from_model",
          [](const std::string& model, const std::optional<std::string>& tool,
             const std::optional<double>& mass, const std::optional<Eigen::Vector3d>& cog) {
            return make(load_calibrated_robot(model), tool, mass, cog);
          },
          py::arg("model"), py::arg("tool") = py::none(), py::arg("payload_mass_kg") = py::none(),
          py::arg("payload_cog_mm") = py::none(), "From a calibrated model file")
      .def_static(
          "from_truth",
          [](const std::string& truth, const std::optional<std::string>& tool,
             const std::optional<double>& mass, const std::optional<Eigen::Vector3d>& cog) {
            return make(load_truth(truth).robot, tool, mass, cog);
          },
          py::arg("truth"), py::arg("tool") = py::none(), py::arg("payload_mass_kg") = py::none(),
          py::arg("payload_cog_mm") = py::none(), "From a simulation's truth file")
      .def_static(
          "nominal",
          [](const std::string& robot, const std::optional<std::string>& tool) {
            return make(CalibratedRobot::nominal(load_robot(robot), Tool{}), tool, std::nullopt,
                        std::nullopt);
          },
          py::arg("robot"), py::arg("tool") = py::none(),
          "The nominal robot at the world origin (compensation changes nothing)")
      .def(
          "tcp_pose",
          [](const PyCompensator& c, const Vector6d& joints_deg) {
            return pose_dict(calibrated_tcp_pose(c.comp.chain, joints_deg * kDegToRad));
          },
          py::arg("joints_deg"), "TCP pose in the world on the calibrated model")
      .def(
          "tcp_poses",
          [](const PyCompensator& c, const Eigen::MatrixXd& joints_deg) {
            if (joints_deg.cols() != kJointCount)
              throw InputError({"<arrays>", 0, 0, "joints_deg"}, "expected N×6 joints (deg)");
            return pose_arrays(joints_deg.rows(), [&](Eigen::Index r) {
              return calibrated_tcp_pose(c.comp.chain,
                                         Vector6d(joints_deg.row(r).transpose() * kDegToRad));
            });
          },
          py::arg("joints_deg"),
          "tcp_pose over the rows of an N×6 array: {'position_mm': N×3, 'quaternion_wxyz': N×4}")
      .def(
          "solve_batch",
          [](const PyCompensator& c, const Eigen::MatrixXd& positions_mm,
             const Eigen::MatrixXd& quaternions_wxyz, const std::string& config) {
            const auto arm = parse_arm_config(config);
            if (!arm)
              throw InputError({"", 0, 0, "config"}, "unknown configuration '" + config + "'");
            const auto n = positions_mm.rows();
            if (positions_mm.cols() != 3 || quaternions_wxyz.cols() != 4 ||
                quaternions_wxyz.rows() != n)
              throw InputError({"<arrays>", 0, 0, "quaternions_wxyz"},
                               "expected positions_mm N×3 and quaternions_wxyz N×4");
            Eigen::MatrixXd joints(n, kJointCount), nominal(n, 3);
            std::vector<std::string> status;
            std::vector<bool> ok;
            for (Eigen::Index r = 0; r < n; ++r) {
              const CalibratedIkResult result = calibrated_ik(
                  c.comp,
                  pose_of(positions_mm.row(r).transpose(), quaternions_wxyz.row(r).transpose()),
                  *arm, Vector6d::Zero(), IkMethod::Newton);
              status.push_back(to_string(result.status));
              ok.push_back(result.ok());
              joints.row(r).setConstant(NAN);
              nominal.row(r).setConstant(NAN);
              if (!result.ok()) continue;
              joints.row(r) = (result.joints * kRadToDeg).transpose();
              nominal.row(r) = nominal_tcp_pose(c.comp, result.joints).p.transpose();
            }
            py::dict d;
            d["joints_deg"] = joints;
            d["status"] = status;
            d["ok"] = ok;
            d["nominal_position_mm"] = nominal;
            return d;
          },
          py::arg("positions_mm"), py::arg("quaternions_wxyz"), py::arg("config"),
          "solve() over N world TCP poses in one configuration: joints_deg N×6, status, ok, and "
          "the nominal target positions to send (NaN rows where ok is False)")
      .def(
          "nominal_tcp_pose",
          [](const PyCompensator& c, const Vector6d& joints_deg) {
            return pose_dict(nominal_tcp_pose(c.comp, joints_deg * kDegToRad));
          },
          py::arg("joints_deg"), "TCP pose in the base frame on the nominal model")
      .def(
          "config_of",
          [](const PyCompensator& c, const Vector6d& joints_deg) {
            return arm_config(c.comp.model, joints_deg * kDegToRad).label();
          },
          py::arg("joints_deg"), "Arm configuration label of controller joints")
      .def(
          "solve",
          [](const PyCompensator& c, const Eigen::Vector3d& position_mm,
             const Eigen::Vector4d& quaternion_wxyz, const std::string& config,
             const std::optional<Vector6d>& near_deg, const std::string& method) {
            const auto arm = parse_arm_config(config);
            if (!arm) throw py::value_error("unknown configuration '" + config + "'");
            if (method != "newton" && method != "pose-shift")
              throw py::value_error("method must be 'newton' or 'pose-shift'");
            const CalibratedIkResult r =
                calibrated_ik(c.comp, pose_of(position_mm, quaternion_wxyz), *arm,
                              near_deg.value_or(Vector6d::Zero()) * kDegToRad,
                              method == "newton" ? IkMethod::Newton : IkMethod::PoseShift);
            py::dict d;
            d["status"] = to_string(r.status);
            d["ok"] = r.ok();
            d["joints_deg"] = Vector6d(r.joints * kRadToDeg);
            d["iterations"] = r.iterations;
            d["position_error_mm"] = r.position_error_mm;
            d["orientation_error_deg"] = rad2deg(r.orientation_error_rad);
            if (r.ok()) d["nominal_target"] = pose_dict(nominal_tcp_pose(c.comp, r.joints));
            return d;
          },
          py::arg("position_mm"), py::arg("quaternion_wxyz"), py::arg("config"),
          py::arg("near_deg") = py::none(), py::arg("method") = "newton",
          "Joints reaching a world TCP pose on the calibrated model in `config`, and the "
          "nominal target to send; status says why when it cannot")
      .def(
          "compensate_program",
          [](const PyCompensator& c, const std::string& in, const std::string& out, bool joints) {
            const ProgramLanguage language = program_language_from_path(in);
            ProgramFilterOptions options;
            options.joints = joints;
            const auto result = filter_program(read_text_file(in), language, in, options,
                                               make_program_corrector(c.comp, language));
            write_file_atomically(out, result.text);
            py::dict d;
            d["cartesian_points"] = result.cartesian_points;
            d["joint_points"] = result.joint_points;
            return d;
          },
          py::arg("in_path"), py::arg("out_path"), py::arg("joints") = false,
          "Writes a corrected copy of a RAPID/KRL program (only the points change)");

  m.def(
      "read_program_points",
      [](const std::string& text, const std::string& language, bool joints) {
        ProgramFilterOptions options;
        options.joints = joints;
        py::list out;
        for (const ProgramPoint& p : read_program_points(
                 text, program_language_from_name(language, "language"), "<text>", options)) {
          py::dict d = p.is_joint_target ? py::dict() : pose_dict(p.base_T_tcp);
          d["name"] = p.name;
          d["line"] = p.line;
          d["column"] = p.column;
          d["joint_target"] = p.is_joint_target;
          if (p.is_joint_target) d["joints_deg"] = Vector6d(p.joints_deg);
          d["config"] = p.config;
          out.append(d);
        }
        return out;
      },
      py::arg("text"), py::arg("language"), py::arg("joints") = false,
      "Every point of a RAPID ('rapid') or KRL ('krl') program, in file order");
});

}  // namespace
}  // namespace robcal::python
