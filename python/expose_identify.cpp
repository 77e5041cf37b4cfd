// Python bindings of the identification (include/robcal/identify/): calibrate from files or
// from arrays, the calibration result, the calibrated model file. Millimetres and degrees in and
// out; InputError becomes ValueError.

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "module_registry.hpp"
#include "py_measurements.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/identify/calibrate_workflow.hpp"
#include "robcal/identify/calibrated_robot_file.hpp"
#include "robcal/identify/calibration_output.hpp"
#include "robcal/identify/cross_validation.hpp"
#include "robcal/identify/fit_error_json.hpp"
#include "robcal/identify/model_exchange.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

/// The identification options every calibrate variant takes, checked by the library
/// (calibrate_files) or here with the same messages for the array variants.
CalibrationRequest make_request(const std::string& level, const std::vector<std::string>& identify,
                                const std::vector<std::string>& fix, const std::string& loss,
                                uint64_t seed, double sigma_mm, int kfold,
                                double orientation_weight_mm, bool keep_near_dependent,
                                std::optional<double> warmup_tau_s) {
  CalibrationRequest request;
  IdentifyOptions& options = request.options;
  options.level = parse_calibration_level(level);
  options.identify = identify;
  options.fix = fix;
  options.seed = seed;
  options.instrument_sigma_mm = sigma_mm;
  options.orientation_weight_mm = orientation_weight_mm;
  options.resolve_near_dependencies = !keep_near_dependent;
  options.warmup_time_constant_s = warmup_tau_s;
  request.kfold = kfold;
  options = checked_options(options, loss);
  return request;
}

/// A cross-validation's held-out errors (mm) and their statistics, pooled and per fold: the
/// library's serializers (fit_error_json.hpp) at full precision, with the errors themselves.
py::dict cross_validation_dict(const CrossValidation& cv) {
  auto out = json_to_python(held_out_error_json(cv)).cast<py::dict>();
  out["folds"] = cv.folds;
  out["seed"] = cv.seed;
  out["user_folds"] = cv.user_folds;
  out["errors_mm"] = cv.errors_mm;
  py::list per_fold;
  for (const FoldErrors& f : cv.per_fold) per_fold.append(json_to_python(fold_errors_json(f)));
  out["per_fold"] = per_fold;
  return out;
}

/// Factor from the internal unit of unknown `i` to its external one (parameters: mm or deg or
/// rad/N·mm; the unknowns after them are coordinates, mm).
double to_external(int i) {
  return i < kParameterCount ? parameter_table()[static_cast<size_t>(i)].to_external() : 1.0;
}

/// `robcal model import|export` from Python: the file's text written to `out` when given, the
/// CLI's JSON as a dict with the text under `key`.
py::object written_model(const std::string& out, const std::string& text,
                         const nlohmann::json& report, const char* key) {
  if (!out.empty()) write_file_atomically(out, text);
  py::object d = json_to_python(report);
  d[key] = text;
  return d;
}

const bool registered = register_bindings(30, [](py::module_& m) {
  m.def(
      "model_import",
      [](const std::string& out, const std::string& urdf, const std::string& tip,
         const std::string& format, const std::string& calibration, const std::string& robot) {
        const ModelImportRequest request{urdf, tip, format, calibration, robot};
        const ModelImportResult r = import_model(request);
        return written_model(out, r.yaml, model_import_json(request, r, out), "yaml");
      },
      py::arg("out") = "", py::arg("urdf") = "", py::arg("tip") = "", py::arg("format") = "urdf",
      py::arg("calibration") = "", py::arg("robot") = "",
      "A URDF (format 'urdf') or a UR calibration.conf on its nominal robot (format "
      "'ur-calibration') as a robot or nominal model file (`robcal model import`): the CLI's "
      "JSON as a dict plus yaml (the file's text, written to `out` when given)");
  m.def(
      "model_export",
      [](const std::string& out, const std::string& robot, const std::string& model,
         const std::string& format, uint64_t seed) {
        const ModelExportRequest request{robot, model, format, seed};
        const ModelExportResult r = export_model(request);
        return written_model(out, r.text, model_export_json(request, r, out), "text");
      },
      py::arg("out") = "", py::arg("robot") = "", py::arg("model") = "", py::arg("format") = "urdf",
      py::arg("seed") = 1,
      "A robot (`robot`) or calibrated model file (`model`) as URDF, UR calibration.conf deltas "
      "or its MDH table with σ (format 'urdf', 'ur-calibration', 'mdh-csv'; `robcal model "
      "export`): the CLI's JSON as a dict (what the format leaves out and its cost at the TCP) "
      "plus text (written to `out` when given)");
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

  py::class_<NoiseTest>(m, "NoiseTest",
                        "Are the residuals the instrument's noise? RSS/σ² against χ²(m − n)")
      .def_readonly("tested", &NoiseTest::tested, "False without a stated instrument σ")
      .def_readonly("instrument_sigma_mm", &NoiseTest::instrument_sigma_mm)
      .def_readonly("chi_square", &NoiseTest::chi_square)
      .def_readonly("dof", &NoiseTest::dof)
      .def_readonly("p_value", &NoiseTest::p_value)
      .def_readonly("consistent", &NoiseTest::consistent,
                    "False when the residuals exceed what the instrument's σ explains (misfit)");

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
      .def(
          "positions",
          [](const CalibratedRobot& r, const Eigen::MatrixXd& joints_deg,
             const Eigen::Vector3d& point_flange_mm) {
            if (joints_deg.cols() != kJointCount)
              throw InputError({"<arrays>", 0, 0, "joints_deg"}, "expected N×6 joints (deg)");
            Eigen::MatrixXd out(joints_deg.rows(), 3);
            for (Eigen::Index row = 0; row < joints_deg.rows(); ++row) {
              Vector6d q;
              for (int i = 0; i < kJointCount; ++i) q[i] = deg2rad(joints_deg(row, i));
              out.row(row) =
                  (flange_pose(r.model, r.tool.payload, r.params, q) * point_flange_mm).transpose();
            }
            return out;
          },
          py::arg("joints_deg"), py::arg("point_flange_mm"),
          "position() over the rows of an N×6 joints array (deg): N×3 world positions (mm)")
      .def_static("from_file", &load_calibrated_robot, py::arg("path"),
                  "Loads a calibrated model file written by calibrate")
      .def_static(
          "from_dict",
          [](const py::dict& d) {
            return parse_calibrated_robot(
                py::module_::import("json").attr("dumps")(d).cast<std::string>(), "<dict>");
          },
          py::arg("d"),
          "A calibrated model from a dict with the calibrated model file's fields (errors name "
          "the key)")
      .def_static(
          "nominal",
          [](const RobotModel& model, const std::optional<Tool>& tool) {
            return CalibratedRobot::nominal(model, tool.value_or(Tool{}));
          },
          py::arg("model"), py::arg("tool") = py::none(),
          "The nominal robot as a model with no world frame (validate with fit_base=True)")
      .def(
          "to_yaml", [](const CalibratedRobot& r) { return calibrated_robot_to_yaml(r); },
          "The calibrated model file's text")
      .def("__repr__", [](const CalibratedRobot& r) {
        return "<CalibratedRobot " + r.model.name + ", level " + r.level +
               (r.base_fitted ? ", world frame fitted>" : ", no world frame>");
      });

  py::class_<IdentificationResult>(m, "IdentificationResult", "A calibration and its statistics")
      .def_readonly("robot", &IdentificationResult::robot)
      .def_readonly("status", &IdentificationResult::status)
      .def_readonly("parameters", &IdentificationResult::unknowns,
                    "Every unknown (model parameters, then target coordinates, ballbar centre)")
      .def_readonly("residual_count", &IdentificationResult::residual_count)
      .def_readonly("identified_count", &IdentificationResult::identified_count)
      .def_readonly("warnings", &IdentificationResult::warnings,
                    "Found before fitting: dropped, near-dependent or unloaded parameters, joints "
                    "outside limits, poses without a tcp")
      .def_readonly("sigma_mm", &IdentificationResult::sigma_mm)
      .def_readonly("mean_mm", &IdentificationResult::mean_mm)
      .def_readonly("rms_mm", &IdentificationResult::rms_mm)
      .def_readonly("max_mm", &IdentificationResult::max_mm)
      .def_readonly("start_mean_mm", &IdentificationResult::start_mean_mm)
      .def_readonly("start_rms_mm", &IdentificationResult::start_rms_mm)
      .def_readonly("start_max_mm", &IdentificationResult::start_max_mm)
      .def_readonly("noise_test", &IdentificationResult::noise_test)
      .def_property_readonly(
          "residuals",
          [](const IdentificationResult& r) {
            return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(
                r.row_errors_mm.data(), static_cast<Eigen::Index>(r.row_errors_mm.size())));
          },
          "Residual of each measurement row at the solution (mm; the 3D position error, the "
          "TCP's for poses, |length error| for distances): mean_mm, rms_mm, max_mm are its")
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
      .def_property_readonly(
          "parameter_table",
          [](const IdentificationResult& r) {
            const auto n = static_cast<Eigen::Index>(r.unknowns.size());
            std::vector<std::string> names, units, status;
            Eigen::VectorXd nominal(n), value(n), std_dev(n);
            for (Eigen::Index i = 0; i < n; ++i) {
              const UnknownEstimate& u = r.unknowns[static_cast<size_t>(i)];
              names.push_back(u.name);
              units.push_back(u.unit);
              status.push_back(status_name(u.status));
              nominal[i] = u.nominal;
              value[i] = u.value;
              std_dev[i] = u.std_dev;
            }
            py::dict out;
            out["name"] = names;
            out["unit"] = units;
            out["status"] = status;
            out["nominal"] = nominal;
            out["value"] = value;
            out["std"] = std_dev;
            return out;
          },
          "Every unknown as columns: name, unit, status (lists), nominal, value, std (arrays, "
          "external units); `pandas.DataFrame(result.parameter_table)` makes a table of it")
      .def_property_readonly(
          "identified_names",
          [](const IdentificationResult& r) {
            std::vector<std::string> out;
            for (const int i : r.free) out.push_back(r.unknowns[static_cast<size_t>(i)].name);
            return out;
          },
          "Names of the identified unknowns: the rows and columns of `covariance`")
      .def_property_readonly(
          "covariance",
          [](const IdentificationResult& r) {
            Eigen::MatrixXd c = r.covariance;
            for (Eigen::Index a = 0; a < c.rows(); ++a)
              for (Eigen::Index b = 0; b < c.cols(); ++b)
                c(a, b) *= to_external(r.free[static_cast<size_t>(a)]) *
                           to_external(r.free[static_cast<size_t>(b)]);
            return c;
          },
          "Covariance of the identified unknowns (order of identified_names), external units "
          "(mm, deg, rad/N·mm)")
      .def(
          "_repr_html_",
          [](const IdentificationResult& r) {
            std::string html = fmt::format(
                "<p><b>{}</b>: {} of {} unknowns identified from {} residuals, rms {:.4f} mm, "
                "{}</p><table><tr><th>parameter</th><th>value</th><th>± std</th><th>unit</th>"
                "<th>status</th></tr>",
                r.robot.model.name, r.identified_count, r.unknowns.size(), r.residual_count,
                r.rms_mm, r.status.converged ? "converged" : "<b>not converged</b>");
            for (const UnknownEstimate& u : r.unknowns)
              html += fmt::format(
                  "<tr><td>{}</td><td>{:.6g}</td><td>{:.3g}</td><td>{}</td><td>{}</td></tr>",
                  u.name, u.value, u.std_dev, u.unit,
                  u.reason.empty() ? status_name(u.status)
                                   : std::string(status_name(u.status)) + ": " + u.reason);
            return html + "</table>";
          },
          "The result as an HTML table (Jupyter shows it)")
      .def("__repr__", [](const IdentificationResult& r) {
        return "<IdentificationResult " + r.robot.model.name + ": " +
               std::to_string(r.identified_count) + " identified, rms " + std::to_string(r.rms_mm) +
               " mm, " + (r.status.converged ? "converged" : "NOT converged") + ">";
      });

  py::class_<CalibrationRun>(
      m, "Calibration",
      "A calibration run: the identification (`result`; its attributes are also this "
      "object's), the warnings, the cross-validation and the problems that keep the model from "
      "being saved")
      .def_readonly("result", &CalibrationRun::result)
      .def_readonly("warnings", &CalibrationRun::warnings,
                    "The measurement file's warnings, then the fit's")
      .def_readonly("problems", &CalibrationRun::problems,
                    "Why the model must not be trusted (each says what to check); empty when "
                    "plausible")
      .def_property_readonly(
          "cross_validation",
          [](const CalibrationRun& run) -> py::object {
            if (!run.cross_validation) return py::none();
            py::dict out = cross_validation_dict(*run.cross_validation);
            out["run_because_of_misfit"] = run.cross_validation_for_misfit;
            return out;
          },
          "K-fold held-out errors (asked for with kfold/folds, or run because the noise test "
          "failed): dict folds, seed, errors_mm, mean_mm, std_mm, max_mm, per_fold; None when "
          "not run")
      .def(
          "save",
          [](const CalibrationRun& run, const std::string& path, bool force) {
            if (const auto refusal = write_calibration(run, path, force, nullptr))
              throw InputError({path, 0, 0, "force"}, *refusal);
          },
          py::arg("path"), py::arg("force") = false,
          "Writes the calibrated model file (YAML), whole or not at all; refused (InputError) "
          "when the run lists problems unless force=True")
      .def(
          "__getattr__",
          [](const py::object& self, const std::string& name) -> py::object {
            return self.attr("result").attr(name.c_str());
          },
          py::arg("name"), "The identification result's attributes (rms_mm, parameters, robot…)")
      .def("__repr__", [](const CalibrationRun& run) {
        return "<Calibration " + run.result.robot.model.name + ": rms " +
               fmt::format("{:.4f}", run.result.rms_mm) + " mm, " +
               (run.result.status.converged ? "converged" : "NOT converged") +
               (run.problems.empty() ? "" : fmt::format(", {} PROBLEMS", run.problems.size())) +
               ">";
      });

  m.def(
      "calibrate",
      [](const std::optional<std::string>& robot, const std::optional<std::string>& tool,
         const std::string& measurements, const std::optional<std::string>& level,
         const std::vector<std::string>& identify, const std::vector<std::string>& fix,
         const std::string& loss, uint64_t seed, const std::optional<std::string>& model,
         double sigma, int kfold, const std::optional<std::string>& folds,
         const std::optional<std::string>& units, const std::optional<std::string>& euler,
         double orientation_weight, bool keep_near_dependent, std::optional<double> warmup_tau_s) {
        CalibrateFilesRequest request{robot.value_or(""), model.value_or(""),
                                      tool.value_or(""),  measurements,
                                      units.value_or(""), euler.value_or(""),
                                      level.value_or(""), loss,
                                      folds.value_or(""), {}};
        IdentifyOptions& options = request.request.options;
        options.identify = identify;
        options.fix = fix;
        options.seed = seed;
        options.instrument_sigma_mm = sigma;
        options.orientation_weight_mm = orientation_weight;
        options.resolve_near_dependencies = !keep_near_dependent;
        options.warmup_time_constant_s = warmup_tau_s;
        request.request.kfold = kfold;
        return calibrate_files(request);
      },
      py::arg("robot"), py::arg("tool"), py::arg("measurements"), py::arg("level") = py::none(),
      py::arg("identify") = std::vector<std::string>{}, py::arg("fix") = std::vector<std::string>{},
      py::arg("loss") = "none", py::arg("seed") = 1, py::arg("model") = py::none(),
      py::arg("sigma") = 0.0, py::arg("kfold") = 0, py::arg("folds") = py::none(),
      py::arg("units") = py::none(), py::arg("euler") = py::none(),
      py::arg("orientation_weight") = kDefaultOrientationWeightMm,
      py::arg("keep_near_dependent") = false, py::arg("warmup_tau_s") = py::none(),
      "`robcal calibrate` from files: robot name or file, tool file, measurement CSV (level "
      "default full), with the CLI's options (sigma: the instrument's σ in mm, kfold/folds, "
      "units/euler of the file, orientation_weight, keep_near_dependent, warmup_tau_s: the "
      "warm-up group's time constant, default the robot file's) and checks. With "
      "model= (a calibrated model file; robot=None) only what level ('tool', 'base') or "
      "identify asks is re-identified, the rest kept (tool: the new tool, or None). Returns a "
      "Calibration: save(path) refuses a model with problems unless force=True");

  m.def(
      "calibrate",
      [](const RobotModel& robot, const Measurements& measurements, const std::string& level,
         const std::vector<std::string>& identify, const std::vector<std::string>& fix,
         const std::string& loss, uint64_t seed, double sigma, int kfold, double orientation_weight,
         bool keep_near_dependent, std::optional<double> warmup_tau_s) {
        return run_calibration(robot, measurements.tool, measurements.set,
                               make_request(level, identify, fix, loss, seed, sigma, kfold,
                                            orientation_weight, keep_near_dependent, warmup_tau_s));
      },
      py::arg("robot"), py::arg("measurements"), py::arg("level") = "full",
      py::arg("identify") = std::vector<std::string>{}, py::arg("fix") = std::vector<std::string>{},
      py::arg("loss") = "none", py::arg("seed") = 1, py::arg("sigma") = 0.0, py::arg("kfold") = 0,
      py::arg("orientation_weight") = kDefaultOrientationWeightMm,
      py::arg("keep_near_dependent") = false, py::arg("warmup_tau_s") = py::none(),
      "Calibrate a RobotModel from Measurements (their tool included); a Calibration");

  m.def(
      "calibrate_points",
      [](const std::string& robot, const std::string& tool, const Eigen::MatrixXd& joints_deg,
         const std::vector<std::string>& targets, const Eigen::MatrixXd& positions_mm,
         const std::string& level, const std::vector<std::string>& identify,
         const std::vector<std::string>& fix, const std::string& loss, uint64_t seed, double sigma,
         int kfold, bool keep_near_dependent, std::optional<double> warmup_tau_s) {
        const Tool t = load_tool(tool);
        return run_calibration(
            load_robot(robot), t, points_from_arrays(t, joints_deg, targets, positions_mm).set,
            make_request(level, identify, fix, loss, seed, sigma, kfold,
                         kDefaultOrientationWeightMm, keep_near_dependent, warmup_tau_s));
      },
      py::arg("robot"), py::arg("tool"), py::arg("joints_deg"), py::arg("targets"),
      py::arg("positions_mm"), py::arg("level") = "full",
      py::arg("identify") = std::vector<std::string>{}, py::arg("fix") = std::vector<std::string>{},
      py::arg("loss") = "none", py::arg("seed") = 1, py::arg("sigma") = 0.0, py::arg("kfold") = 0,
      py::arg("keep_near_dependent") = false, py::arg("warmup_tau_s") = py::none(),
      "Calibrate from arrays: joints N×6 (deg), target names (N), measured positions N×3 (mm); "
      "a Calibration");

  m.def(
      "cross_validate",
      [](const std::string& robot, const std::string& tool, const std::string& measurements,
         int folds, const std::string& level, uint64_t seed) {
        const RobotModel model = load_robot(robot);
        const Tool t = load_tool(tool);
        const MeasurementFile file = read_measurements_csv(measurements, t);
        const CalibrationRequest request = make_request(
            level, {}, {}, "none", seed, 0, 0, kDefaultOrientationWeightMm, false, std::nullopt);
        return cross_validation_dict(
            cross_validate(model, t, file.measurements, request.options, folds, seed));
      },
      py::arg("robot"), py::arg("tool"), py::arg("measurements"), py::arg("folds"),
      py::arg("level") = "full", py::arg("seed") = 1,
      "K-fold cross-validation: held-out position error per row and its statistics (mm)");

  m.def(
      "load_calibrated_robot", [](const std::string& path) { return load_calibrated_robot(path); },
      py::arg("path"), "Loads a calibrated model file written by calibrate");
});

}  // namespace
}  // namespace robcal::python
