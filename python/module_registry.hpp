#pragma once
// Each expose_*.cpp registers the bindings of one library header group; module.cpp runs them.
#include <pybind11/pybind11.h>

#include <functional>

#include "robcal/core/error.hpp"

namespace robcal::python {
using ExposeFunction = std::function<void(pybind11::module_&)>;
bool register_bindings(int order, ExposeFunction expose);

/// Runs `f`, turning bad input (InputError) into Python's ValueError.
template <typename F>
auto checked(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const InputError& e) {
    throw pybind11::value_error(e.what());
  }
}
}  // namespace robcal::python
