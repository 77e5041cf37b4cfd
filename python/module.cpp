#include <algorithm>
#include <utility>
#include <vector>

#include "module_registry.hpp"

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
  auto& functions = robcal::python::registry();
  std::stable_sort(functions.begin(), functions.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [order, expose] : functions) expose(m);
}
