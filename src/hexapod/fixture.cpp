#include "robcal/hexapod/fixture.hpp"

#include <fmt/format.h>

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

}  // namespace robcal::hexapod
