// Python bindings of the measurement files (include/robcal/io/measurement_file.hpp) and of the
// validation statistics (include/robcal/validate/). Degrees and mm outside; bad input raises
// ValueError with the file, line and column.

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "module_registry.hpp"
#include "py_measurements.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/validate/class_statistics.hpp"
#include "robcal/validate/error_statistics_json.hpp"
#include "robcal/validate/validate_workflow.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

py::dict histogram_dict(const Histogram& h) {
  return py::dict(py::arg("lower") = h.lower, py::arg("upper") = h.upper,
                  py::arg("counts") = h.counts);
}

Eigen::Matrix3Xd positions_from_rows(const Eigen::MatrixXd& rows, const char* name) {
  if (rows.cols() != 3)
    throw py::value_error(std::string(name) + " must have 3 columns (x, y, z in mm)");
  return rows.transpose();
}

ValidateOptions options_of(bool fit_base, int threads, double orientation_weight,
                           const std::optional<Eigen::Vector3d>& ballbar_centre,
                           std::optional<double> ballbar_length,
                           std::optional<double> ballbar_range) {
  ValidateOptions options;
  options.fit_base = fit_base;
  options.threads = threads;
  options.orientation_weight_mm = orientation_weight;
  options.ballbar_centre_mm = ballbar_centre;
  options.ballbar_length_mm = ballbar_length;
  options.ballbar_range_mm = ballbar_range;
  return options;
}

/// The rows' target indices refer to their own tool: the model's must name the same targets.
void check_same_targets(const Tool& model_tool, const Tool& rows_tool, const std::string& name) {
  std::vector<std::string> model_targets, row_targets;
  for (const Target& t : model_tool.targets) model_targets.push_back(t.name);
  for (const Target& t : rows_tool.targets) row_targets.push_back(t.name);
  if (!model_targets.empty() && model_targets != row_targets)
    throw InputError({name, 0, 0, "measurements"},
                     "the measurements' tool names other targets (or another order) than the "
                     "model's tool: read them with the model's tool");
}

template <typename Work>
ValidateResult run_released(const Work& work) {
  py::gil_scoped_release release;
  return work();
}

py::array_t<double> as_array(const std::vector<double>& v) {
  return py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
}

/// validate_json's document, with the per-row errors as arrays, the warnings and the notes.
py::dict validate_dict(const ValidateResult& result) {
  py::dict d = json_to_python(validate_json(result));
  if (result.report) {
    const PositionErrors& p = result.report->positions;
    d["position_errors_mm"] = as_array(p.position_error_mm);
    if (result.kind == MeasurementKind::Poses) {
      d["orientation_errors_deg"] = as_array(p.orientation_error_deg);
      d["pose_errors_mm"] = as_array(p.pose_error_mm);
    }
  } else {
    d["length_errors_mm"] = as_array(result.ballbar->length_error_mm);
  }
  d["warnings"] = result.warnings;
  d["notes"] = result.notes;
  return d;
}

const bool registered = register_bindings(60, [](py::module_& m) {
  m.def(
      "read_measurements",
      [](const std::string& path, const std::string& tool_file) {
        const Tool tool = load_tool(tool_file);
        MeasurementFile file = read_measurements_csv(path, tool);
        return measurements_dict({std::move(file.measurements), tool, std::move(file.warnings)});
      },
      py::arg("path"), py::arg("tool_file"),
      "Reads a measurement CSV (points, poses or distances). Returns a dict: kind, config, "
      "target (points/distances), joints_deg (N×6), position_mm (N×3) and quaternion_wxyz "
      "(poses), length_mm (distances), warnings (ignored columns).");

  m.def(
      "error_statistics",
      [](const std::vector<double>& errors, const std::string& unit) {
        return json_to_python(error_statistics_json(error_statistics(errors), unit));
      },
      py::arg("errors"), py::arg("unit") = "mm",
      "count, mean, std (population), mean_plus_3std, min and max of absolute errors, keyed "
      "with their unit (mean_mm, ... or mean_deg, ... for unit='deg'), as validate's JSON");

  m.def(
      "pairwise_distance_errors",
      [](const Eigen::MatrixXd& measured_mm, const Eigen::MatrixXd& modelled_mm, int threads,
         int bins) {
        const Eigen::Matrix3Xd m = positions_from_rows(measured_mm, "measured_mm");
        const Eigen::Matrix3Xd p = positions_from_rows(modelled_mm, "modelled_mm");
        PairwiseDistanceErrors r;
        {
          py::gil_scoped_release release;
          r = pairwise_distance_errors(m, p, threads, bins);
        }
        py::dict d = json_to_python(error_statistics_json(r.stats, "mm"));
        d["pairs"] = r.stats.count;
        d["histogram"] = histogram_dict(r.histogram);
        return d;
      },
      py::arg("measured_mm"), py::arg("modelled_mm"), py::arg("threads") = 2, py::arg("bins") = 128,
      "Distance errors | |m_i − m_j| − |p_i − p_j| | over every pair of rows (N×3 arrays, mm): "
      "count (= pairs), mean_mm, std_mm, mean_plus_3std_mm, min_mm, max_mm, histogram; the same "
      "for any thread count");

  m.def(
      "validate",
      [](const std::string& robot, const std::string& tool_file, const std::string& measurements,
         const std::string& model, bool fit_base, int threads, double orientation_weight,
         const std::optional<Eigen::Vector3d>& ballbar_centre, const std::string& calibration,
         const std::string& units, const std::string& euler, std::optional<double> ballbar_length,
         std::optional<double> ballbar_range) {
        ValidateRequest request{robot,       tool_file, model, measurements,
                                calibration, {},        units, euler};
        request.options = options_of(fit_base, threads, orientation_weight, ballbar_centre,
                                     ballbar_length, ballbar_range);
        return validate_dict(run_released([&] { return validate(request); }));
      },
      py::arg("robot"), py::arg("tool_file"), py::arg("measurements"), py::arg("model") = "",
      py::arg("fit_base") = false, py::arg("threads") = 2,
      py::arg("orientation_weight") = kDefaultOrientationWeightMm,
      py::arg("ballbar_centre") = py::none(), py::arg("calibration") = "", py::arg("units") = "",
      py::arg("euler") = "", py::arg("ballbar_length") = py::none(),
      py::arg("ballbar_range") = py::none(),
      "`robcal validate`: a calibrated model file (`model`), or the nominal robot `robot`, "
      "against a points, poses or distances (ballbar) file (units, euler: as calibrate's, for "
      "files that do not declare them; ballbar_length, ballbar_range: mm, as --ballbar-length "
      "and --ballbar-range); the CLI's --json document as a dict "
      "plus per-row arrays (docs/method/09-validation.md)");

  m.def(
      "validate_rows",
      [](const CalibratedRobot& model, const Measurements& measurements, bool fit_base, int threads,
         double orientation_weight, const std::optional<Eigen::Vector3d>& ballbar_centre,
         const std::optional<Measurements>& calibration, const std::string& name,
         std::optional<double> ballbar_length, std::optional<double> ballbar_range) {
        check_same_targets(model.tool, measurements.tool, name);
        ValidateOptions options = options_of(fit_base, threads, orientation_weight, ballbar_centre,
                                             ballbar_length, ballbar_range);
        if (calibration) options.calibration_mm = measured_positions(calibration->set);
        ValidateResult result =
            run_released([&] { return validate(model, measurements.set, options, name); });
        result.warnings.insert(result.warnings.begin(), measurements.warnings.begin(),
                               measurements.warnings.end());
        return validate_dict(result);
      },
      py::arg("model"), py::arg("measurements"), py::arg("fit_base") = false,
      py::arg("threads") = 2, py::arg("orientation_weight") = kDefaultOrientationWeightMm,
      py::arg("ballbar_centre") = py::none(), py::arg("calibration") = py::none(),
      py::arg("name") = "<arrays>", py::arg("ballbar_length") = py::none(),
      py::arg("ballbar_range") = py::none(),
      "validate() of a CalibratedRobot against Measurements (from files, dicts or arrays); "
      "`calibration` (Measurements) adds the region classes");
});

}  // namespace
}  // namespace robcal::python
