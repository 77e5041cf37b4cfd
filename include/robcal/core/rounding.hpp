#pragma once
/// \file
/// Rounding numbers for output files and printouts: readable decimals, and no "-0".

#include <cmath>
#include <optional>

namespace robcal {

/// `value` rounded to `decimals` decimal places; -0 becomes 0.
inline double rounded(double value, int decimals = 9) {
  const double scale = std::pow(10.0, decimals);
  const double r = std::round(value * scale) / scale;
  return r == 0.0 ? 0.0 : r;
}

/// `value` rounded to `decimals` places when given, else unchanged (full precision).
inline double rounded_if(double value, std::optional<int> decimals) {
  return decimals ? rounded(value, *decimals) : value;
}

}  // namespace robcal
