// Python bindings of compensation (include/robcal/compensate/): calibrated inverse
// kinematics, corrected targets (compensate_targets) and program filtering
// (compensate_program). Degrees and mm outside.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "module_registry.hpp"
#include "py_compensator.hpp"
#include "py_measurements.hpp"
#include "robcal/compensate/compensate_targets.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/programs/program_compensation.hpp"
#include "robcal/sim/true_robot.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

/// The conditions the targets are reached under (`robcal compensate --approach, --payload,
/// --temperature-c, --warmup-time-s, --warm`), checked by prepare_compensation.
struct ReachOptions {
  std::string approach = "++++++";
  std::optional<std::string> payload;
  std::optional<double> temperature_c, warmup_time_s;
  bool warm = false;
};

PyCompensator make(CalibratedRobot robot, const std::string& source,
                   const std::optional<std::string>& tool,
                   const std::optional<double>& payload_mass_kg,
                   const std::optional<Eigen::Vector3d>& payload_cog_mm,
                   const ReachOptions& reach = {}) {
  CompensationSetup setup;
  setup.robot = std::move(robot);
  setup.model_file = source;
  if (tool) setup.tool = load_tool(*tool);
  if (payload_mass_kg.has_value() != payload_cog_mm.has_value())
    throw InputError({"", 0, 0, payload_mass_kg ? "payload_cog_mm" : "payload_mass_kg"},
                     "give both payload_mass_kg and payload_cog_mm");
  if (payload_mass_kg) setup.payload = PointMass{*payload_mass_kg, *payload_cog_mm};
  setup.approach = parse_approach(reach.approach, {"", 0, 0, "approach"});
  setup.payload_name = reach.payload.value_or("");
  setup.temperature_c = reach.temperature_c;
  setup.warmup_time_s = reach.warmup_time_s;
  setup.warm = reach.warm;
  Compensation c = prepare_compensation(setup);
  return PyCompensator{std::move(setup), std::move(c)};
}

/// from_model / from_truth: a calibrated robot from `path` read by `load`, with the CLI's tool,
/// payload and reach options.
template <typename Load>
auto from_file(Load load) {
  return [load](const std::string& path, const std::optional<std::string>& tool,
                const std::optional<double>& mass, const std::optional<Eigen::Vector3d>& cog,
                const std::string& approach, const std::optional<std::string>& payload,
                const std::optional<double>& temperature_c,
                const std::optional<double>& warmup_time_s, bool warm) {
    return make(load(path), path, tool, mass, cog,
                {approach, payload, temperature_c, warmup_time_s, warm});
  };
}

Pose<double> pose_of(const Eigen::Vector3d& position_mm, const Eigen::Vector4d& quaternion_wxyz) {
  return pose_from_position_quaternion(position_mm, quaternion_wxyz);
}

const bool registered = register_bindings(70, [](py::module_& m) {
  py::class_<PyCompensator>(m, "Compensator",
                            "Calibrated inverse kinematics and corrected targets for one "
                            "calibrated robot, tool and payload (docs/method/10-compensation.md)")
      .def_static(
          "from_model", from_file([](const std::string& p) { return load_calibrated_robot(p); }),
          py::arg("model"), py::arg("tool") = py::none(), py::arg("payload_mass_kg") = py::none(),
          py::arg("payload_cog_mm") = py::none(), py::arg("approach") = "++++++",
          py::arg("payload") = py::none(), py::arg("temperature_c") = py::none(),
          py::arg("warmup_time_s") = py::none(), py::arg("warm") = false,
          "From a calibrated model file, for targets reached under the CLI's conditions: "
          "approach (each joint's side, '+-++++'), payload (a name of the tool's "
          "payloads), temperature_c, warmup_time_s (how long the arm has worked) or warm "
          "(fully warm); a targets file's rows may give their own")
      .def_static("from_truth", from_file([](const std::string& p) { return load_truth(p).robot; }),
                  py::arg("truth"), py::arg("tool") = py::none(),
                  py::arg("payload_mass_kg") = py::none(), py::arg("payload_cog_mm") = py::none(),
                  py::arg("approach") = "++++++", py::arg("payload") = py::none(),
                  py::arg("temperature_c") = py::none(), py::arg("warmup_time_s") = py::none(),
                  py::arg("warm") = false,
                  "From a simulation's truth file, with from_model's conditions")
      .def_static(
          "nominal",
          [](const std::string& robot, const std::optional<std::string>& tool) {
            return make(CalibratedRobot::nominal(load_robot(robot), Tool{}), robot, tool,
                        std::nullopt, std::nullopt);
          },
          py::arg("robot"), py::arg("tool") = py::none(),
          "The nominal robot at the world origin (compensation changes nothing)")
      .def(
          "tcp_pose",
          [](const PyCompensator& c, const Vector6d& joints_deg) {
            return pose_dict(calibrated_tcp_pose(c.c.comp.chain, joints_deg * kDegToRad));
          },
          py::arg("joints_deg"), "TCP pose in the world on the calibrated model")
      .def(
          "tcp_poses",
          [](const PyCompensator& c, const Eigen::MatrixXd& joints_deg) {
            if (joints_deg.cols() != kJointCount)
              throw InputError({"<arrays>", 0, 0, "joints_deg"}, "expected N×6 joints (deg)");
            return pose_arrays(joints_deg.rows(), [&](Eigen::Index r) {
              return calibrated_tcp_pose(c.c.comp.chain,
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
                  c.c.comp,
                  pose_of(positions_mm.row(r).transpose(), quaternions_wxyz.row(r).transpose()),
                  *arm, Vector6d::Zero(), IkMethod::Newton);
              status.push_back(to_string(result.status));
              ok.push_back(result.ok());
              joints.row(r).setConstant(NAN);
              nominal.row(r).setConstant(NAN);
              if (!result.ok()) continue;
              joints.row(r) = (result.joints * kRadToDeg).transpose();
              nominal.row(r) = nominal_tcp_pose(c.c.comp, result.joints).p.transpose();
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
            return pose_dict(nominal_tcp_pose(c.c.comp, joints_deg * kDegToRad));
          },
          py::arg("joints_deg"), "TCP pose in the base frame on the nominal model")
      .def(
          "config_of",
          [](const PyCompensator& c, const Vector6d& joints_deg) {
            return arm_config(c.c.comp.model, joints_deg * kDegToRad).label();
          },
          py::arg("joints_deg"), "Arm configuration label of controller joints")
      .def(
          "solve",
          [](const PyCompensator& c, const Eigen::Vector3d& position_mm,
             const Eigen::Vector4d& quaternion_wxyz, const std::string& config,
             const std::optional<Vector6d>& near_deg, const std::string& method) {
            const auto arm = parse_arm_config(config);
            if (!arm) throw py::value_error("unknown configuration '" + config + "'");
            const CalibratedIkResult r =
                calibrated_ik(c.c.comp, pose_of(position_mm, quaternion_wxyz), *arm,
                              near_deg.value_or(Vector6d::Zero()) * kDegToRad,
                              ik_method_from_name(method, "method"));
            py::dict d;
            d["status"] = to_string(r.status);
            d["ok"] = r.ok();
            d["joints_deg"] = Vector6d(r.joints * kRadToDeg);
            d["iterations"] = r.iterations;
            d["position_error_mm"] = r.position_error_mm;
            d["orientation_error_deg"] = rad2deg(r.orientation_error_rad);
            if (r.ok()) d["nominal_target"] = pose_dict(nominal_tcp_pose(c.c.comp, r.joints));
            return d;
          },
          py::arg("position_mm"), py::arg("quaternion_wxyz"), py::arg("config"),
          py::arg("near_deg") = py::none(), py::arg("method") = "newton",
          "Joints reaching a world TCP pose on the calibrated model in `config`, and the "
          "nominal target to send; status says why when it cannot")
      .def(
          "compensate_program",
          [](const PyCompensator& c, const std::string& in, const std::string& out, bool joints,
             bool keep_going, const std::optional<std::string>& frames,
             const std::optional<std::string>& confidence_out,
             const std::optional<Vector6d>& pulses_per_degree, bool approach_from_motion) {
            ProgramCompensationRequest request;
            request.setup = c.setup;
            request.approach_from_motion = approach_from_motion;
            request.in = in;
            request.out = out;
            request.frames_file = frames.value_or("");
            request.confidence_out = confidence_out.value_or("");
            request.options.joints = joints;
            request.options.keep_going = keep_going;
            if (pulses_per_degree)
              for (int j = 0; j < kJointCount; ++j)
                request.options.pulses_per_degree[static_cast<size_t>(j)] = (*pulses_per_degree)[j];
            return json_to_python(nlohmann::json(compensate_program(request)));
          },
          py::arg("in_path"), py::arg("out_path"), py::arg("joints") = false,
          py::arg("keep_going") = false, py::arg("frames") = py::none(),
          py::arg("confidence_out") = py::none(), py::arg("pulses_per_degree") = py::none(),
          py::arg("approach_from_motion") = false,
          "Writes a corrected copy of a robot program (only the points change), as `robcal "
          "compensate-program` (approach_from_motion: `--approach motion`); returns its JSON "
          "summary")
      .def(
          "compensate_targets",
          [](const PyCompensator& c, const std::string& targets, const std::string& method,
             const std::optional<std::string>& check_truth, const std::optional<std::string>& out) {
            CompensateTargetsRequest request;
            request.setup = c.setup;
            request.targets = read_pose_list(targets);
            request.targets_file = targets;
            request.method = ik_method_from_name(method, "method");
            if (check_truth) request.truth = load_truth(*check_truth);
            request.out = out.value_or("");
            const CompensateTargetsResult r = compensate_targets(request);
            py::dict d = json_to_python(nlohmann::json(r));
            Eigen::MatrixXd joints(static_cast<Eigen::Index>(r.rows.size()), kJointCount);
            Eigen::MatrixXd nominal(static_cast<Eigen::Index>(r.rows.size()), 3);
            Eigen::MatrixXd approach(static_cast<Eigen::Index>(r.rows.size()), kJointCount);
            Eigen::VectorXd temperature(static_cast<Eigen::Index>(r.rows.size()));
            Eigen::VectorXd warmup_time(static_cast<Eigen::Index>(r.rows.size()));
            std::vector<std::string> names, payloads;
            for (size_t i = 0; i < r.rows.size(); ++i) {
              const auto row = static_cast<Eigen::Index>(i);
              const ReachCondition& condition = r.rows[i].condition;
              joints.row(row) = (r.rows[i].ik.joints * kRadToDeg).transpose();
              nominal.row(row) = r.rows[i].base_T_tcp_nominal.p.transpose();
              names.push_back(r.rows[i].name);
              approach.row(row) = condition.approach.transpose();
              temperature[row] =
                  c.c.robot.model.reference_temperature_c + condition.temperature_rise_k;
              warmup_time[row] = condition.warmup_time_s.value_or(NAN);
              payloads.push_back(condition.payload_name);
            }
            d["names"] = names;
            d["approach"] = approach;
            d["temperature_c"] = temperature;
            d["warmup_time_s"] = warmup_time;
            d["payloads"] = payloads;
            d["joints_deg"] = joints;
            d["nominal_position_mm"] = nominal;
            d["csv"] = r.csv;
            return d;
          },
          py::arg("targets"), py::arg("method") = "newton", py::arg("check_truth") = py::none(),
          py::arg("out") = py::none(),
          "Corrected targets for a pose-list file of wanted world poses, each under its row's "
          "approach, temperature, warm-up time and payload (the compensator's where a row gives "
          "none), as `robcal compensate`: its JSON summary (conditions: how many distinct) plus "
          "names, joints_deg N×6, nominal_position_mm N×3, each row's condition (approach N×6 of "
          "+1 below, -1 above, 0 unknown; temperature_c N; warmup_time_s N, inf fully warm, NaN "
          "cold; payloads N names, '' for the tool's own or one given by mass) and the CSV text");
});

}  // namespace
}  // namespace robcal::python
