#pragma once
/// \file
/// atan2 for the closed-form IK's hot path: within 5e-16 rad of std::atan2 (checked in
/// tests/test_inverse_kinematics.cpp) at a fraction of glibc's cost, which is dominated by its
/// correctly-rounded slow paths. Branch-free: one division and a degree-13 odd polynomial.
///
/// Method: with lo = min(|x|,|y|), hi = max(|x|,|y|), t = lo/hi ∈ [0, 1] and c = k/8 the
/// nearest eighth (k found by comparisons, no division), atan t = atan c + atan u with
/// u = (lo − c·hi)/(hi + c·lo), |u| ≤ 1/16, and atan u by its Taylor series to u¹³ (remainder
/// u¹⁵/15 < 6e-20); then the octant is restored and the sign of y applied.

#include <array>
#include <cmath>
#include <numbers>

namespace robcal {

namespace detail {
/// atan x for 0 ≤ x ≤ 1 at compile time by Euler's series
/// atan x = Σ_n (2^{2n}(n!)²/(2n+1)!)·x^{2n+1}/(1+x²)^{n+1}, whose terms shrink by ≤ ½ per step.
/// Summed in long double so the rounded table is exact to the last bit of a double.
constexpr double euler_atan(long double x) {
  const long double y = x * x / (1.0L + x * x);
  long double term = x / (1.0L + x * x), sum = 0.0L;
  for (int n = 0; n < 120; ++n) {
    sum += term;
    term *= y * (2.0L * n + 2.0L) / (2.0L * n + 3.0L);
  }
  return static_cast<double>(sum);
}

/// atan(k/8) for k = 0..8.
inline constexpr std::array<double, 9> kAtanEighths = [] {
  std::array<double, 9> t{};
  for (int k = 0; k <= 8; ++k) t[k] = euler_atan(k / 8.0L);
  return t;
}();
}  // namespace detail

/// atan2(y, x) in [−π, π]; ±0 for (±0, 0).
inline double fast_atan2(double y, double x) {
  constexpr const std::array<double, 9>& table = detail::kAtanEighths;
  const double ax = std::abs(x), ay = std::abs(y);
  const bool steep = ay > ax;
  const double hi = steep ? ay : ax, lo = steep ? ax : ay;
  // k = round(8·lo/hi): count the midpoints (2m − 1)/16 that t exceeds.
  const double lo16 = 16.0 * lo;
  const int k = (lo16 > hi) + (lo16 > 3 * hi) + (lo16 > 5 * hi) + (lo16 > 7 * hi) +
                (lo16 > 9 * hi) + (lo16 > 11 * hi) + (lo16 > 13 * hi) + (lo16 > 15 * hi);
  const double c = 0.125 * k;
  const double den = hi + c * lo;
  const double u = den > 0 ? (lo - c * hi) / den : 0.0;
  const double u2 = u * u;
  // Taylor series of atan u: u − u³/3 + u⁵/5 − u⁷/7 + u⁹/9 − u¹¹/11 + u¹³/13, Horner form.
  double p = 1.0 / 13;
  p = p * u2 - 1.0 / 11;
  p = p * u2 + 1.0 / 9;
  p = p * u2 - 1.0 / 7;
  p = p * u2 + 1.0 / 5;
  p = p * u2 - 1.0 / 3;
  const double r = table[k] + (u + u * u2 * p);
  const double r1 = steep ? std::numbers::pi / 2 - r : r;
  const double r2 = x < 0 ? std::numbers::pi - r1 : r1;
  return std::copysign(r2, y);
}

}  // namespace robcal
