#pragma once

#include <cmath>

namespace robcal {

/// Below this |δ| (rad) sin δ and cos δ come from their Taylor series to δ⁷ and δ⁶: the first
/// terms left out, δ⁹/9! and δ⁸/8!, are below 7e-19 there, far under double rounding.
inline constexpr double kSeriesShiftLimitRad = 0.02;

/// sin(θ + δ) and cos(θ + δ) from s0 = sin θ, c0 = cos θ. The shifts met in the hot loops are
/// small (gearbox deflections, a fit's or a Newton iteration's step) and take the series:
/// multiplications only, no call. Larger ones take std::sin and std::cos of δ: exact either way,
/// the series only saves time.
inline void sin_cos_shifted(double s0, double c0, double delta, double* s, double* c) {
  double sd, cd;
  if (std::abs(delta) < kSeriesShiftLimitRad) {
    const double d2 = delta * delta;  // Horner with the factorials' reciprocals
    sd = delta * (1 - d2 * (1.0 / 6 - d2 * (1.0 / 120 - d2 * (1.0 / 5040))));
    cd = 1 - d2 * (0.5 - d2 * (1.0 / 24 - d2 * (1.0 / 720)));
  } else {
    sd = std::sin(delta);
    cd = std::cos(delta);
  }
  *s = s0 * cd + c0 * sd;
  *c = c0 * cd - s0 * sd;
}

}  // namespace robcal
