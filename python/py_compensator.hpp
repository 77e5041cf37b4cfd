#pragma once
// The Python Compensator (bound in expose_compensate.cpp), shared with the programs bindings that
// take one.
#include "robcal/compensate/compensation_setup.hpp"

namespace robcal::python {

/// A calibrated robot prepared for compensation, with the setup it came from (the file
/// workflows start again from the setup, as the CLI does).
struct PyCompensator {
  CompensationSetup setup;
  Compensation c;
};

}  // namespace robcal::python
