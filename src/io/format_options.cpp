#include "robcal/io/format_options.hpp"

namespace robcal {

MeasurementFormat declared_format(const std::string& units, const std::string& euler) {
  MeasurementFormat format;
  if (!units.empty()) parse_units(units, {"", 0, 0, "--units"}, format);
  if (!euler.empty()) format.euler = parse_euler_order(euler, {"", 0, 0, "--euler"});
  return format;
}

}  // namespace robcal
