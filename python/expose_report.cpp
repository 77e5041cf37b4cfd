// Python binding of the report workflow (include/robcal/report/report_workflow.hpp): the same
// data and JSON as `robcal report`, and optionally its HTML page and JSON file.

#include <pybind11/stl.h>

#include <optional>

#include "module_registry.hpp"
#include "robcal/report/report_workflow.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

const bool registered = register_bindings(85, [](py::module_& m) {
  m.def(
      "report",
      [](const std::string& model, const std::vector<std::string>& measurements,
         const std::optional<std::string>& calibration, const std::optional<std::string>& before,
         const std::string& title, const std::optional<std::string>& out,
         const std::string& instrument, const std::optional<uint64_t>& seed,
         const std::string& iso9283_poses, const std::string& iso9283_measurements,
         int iso9283_min_cycles, const std::string& ballbar) {
        ReportRequest request;
        request.model = model;
        request.measurements = measurements;
        request.calibration = calibration.value_or("");
        request.before = before.value_or("");
        request.title = title;
        request.instrument = instrument;
        request.seed = seed;
        request.iso9283_poses = iso9283_poses;
        request.iso9283_measurements = iso9283_measurements;
        request.iso9283_min_cycles = iso9283_min_cycles;
        request.ballbar = ballbar;
        std::vector<std::string> warnings;
        const nlohmann::json report = make_report(request, out.value_or(""), warnings);
        py::object result = json_to_python(report);
        result["warnings"] = warnings;
        return result;
      },
      py::arg("model"), py::arg("measurements"), py::arg("calibration") = py::none(),
      py::arg("before") = py::none(), py::arg("title") = "robcal calibration report",
      py::arg("out") = py::none(), py::arg("instrument") = "", py::arg("seed") = py::none(),
      py::arg("iso9283_poses") = "", py::arg("iso9283_measurements") = "",
      py::arg("iso9283_min_cycles") = 30, py::arg("ballbar") = "",
      "A calibrated model validated on measurement files beside the nominal robot (or `before`) "
      "(`robcal report`): the report's JSON as a dict plus `warnings`; with `out` (.html) also "
      "the self-contained page and the JSON beside it. instrument (instrument.yaml) and seed go "
      "to the provenance; iso9283_poses with iso9283_measurements add the ISO 9283 figures, "
      "ballbar (a distances file) the length errors of both models");
});

}  // namespace
}  // namespace robcal::python
