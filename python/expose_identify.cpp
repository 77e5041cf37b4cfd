// Python bindings of the identification (include/robcal/identify/): calibrate from files or
// from arrays, the calibration result, the calibrated model file. Millimetres and degrees in and
// out; InputError becomes ValueError.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "module_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/identify/cross_validation.hpp"
#include "robcal/identify/identification.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

IdentifyOptions make_options(const std::string& level, const std::vector<std::string>& identify,
                             const std::vector<std::string>& fix, const std::string& loss,
                             uint64_t seed) {
  if (loss != "none" && loss != "huber")
    throw InputError({"", 0, 0, "loss"}, "unknown loss '" + loss + "': expected none or huber");
  IdentifyOptions options;
  options.level = parse_calibration_level(level);
  options.identify = identify;
  options.fix = fix;
  options.huber = loss == "huber";
  options.seed = seed;
  return options;
}

/// Point measurements from arrays: joints (N×6, deg), target names (N), positions (N×3, mm).
MeasurementSet points_from_arrays(const Tool& tool, const Eigen::MatrixXd& joints_deg,
                                  const std::vector<std::string>& targets,
                                  const Eigen::MatrixXd& positions_mm) {
  const auto n = joints_deg.rows();
  if (joints_deg.cols() != kJointCount || positions_mm.cols() != 3 || positions_mm.rows() != n ||
      static_cast<Eigen::Index>(targets.size()) != n)
    throw InputError("expected joints_deg N×6, targets of length N and positions_mm N×3");
  if (!joints_deg.allFinite() || !positions_mm.allFinite())
    throw InputError("joints_deg and positions_mm must be finite");
  MeasurementSet set;
  set.kind = MeasurementKind::Points;
  set.file = "<arrays>";
  for (Eigen::Index r = 0; r < n; ++r) {
    PointMeasurement m;
    m.config = std::to_string(r + 1);
    m.target = tool.target_index(targets[static_cast<size_t>(r)]);
    if (m.target < 0)
      throw InputError("row " + std::to_string(r + 1) + ": the tool has no target '" +
                       targets[static_cast<size_t>(r)] + "'");
    for (int j = 0; j < kJointCount; ++j) m.joints[j] = deg2rad(joints_deg(r, j));
    m.position_mm = positions_mm.row(r).transpose();
    set.points.push_back(m);
  }
  return set;
}

const bool registered = register_bindings(30, [](py::module_& m) {
  py::class_<SolverStatus>(m, "SolverStatus", "How the least-squares solver ended")
      .def_readonly("converged", &SolverStatus::converged)
      .def_readonly("iterations", &SolverStatus::iterations)
      .def_readonly("message", &SolverStatus::message)
      .def_readonly("initial_rms_mm", &SolverStatus::initial_rms_mm)
      .def_readonly("final_rms_mm", &SolverStatus::final_rms_mm);

  py::class_<UnknownEstimate>(m, "UnknownEstimate", "One parameter: value ± std (mm, deg)")
      .def_readonly("name", &UnknownEstimate::name)
      .def_readonly("unit", &UnknownEstimate::unit)
      .def_readonly("nominal", &UnknownEstimate::nominal)
      .def_readonly("value", &UnknownEstimate::value)
      .def_readonly("std", &UnknownEstimate::std_dev)
      .def_property_readonly("status",
                             [](const UnknownEstimate& u) { return status_name(u.status); })
      .def_readonly("reason", &UnknownEstimate::reason)
      .def("__repr__", [](const UnknownEstimate& u) {
        return "<" + u.name + " = " + std::to_string(u.value) + " " + u.unit + " (" +
               status_name(u.status) + ")>";
      });

  py::class_<PredictedAccuracy>(m, "PredictedAccuracy",
                                "Cramér–Rao predicted position error (mm) over configurations")
      .def_readonly("configurations", &PredictedAccuracy::configurations)
      .def_readonly("mean_mm", &PredictedAccuracy::mean_mm)
      .def_readonly("rms_mm", &PredictedAccuracy::rms_mm)
      .def_readonly("max_mm", &PredictedAccuracy::max_mm)
      .def_readonly("measurement_sigma_mm", &PredictedAccuracy::measurement_sigma_mm)
      .def_readonly("mean_vs_measurements_mm", &PredictedAccuracy::mean_vs_measurements_mm)
      .def_readonly("rms_vs_measurements_mm", &PredictedAccuracy::rms_vs_measurements_mm);

  py::class_<CalibratedRobot>(m, "CalibratedRobot", "A robot with identified parameters")
      .def_readonly("model", &CalibratedRobot::model)
      .def_readonly("level", &CalibratedRobot::level)
      .def_readonly("base_fitted", &CalibratedRobot::base_fitted)
      .def_property_readonly(
          "parameters",
          [](const CalibratedRobot& r) {
            py::dict out;
            for (int i = 0; i < kParameterCount; ++i)
              out[py::str(parameter_table()[i].name)] =
                  r.params[i] * parameter_table()[i].to_external();
            return out;
          },
          "{name: value} in mm, deg, rad/N·mm")
      .def_property_readonly(
          "targets",
          [](const CalibratedRobot& r) {
            py::dict out;
            for (const Target& t : r.tool.targets) out[py::str(t.name)] = t.position_mm;
            return out;
          },
          "{target name: [x, y, z]} in the flange frame, mm (identified ones filled in)")
      .def(
          "position",
          [](const CalibratedRobot& r, const Eigen::VectorXd& joints_deg,
             const Eigen::Vector3d& point_flange_mm) {
            if (joints_deg.size() != kJointCount) throw py::value_error("expected 6 joints (deg)");
            Vector6d q;
            for (int i = 0; i < kJointCount; ++i) q[i] = deg2rad(joints_deg[i]);
            return Eigen::Vector3d(flange_pose(r.model, r.tool.payload, r.params, q) *
                                   point_flange_mm);
          },
          py::arg("joints_deg"), py::arg("point_flange_mm"),
          "World position (mm) of a flange-frame point at controller joints (deg)")
      .def("to_yaml", [](const CalibratedRobot& r) { return calibrated_robot_to_yaml(r); });

  py::class_<IdentificationResult>(m, "IdentificationResult", "A calibration and its statistics")
      .def_readonly("robot", &IdentificationResult::robot)
      .def_readonly("status", &IdentificationResult::status)
      .def_readonly("parameters", &IdentificationResult::unknowns,
                    "Every unknown (model parameters, then target coordinates, ballbar centre)")
      .def_readonly("residual_count", &IdentificationResult::residual_count)
      .def_readonly("identified_count", &IdentificationResult::identified_count)
      .def_readonly("sigma_mm", &IdentificationResult::sigma_mm)
      .def_readonly("rms_mm", &IdentificationResult::rms_mm)
      .def_readonly("max_mm", &IdentificationResult::max_mm)
      .def_readonly("condition_number", &IdentificationResult::condition_number)
      .def_readonly("predicted", &IdentificationResult::predicted)
      .def_property_readonly("correlations",
                             [](const IdentificationResult& r) {
                               py::list out;
                               for (const auto& c : r.correlations)
                                 out.append(py::make_tuple(c.first, c.second, c.rho));
                               return out;
                             })
      .def_property_readonly(
          "outliers",
          [](const IdentificationResult& r) {
            py::list out;
            for (const auto& o : r.outliers)
              out.append(py::make_tuple(o.config, o.line, o.residual_mm));
            return out;
          },
          "[(config, line, residual_mm)] beyond 4 robust σ")
      .def_property_readonly(
          "by_target",
          [](const IdentificationResult& r) {
            py::dict out;
            for (const auto& t : r.by_target)
              out[py::str(t.target)] = py::make_tuple(t.rows, t.rms_mm, t.max_mm);
            return out;
          },
          "{target: (rows, rms_mm, max_mm)}")
      .def(
          "save",
          [](const IdentificationResult& r, const std::string& path) {
            [&] {
              write_file_atomically(path, calibrated_robot_to_yaml(r.robot, statistics_yaml(r)));
              return 0;
            }();
          },
          py::arg("path"), "Writes the calibrated model file (YAML), whole or not at all");

  m.def(
      "calibrate",
      [](const std::string& robot, const std::string& tool, const std::string& measurements,
         const std::string& level, const std::vector<std::string>& identify,
         const std::vector<std::string>& fix, const std::string& loss, uint64_t seed) {
        return [&] {
          const RobotModel model = load_robot(robot);
          const Tool t = load_tool(tool);
          const MeasurementFile file = read_measurements_csv(measurements, t);
          return calibrate(model, t, file.measurements,
                           make_options(level, identify, fix, loss, seed));
        }();
      },
      py::arg("robot"), py::arg("tool"), py::arg("measurements"), py::arg("level") = "full",
      py::arg("identify") = std::vector<std::string>{}, py::arg("fix") = std::vector<std::string>{},
      py::arg("loss") = "none", py::arg("seed") = 1,
      "Calibrate from files: robot name or file, tool file, measurement CSV");

  m.def(
      "calibrate_points",
      [](const std::string& robot, const std::string& tool, const Eigen::MatrixXd& joints_deg,
         const std::vector<std::string>& targets, const Eigen::MatrixXd& positions_mm,
         const std::string& level, const std::vector<std::string>& identify,
         const std::vector<std::string>& fix, const std::string& loss, uint64_t seed) {
        return [&] {
          const RobotModel model = load_robot(robot);
          const Tool t = load_tool(tool);
          return calibrate(model, t, points_from_arrays(t, joints_deg, targets, positions_mm),
                           make_options(level, identify, fix, loss, seed));
        }();
      },
      py::arg("robot"), py::arg("tool"), py::arg("joints_deg"), py::arg("targets"),
      py::arg("positions_mm"), py::arg("level") = "full",
      py::arg("identify") = std::vector<std::string>{}, py::arg("fix") = std::vector<std::string>{},
      py::arg("loss") = "none", py::arg("seed") = 1,
      "Calibrate from arrays: joints N×6 (deg), target names (N), measured positions N×3 (mm)");

  m.def(
      "cross_validate",
      [](const std::string& robot, const std::string& tool, const std::string& measurements,
         int folds, const std::string& level, uint64_t seed) {
        return [&] {
          const RobotModel model = load_robot(robot);
          const Tool t = load_tool(tool);
          const MeasurementFile file = read_measurements_csv(measurements, t);
          const CrossValidation cv = cross_validate(
              model, t, file.measurements, make_options(level, {}, {}, "none", seed), folds, seed);
          py::dict out;
          out["folds"] = cv.folds;
          out["errors_mm"] = cv.errors_mm;
          out["mean_mm"] = cv.mean_mm;
          out["std_mm"] = cv.std_mm;
          out["max_mm"] = cv.max_mm;
          return out;
        }();
      },
      py::arg("robot"), py::arg("tool"), py::arg("measurements"), py::arg("folds"),
      py::arg("level") = "full", py::arg("seed") = 1,
      "K-fold cross-validation: held-out position error per row and its statistics (mm)");

  m.def(
      "load_calibrated_robot",
      [](const std::string& path) { return [&] { return load_calibrated_robot(path); }(); },
      py::arg("path"), "Loads a calibrated model file written by calibrate");
});

}  // namespace
}  // namespace robcal::python
