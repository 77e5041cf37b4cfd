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
         const std::string& title, const std::optional<std::string>& out) {
        if (out) check_report_path(*out);
        ReportRequest request;
        request.model = model;
        request.measurements = measurements;
        request.calibration = calibration.value_or("");
        request.before = before.value_or("");
        request.title = title;
        const ReportBuild build = build_report(request);
        const nlohmann::json report = report_json(build.data);
        if (out) write_report(report, *out);
        py::object result = json_to_python(report);
        result["warnings"] = build.warnings;
        return result;
      },
      py::arg("model"), py::arg("measurements"), py::arg("calibration") = py::none(),
      py::arg("before") = py::none(), py::arg("title") = "robcal calibration report",
      py::arg("out") = py::none(),
      "A calibrated model validated on measurement files beside the nominal robot (or `before`) "
      "(`robcal report`): the report's JSON as a dict plus `warnings`; with `out` (.html) also "
      "the self-contained page and the JSON beside it");
});

}  // namespace
}  // namespace robcal::python
