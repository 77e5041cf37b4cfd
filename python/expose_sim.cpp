// Python bindings of the virtual instruments (include/robcal/measure/instrument.hpp) and the
// simulator (include/robcal/sim/). Degrees and mm outside, as everywhere in the bindings.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <random>

#include "module_registry.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/measure/instrument.hpp"
#include "robcal/sim/simulate_workflow.hpp"
#include "robcal/sim/simulator.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

/// A simulated campaign as arrays: what `robcal simulate` writes, in memory.
py::dict simulate(const std::string& instrument_name, const std::string& truth_name, int count,
                  uint64_t seed, double noise_mm, const std::string& robot, const std::string& cell,
                  const std::string& tool_file, const std::string& configs,
                  const std::vector<std::string>& effects, const std::string& approach, bool clock,
                  double error_length_mm, double error_angle_deg, const std::string& out_dir) {
  SimulateRequest request;
  request.robot = robot;
  request.instrument = instrument_name;
  request.truth = truth_name;
  request.cell = cell;
  request.tool = tool_file;
  request.configs = configs;
  request.random = configs.empty() ? count : 0;  // the configurations file, else `count` random
  request.seed = seed;
  request.noise_mm = noise_mm;
  request.exact = noise_mm == 0;
  request.effects = effects;
  request.approach = approach;
  request.clock = clock;
  request.error_length_mm = error_length_mm;
  request.error_angle_deg = error_angle_deg;
  request.out = out_dir;
  const SimulateResult result = [&] {
    py::gil_scoped_release release;
    return run_simulation(request);
  }();
  const MeasurementSet& set = result.simulation.measurements;
  const Tool& tool = result.tool;
  const Eigen::Index n = static_cast<Eigen::Index>(set.size());
  Eigen::MatrixXd joints(n, kJointCount), values(n, set.residuals_per_row() == 1 ? 1 : 3);
  Eigen::VectorXd times(n), temperatures(n);  // NaN: the row records none
  py::list names, targets;
  for (Eigen::Index i = 0; i < n; ++i) {
    const size_t k = static_cast<size_t>(i);
    times[i] = set.time_s(k).value_or(NAN);
    temperatures[i] = set.temperature_c(k).value_or(NAN);
    switch (set.kind) {
      case MeasurementKind::Points:
        names.append(set.points[k].config);
        targets.append(tool.targets[static_cast<size_t>(set.points[k].target)].name);
        joints.row(i) = set.points[k].joints.transpose() * kRadToDeg;
        values.row(i) = set.points[k].position_mm.transpose();
        break;
      case MeasurementKind::Poses:
        names.append(set.poses[k].config);
        targets.append("tcp");
        joints.row(i) = set.poses[k].joints.transpose() * kRadToDeg;
        values.row(i) = set.poses[k].world_T_tcp.p.transpose();
        break;
      case MeasurementKind::Distances:
        names.append(set.distances[k].config);
        targets.append(tool.targets[static_cast<size_t>(set.distances[k].target)].name);
        joints.row(i) = set.distances[k].joints.transpose() * kRadToDeg;
        values(i, 0) = set.distances[k].length_mm;
        break;
    }
  }
  py::dict out;
  out["config"] = names;
  out["target"] = targets;
  out["joints_deg"] = joints;
  out[set.kind == MeasurementKind::Distances ? "length_mm" : "position_mm"] = values;
  out["time_s"] = times;
  out["temperature_c"] = temperatures;
  out["summary"] = json_to_python(simulation_json(result));
  return out;
}

const bool registered = register_bindings(40, [](py::module_& m) {
  py::class_<LaserTracker>(m, "LaserTracker",
                           "Laser tracker: 3D point of one SMR (docs/method/06-instruments.md §1)")
      .def(py::init<>())
      .def_readwrite("position_mm", &LaserTracker::position_mm)
      .def_readwrite("sigma_mm", &LaserTracker::sigma_mm, "σ per axis, mm")
      .def_readwrite("cone_half_angle_deg", &LaserTracker::cone_half_angle_deg)
      .def_readwrite("min_range_mm", &LaserTracker::min_range_mm)
      .def_readwrite("max_range_mm", &LaserTracker::max_range_mm);
  m.def("smr_visible", &smr_visible, py::arg("tracker"), py::arg("smr_mm"), py::arg("smr_axis"),
        "True when the tracker lies within the SMR's acceptance cone and range");
  m.def(
      "read_points",
      [](const LaserTracker& tracker, const Eigen::Vector3d& smr_mm, int count, uint64_t seed) {
        if (count < 0) throw py::value_error("count must not be negative");
        std::mt19937_64 rng(seed);
        Eigen::MatrixXd readings(count, 3);
        for (int i = 0; i < count; ++i) readings.row(i) = read_point(tracker, smr_mm, rng);
        return readings;
      },
      py::arg("tracker"), py::arg("smr_mm"), py::arg("count"), py::arg("seed"),
      "`count` noisy readings of one SMR (rows x, y, z in mm), seeded");

  py::class_<Ballbar>(m, "Ballbar", "Telescoping ballbar: one length near its nominal")
      .def(py::init<>())
      .def_readwrite("centre_mm", &Ballbar::centre_mm)
      .def_readwrite("nominal_length_mm", &Ballbar::nominal_length_mm)
      .def_readwrite("sigma_mm", &Ballbar::sigma_mm)
      .def_readwrite("range_mm", &Ballbar::range_mm);
  m.def("ballbar_readable", &ballbar_readable, py::arg("ballbar"), py::arg("length_mm"),
        "True when the length is within the ballbar's ±range of its nominal");

  py::class_<OpticalCmm>(m, "OpticalCmm", "Optical CMM: 6D pose of a target cluster")
      .def(py::init<>())
      .def_readwrite("position_mm", &OpticalCmm::position_mm)
      .def_readwrite("sigma_mm", &OpticalCmm::sigma_mm)
      .def_readwrite("sigma_orientation_deg", &OpticalCmm::sigma_orientation_deg)
      .def_readwrite("facing_limit_deg", &OpticalCmm::facing_limit_deg);

  m.def("simulate", &simulate, py::arg("instrument") = "laser-tracker",
        py::arg("truth") = "published", py::arg("count") = 20, py::arg("seed") = 1,
        py::arg("noise_mm") = 0.0, py::arg("robot") = "abb-irb120", py::arg("cell") = "",
        py::arg("tool") = "", py::arg("configs") = "",
        py::arg("effects") = std::vector<std::string>{}, py::arg("approach") = "below",
        py::arg("clock") = false, py::arg("error_length_mm") = ErrorBounds{}.length_mm,
        py::arg("error_angle_deg") = ErrorBounds{}.angle_deg, py::arg("out") = "",
        "`robcal simulate`: measures `count` random measurable configurations (or those of the "
        "`configs` file) of a virtual robot (published, random or a truth file, with unmodelled "
        "`effects`) with a virtual instrument placed by `cell`; noise_mm = 0 gives exact "
        "readings (the CLI's --noise-mm 0 means the instrument's own σ); with thermal drift, "
        "clock=True records each row's time instead of the arm's temperature (--clock). With "
        "`out` the files of a real campaign are written there. Returns a dict of config, target, "
        "joints_deg (n×6) and position_mm (n×3) or length_mm (n×1), time_s and temperature_c "
        "(n, NaN where a row records none), and 'summary' (the CLI's --json).");
});

}  // namespace
}  // namespace robcal::python
