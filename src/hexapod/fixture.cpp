#include "robcal/hexapod/fixture.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "robcal/core/error.hpp"

namespace robcal::hexapod {

std::string triangle_problem(const TriangleSides& s) {
  const std::array<double, 3> d = s.as_array();
  static constexpr std::array<const char*, 3> kNames{"d12", "d23", "d31"};
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(d[i]) || d[i] <= 0)
      return fmt::format("side {} = {} mm is not a positive length", kNames[i], d[i]);
  for (int i = 0; i < 3; ++i) {
    const double others = d[(i + 1) % 3] + d[(i + 2) % 3];
    // A relative margin: a flat triangle has collinear cups and no fixture frame.
    if (d[i] >= others * (1 - 1e-6))
      return fmt::format(
          "sides d12 = {}, d23 = {}, d31 = {} mm break the triangle inequality ({} ≥ the sum of "
          "the other two, {} mm): the cups would be collinear or the lengths are misread",
          d[0], d[1], d[2], kNames[i], others);
  }
  return {};
}

Cups<double> fixture_cups(const TriangleSides& sides, const std::string& what) {
  if (const std::string problem = triangle_problem(sides); !problem.empty())
    throw InputError({"", 0, 0, what}, problem);
  return triangle_from_sides(sides.d12, sides.d23, sides.d31);
}

std::vector<double> FixtureDistances::values() const {
  std::vector<double> v{sides.d12, sides.d23, sides.d31};
  if (fourth) v.insert(v.end(), fourth->begin(), fourth->end());
  return v;
}

std::string fixture_problem(const FixtureDistances& f, const std::string& what) {
  const char letter = what.rfind("tool", 0) == 0 ? 'T' : 'B';
  const std::vector<double> values = f.values();
  for (size_t k = 0; k < values.size(); ++k)
    if (!std::isfinite(values[k]) || values[k] <= 0)
      return fmt::format("{}: side d{}{} = {} mm is not a positive length", what,
                         kFixtureDistancePairs[k][0] + 1, kFixtureDistancePairs[k][1] + 1,
                         values[k]);
  if (f.fourth) {
    // Each triangle with the fourth cup, as (cup i, cup j, side ij, side i4, side j4).
    const std::array<std::array<int, 5>, 3> triangles{
        {{0, 1, 0, 3, 4}, {1, 2, 1, 4, 5}, {2, 0, 2, 5, 3}}};
    for (const auto& t : triangles)
      if (!triangle_problem({values[t[2]], values[t[4]], values[t[3]]}).empty())
        return fmt::format(
            "{}: the fourth cup {}4 is collinear with {}{} and {}{} (d{}{} = {}, d{}4 = {}, d{}4 = "
            "{} mm break the triangle inequality): put the fourth cup off the lines through the "
            "others",
            what, letter, letter, t[0] + 1, letter, t[1] + 1, t[0] + 1, t[1] + 1, values[t[2]],
            t[0] + 1, values[t[3]], t[1] + 1, values[t[4]]);
  }
  if (const std::string problem = triangle_problem(f.sides); !problem.empty())
    return what + ": " + problem;
  return {};
}

std::vector<Eigen::Vector3d> fixture_cup_positions(const FixtureDistances& f) {
  const Cups<double> c = triangle_from_sides(f.sides.d12, f.sides.d23, f.sides.d31);
  std::vector<Eigen::Vector3d> cups(c.begin(), c.end());
  if (!f.fourth) return cups;
  // |x − c1| = d14, |x − c2| = d24, |x − c3| = d34 with c1 = 0, c2 on x, c3 in the xy plane.
  const auto [d14, d24, d34] = *f.fourth;
  const double x = (d14 * d14 - d24 * d24 + c[1].x() * c[1].x()) / (2 * c[1].x());
  const double y = (d14 * d14 - d34 * d34 + c[2].squaredNorm() - 2 * x * c[2].x()) / (2 * c[2].y());
  cups.emplace_back(x, y, std::sqrt(std::max(0.0, d14 * d14 - x * x - y * y)));
  return cups;
}

}  // namespace robcal::hexapod
