// Python bindings of the virtual instruments (include/robcal/measure/instrument.hpp) and the
// simulator (include/robcal/sim/). Degrees and mm outside, as everywhere in the bindings.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <random>

#include "module_registry.hpp"
#include "robcal/measure/instrument.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

const bool registered = register_bindings(40, [](py::module_& m) {
  py::class_<LaserTracker>(m, "LaserTracker", "Laser tracker: 3D point of one SMR (METHOD §7)")
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
});

}  // namespace
}  // namespace robcal::python
