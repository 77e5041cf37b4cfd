#include <algorithm>
#include <utility>
#include <vector>

#include "module_registry.hpp"
#include "robcal/core/error.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {
std::vector<std::pair<int, ExposeFunction>>& registry() {
  static std::vector<std::pair<int, ExposeFunction>> functions;
  return functions;
}
}  // namespace

bool register_bindings(int order, ExposeFunction expose) {
  registry().emplace_back(order, std::move(expose));
  return true;
}
}  // namespace robcal::python

PYBIND11_MODULE(_robcal, m) {
  m.doc() = "robcal: absolute calibration of six-axis industrial robots (mm and degrees outside)";
  m.attr("__version__") = ROBCAL_VERSION;
  // Bad input (robcal::InputError) becomes robcal.InputError, a ValueError whose message names the
  // file, line, column or key, which are also its attributes.
  static const py::handle input_error = PyErr_NewExceptionWithDoc(
      "robcal.InputError",
      "Bad input: the message names the file, line and column or key and says what was expected; "
      "the same parts are the attributes file, line, column and key.",
      PyExc_ValueError, nullptr);
  m.attr("InputError") = input_error;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const robcal::InputError& e) {
      py::object error = input_error(e.what());
      error.attr("file") = e.where().file;
      error.attr("line") = e.where().line;
      error.attr("column") = e.where().column;
      error.attr("key") = e.where().key;
      PyErr_SetObject(input_error.ptr(), error.ptr());
    }
  });
  auto& functions = robcal::python::registry();
  std::stable_sort(functions.begin(), functions.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [order, expose] : functions) expose(m);
}
