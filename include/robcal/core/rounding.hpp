#pragma once
/// \file
/// Rounding numbers for output files and printouts: readable decimals, and no "-0".

#include <cmath>

namespace robcal {

/// `value` rounded to `decimals` decimal places; -0 becomes 0.
inline double rounded(double value, int decimals = 9) {
  const double scale = std::pow(10.0, decimals);
  const double r = std::round(value * scale) / scale;
  return r == 0.0 ? 0.0 : r;
}

}  // namespace robcal
