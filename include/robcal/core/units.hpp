#pragma once
/// \file
/// Units: millimetres and degrees outside, millimetres and radians inside
/// (docs/method/02-frames.md §1).

#include <numbers>

namespace robcal {

inline constexpr double kDegToRad = std::numbers::pi / 180.0;
inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;

constexpr double deg2rad(double deg) {
  return deg * kDegToRad;
}
constexpr double rad2deg(double rad) {
  return rad * kRadToDeg;
}

}  // namespace robcal
