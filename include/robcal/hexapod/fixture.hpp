#pragma once
/// \file
/// The two triangular fixtures of the ballbar hexapod (docs/method/07-hexapod.md §1): cup positions
/// from the three side lengths measured with the ballbar, and the fixture frame that three cup
/// positions define.
///
/// Convention, used for both fixtures: cup 1 at the origin, cup 2 on +x, cup 3 in the xy plane
/// with y > 0, so z = (c2 − c1) × (c3 − c1) / |…|. The base cups are numbered counter-clockwise
/// seen from above (z points up, towards the tool); the tool cups counter-clockwise seen from the
/// side the cups open to.

#include <ceres/jet.h>

#include <Eigen/Geometry>

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "robcal/kinematics/forward_kinematics.hpp"

namespace robcal::hexapod {

/// Three cup centres (mm) in some frame; index 0..2 = cup 1..3.
template <typename T>
using Cups = std::array<Vector3<T>, 3>;

/// The value part of a double or a Jet: validity tests must not look at derivatives.
inline double scalar_value(double x) {
  return x;
}
template <typename S, int N>
double scalar_value(const ceres::Jet<S, N>& x) {
  return x.a;
}

/// Side lengths of a triangular fixture (mm): d12 = |c1c2|, d23 = |c2c3|, d31 = |c3c1|.
struct TriangleSides {
  double d12 = 0;
  double d23 = 0;
  double d31 = 0;
  [[nodiscard]] std::array<double, 3> as_array() const { return {d12, d23, d31}; }
};

/// The cup pairs of FixtureDistances::values(), 0-based: 12, 23, 31, 14, 24, 34.
inline constexpr std::array<std::array<int, 2>, 6> kFixtureDistancePairs{
    {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};

/// The measured (or designed) distances of a fixture of three or four cups (mm): the fourth cup
/// of issue 20 (four_cup_kinematics.hpp) is given by its distances to cups 1..3.
struct FixtureDistances {
  FixtureDistances() = default;
  /// Implicit from the sides: a fixture of three cups.
  FixtureDistances(const TriangleSides& sides_mm,
                   std::optional<std::array<double, 3>> fourth_mm = std::nullopt)
      : sides(sides_mm), fourth(fourth_mm) {}
  TriangleSides sides;  ///< cups 1..3
  /// d14, d24, d34 when the fixture has a fourth cup.
  std::optional<std::array<double, 3>> fourth;
  [[nodiscard]] int cup_count() const { return fourth ? 4 : 3; }
  /// d12, d23, d31 then d14, d24, d34: the order the session reads them in.
  [[nodiscard]] std::vector<double> values() const;
};

/// Empty when the sides make a proper triangle; otherwise why not (a side not positive or
/// finite, or the triangle inequality broken or within 1e-6 of equality: the cups are collinear).
std::string triangle_problem(const TriangleSides& sides);

/// Cup positions from the side lengths (docs/method/07-hexapod.md §1): c1 = 0, c2 = (d12, 0, 0),
/// c3 = (x, y, 0) with x = (d12² − d23² + d31²)/(2·d12) and y = 2·area/d12 (Heron).
/// Precondition: triangle_problem(sides) is empty (the Jet version cannot throw usefully).
template <typename T>
Cups<T> triangle_from_sides(const T& d12, const T& d23, const T& d31) {
  using std::sqrt;
  const T s = (d12 + d23 + d31) / T(2);
  const T area = sqrt(s * (s - d12) * (s - d23) * (s - d31));
  Cups<T> c;
  c[0] = Vector3<T>::Zero();
  c[1] << d12, T(0), T(0);
  c[2] << (d12 * d12 - d23 * d23 + d31 * d31) / (T(2) * d12), T(2) * area / d12, T(0);
  return c;
}

/// Checked version for measured sides: throws InputError naming `what` (e.g. "base fixture")
/// and the sides when they do not make a triangle.
Cups<double> fixture_cups(const TriangleSides& sides, const std::string& what);

/// Empty when the fixture's distances can be solved; otherwise why not (`what` names it:
/// "base fixture"): a triangle of any three of its cups that is not a proper triangle, i.e. a
/// side not positive or three cups collinear — a fourth cup on the line through two others.
std::string fixture_problem(const FixtureDistances& fixture, const std::string& what);

/// The cups in the fixture's own frame (cups 1..3 as triangle_from_sides, the fourth by
/// trilateration on the side its cups open to, +z; in the plane when its distances put it there
/// within rounding or are inconsistent: then d34 is not reproduced, which callers that design a
/// fixture check).
/// Precondition: fixture_problem is empty.
std::vector<Eigen::Vector3d> fixture_cup_positions(const FixtureDistances& fixture);

/// The fixture frame defined by three cup positions: origin at c1, x towards c2,
/// z = (c2 − c1) × (c3 − c1) normalised. Returns frame_T_fixture (maps fixture coordinates into
/// the cups' frame). Precondition: the cups are not collinear.
template <typename T>
Pose<T> frame_from_cups(const Cups<T>& c) {
  const Vector3<T> x = (c[1] - c[0]).normalized();
  const Vector3<T> z = (c[1] - c[0]).cross(c[2] - c[0]).normalized();
  Pose<T> pose;
  pose.R.col(0) = x;
  pose.R.col(1) = z.cross(x);
  pose.R.col(2) = z;
  pose.p = c[0];
  return pose;
}

/// Centroid of three cups.
template <typename T>
Vector3<T> centroid(const Cups<T>& c) {
  return (c[0] + c[1] + c[2]) / T(3);
}

}  // namespace robcal::hexapod
