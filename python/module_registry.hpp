#pragma once
// Each expose_*.cpp registers the bindings of one library header group; module.cpp runs them.
#include <pybind11/pybind11.h>

#include <functional>
#include <nlohmann/json.hpp>

namespace robcal::python {
using ExposeFunction = std::function<void(pybind11::module_&)>;
bool register_bindings(int order, ExposeFunction expose);

/// A result's JSON (the library's serializer, the one the CLI prints) as Python dicts and lists.
inline pybind11::object json_to_python(const nlohmann::json& value) {
  return pybind11::module_::import("json").attr("loads")(value.dump());
}

}  // namespace robcal::python
