#pragma once
// Each expose_*.cpp registers the bindings of one library header group; module.cpp runs them.
#include <pybind11/pybind11.h>

#include <functional>

namespace robcal::python {
using ExposeFunction = std::function<void(pybind11::module_&)>;
bool register_bindings(int order, ExposeFunction expose);

}  // namespace robcal::python
