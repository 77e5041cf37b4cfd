#pragma once
/// \file
/// atan2 for the closed-form IK's hot path: within 2 ulp (4.4e-16 rad) of std::atan2 and exact
/// at its special values (checked in tests/test_inverse_kinematics.cpp), at a fraction of
/// glibc's cost, which is dominated by its correctly-rounded slow paths. Branch-free and
/// without indexed loads, so that a loop of calls compiles to vector code (SSE2 or AVX2): two
/// divisions, a degree-13 odd polynomial, selects.
///
/// Method: with lo = min(|x|,|y|), hi = max(|x|,|y|), t = lo/hi ∈ [0, 1] and c = k/8 the
/// nearest eighth, atan t = atan c + atan u with u = (t − c)/(1 + c·t), |u| ≤ 1/16, and atan u by
/// its Taylor series to u¹³ (remainder u¹⁵/15 < 6e-20); then the octant is restored and the sign
/// of y applied.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

// A solver whose loop of fast_atan2 calls should run in vector lanes is compiled twice, for
// AVX2 (4 lanes) and for any x86-64 (SSE2, 2 lanes), and the copy the processor runs is picked
// at load time; flatten keeps every helper inside the copy (a helper left in the SSE2 encoding
// measured twice as slow, called from the AVX2 one). (GCC only: clang refuses flatten on a
// multiversioned function.)
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define ROBCAL_VECTOR_CLONES __attribute__((target_clones("avx2", "default"), flatten))
#else
#define ROBCAL_VECTOR_CLONES
#endif

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

/// atan2(y, x) in [−π, π], with std::atan2's values at ±0, ±∞ and NaN.
inline double fast_atan2(double y, double x) {
  constexpr const std::array<double, 9>& kTable = detail::kAtanEighths;
  const double ax = std::abs(x), ay = std::abs(y);
  // Operand order makes a NaN x reach lo and a NaN y reach hi, so t is NaN for either; 0/0 and
  // ∞/∞ are taken as 0 and 1.
  const double lo = std::min(ax, ay), hi = std::max(ay, ax);
  const double t = lo == hi ? (lo > 0 ? 1.0 : 0.0) : lo / hi;
  // k = round(8t); min(8.5, ·) also maps the NaN to a valid index.
  const int k = static_cast<int>(std::min(8.5, 8.0 * t + 0.5));
  const double c = 0.125 * k;
  const double u = (t - c) / (1.0 + c * t);
  const double u2 = u * u;
  // Taylor series of atan u: u − u³/3 + u⁵/5 − u⁷/7 + u⁹/9 − u¹¹/11 + u¹³/13, Horner form.
  double p = 1.0 / 13;
  p = p * u2 - 1.0 / 11;
  p = p * u2 + 1.0 / 9;
  p = p * u2 - 1.0 / 7;
  p = p * u2 + 1.0 / 5;
  p = p * u2 - 1.0 / 3;
  // atan(k/8) by selects rather than an indexed load, which vector units without a gather
  // (SSE2) cannot do.
  double atan_c = kTable[0];
  for (int j = 1; j <= 8; ++j) atan_c = c >= 0.125 * j ? kTable[j] : atan_c;
  const double r = atan_c + (u + u * u2 * p);
  // Octant restored by arithmetic on ±1 factors rather than selects, which compilers turn into
  // branches that random inputs mispredict: r → π/2 − r when steep, r → π − r when x < 0.
  const double steep = std::copysign(1.0, ax - ay);  // −1 when |y| > |x|
  const double r1 = steep * r + (1.0 - steep) * (std::numbers::pi / 4);
  const double west = std::copysign(1.0, x);  // −1 when x < 0 (or −0)
  const double r2 = west * r1 + (1.0 - west) * (std::numbers::pi / 2);
  return std::copysign(r2, y);
}

}  // namespace robcal
