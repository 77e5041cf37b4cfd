// Python bindings of the measurement files (include/robcal/io/measurement_file.hpp) and of the
// validation statistics (include/robcal/validate/). Degrees and mm outside; bad input raises
// ValueError with the file, line and column.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "module_registry.hpp"
#include "py_measurements.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/validate/base_fit.hpp"
#include "robcal/validate/validation.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

py::dict statistics_dict(const ErrorStatistics& s) {
  py::dict d;
  d["count"] = s.count;
  d["mean"] = s.mean;
  d["std"] = s.std;
  d["mean_plus_3std"] = s.mean_plus_3std();
  d["min"] = s.min;
  d["max"] = s.max;
  return d;
}

py::dict histogram_dict(const Histogram& h) {
  py::dict d;
  d["lower"] = h.lower;
  d["upper"] = h.upper;
  d["counts"] = h.counts;
  return d;
}

Eigen::Matrix3Xd positions_from_rows(const Eigen::MatrixXd& rows, const char* name) {
  if (rows.cols() != 3)
    throw py::value_error(std::string(name) + " must have 3 columns (x, y, z in mm)");
  return rows.transpose();
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
      [](const std::vector<double>& errors) { return statistics_dict(error_statistics(errors)); },
      py::arg("errors"),
      "count, mean, std (population), mean_plus_3std, min and max of absolute errors");

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
        py::dict d = statistics_dict(r.stats);
        d["pairs"] = r.stats.count;
        d["histogram"] = histogram_dict(r.histogram);
        return d;
      },
      py::arg("measured_mm"), py::arg("modelled_mm"), py::arg("threads") = 2, py::arg("bins") = 128,
      "Distance errors | |m_i − m_j| − |p_i − p_j| | over every pair of rows (N×3 arrays, mm): "
      "count (= pairs), mean, std, min, max, histogram; the same for any thread count");

  m.def(
      "validate",
      [](const std::string& robot_name, const std::string& tool_file,
         const std::string& measurements, const std::string& model_file, bool fit_base_first,
         int threads) {
        const Tool tool = load_tool(tool_file);
        CalibratedRobot robot = model_file.empty()
                                    ? CalibratedRobot::nominal(load_robot(robot_name), tool)
                                    : load_calibrated_robot(model_file);
        if (robot.tool.targets.empty()) robot.tool = tool;
        const MeasurementSet set =
            read_measurements_csv(measurements, robot.tool,
                                  {MeasurementKind::Points, MeasurementKind::Poses})
                .measurements;
        if (!robot.base_fitted && !fit_base_first)
          throw InputError({measurements, 0, 0, "fit_base"},
                           "the model has no world frame (its base was never fitted): pass "
                           "fit_base=True, or calibrate with --level base");
        if (!robot.base_fitted) robot = fit_base(robot, set);
        const ValidationReport report = validate_model(robot, set, threads);
        py::dict d;
        d["points"] = set.size();
        d["position_error_mm"] = statistics_dict(report.positions.position_mm);
        d["position_errors_mm"] = report.positions.position_error_mm;
        d["position_histogram_mm"] = histogram_dict(report.position_histogram);
        py::dict per_target;
        for (const TargetErrorStatistics& t : report.positions.per_target)
          per_target[py::str(t.target)] = statistics_dict(t.position_mm);
        d["per_target"] = per_target;
        if (set.kind == MeasurementKind::Poses)
          d["orientation_error_deg"] = statistics_dict(report.positions.orientation_deg);
        py::dict distances = statistics_dict(report.distances.stats);
        distances["pairs"] = report.distances.stats.count;
        distances["histogram"] = histogram_dict(report.distances.histogram);
        d["distance_error_mm"] = distances;
        return d;
      },
      py::arg("robot"), py::arg("tool_file"), py::arg("measurements"), py::arg("model") = "",
      py::arg("fit_base") = false, py::arg("threads") = 2,
      "Validates a calibrated model file (`model`), or the nominal robot `robot`, (placed by a "
      "rigid best fit when it has no world frame and fit_base=True) against a "
      "points or poses file: position errors overall and per target, histogram, and distance "
      "errors over every pair of rows (docs/method/09-validation.md)");
});

}  // namespace
}  // namespace robcal::python
