#pragma once
/// \file
/// The `--units` and `--euler` options every command that reads measurement files takes
/// (calibrate, validate; Python's units= and euler=): what the user declares about a file that
/// does not declare it in its header comments.

#include <string>

#include "robcal/io/measurement_file.hpp"

namespace robcal {

/// The format declared by `units` ("m, rad", "mm"…; parse_units) and `euler` ("intrinsic ZYX"…;
/// parse_euler_order); an empty string declares nothing. InputError naming --units or --euler.
MeasurementFormat declared_format(const std::string& units, const std::string& euler);

}  // namespace robcal
