#include "robcal/hexapod/direct_kinematics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace robcal::hexapod {
namespace {

int side(const Eigen::Vector3d& x, const Eigen::Vector3d& v1, const Eigen::Vector3d& v2,
         const Eigen::Vector3d& v3) {
  return (x - v1).dot((v2 - v1).cross(v3 - v1)) >= 0 ? 1 : -1;
}

}  // namespace

std::array<int, 3> cascade_signs(const Cups<double>& b, const Cups<double>& t) {
  return {side(t[0], b[0], b[1], b[2]), side(t[1], b[0], b[1], t[0]), side(t[2], t[1], b[1], t[0])};
}

LegLengths<double> leg_lengths(const Cups<double>& base, const Cups<double>& tool) {
  LegLengths<double> legs;
  for (size_t i = 0; i < kDesignLegs.size(); ++i)
    legs[i] = (base[kDesignLegs[i].base] - tool[kDesignLegs[i].tool]).norm();
  return legs;
}

DkpResult solve_dkp(const Cups<double>& base, const Eigen::Vector3d& up,
                    const TriangleSides& tool_sides, const LegLengths<double>& legs) {
  DkpResult result;
  const Eigen::Vector3d n = (base[1] - base[0]).cross(base[2] - base[0]);
  if (!(n.norm() > 1e-6 * (base[1] - base[0]).squaredNorm())) {
    result.status = DkpStatus::BaseTriangleInvalid;
    result.message = "the base cups are collinear: no base plane";
    return result;
  }
  if (const std::string problem = triangle_problem(tool_sides); !problem.empty()) {
    result.status = DkpStatus::ToolTriangleInvalid;
    result.message = "tool fixture: " + problem;
    return result;
  }
  static constexpr std::array<const char*, 6> kLegNames{"ρ11", "ρ12", "ρ21", "ρ22", "ρ23", "ρ31"};
  for (size_t i = 0; i < legs.size(); ++i)
    if (!std::isfinite(legs[i]) || legs[i] <= 0) {
      result.status = DkpStatus::NoRealSolution;
      result.message =
          fmt::format("leg {} = {} mm is not a positive length", kLegNames[i], legs[i]);
      return result;
    }
  const std::array<double, 3> sides = tool_sides.as_array();
  // Which steps succeed tells which distances are inconsistent when no solution is real.
  const bool t1_real = tripod(base[0], base[1], base[2], legs[0], legs[2], legs[5], 1).has_value();
  bool any_real = false;
  for (const CascadeSolution<double>& s : cascade_all(base, sides, legs)) {
    if (!s.real) continue;
    any_real = true;
    if ((s.tool[0] - base[0]).dot(up) <= 0) continue;
    result.solutions.push_back({assembly_mode(s.signs[1], s.signs[2]), s.signs, s.tool});
  }
  std::sort(result.solutions.begin(), result.solutions.end(),
            [](const auto& a, const auto& b) { return a.mode < b.mode; });
  if (result.solutions.empty()) {
    result.status = DkpStatus::NoRealSolution;
    if (!t1_real)
      result.message = fmt::format(
          "no real solution: legs ρ11 = {}, ρ21 = {}, ρ31 = {} mm do not meet at one point (the "
          "spheres around B1, B2, B3 do not intersect)",
          legs[0], legs[2], legs[5]);
    else if (!any_real)
      result.message = fmt::format(
          "no real solution: legs ρ12 = {}, ρ22 = {}, ρ23 = {} mm and the tool sides t12 = {}, "
          "t23 = {}, t31 = {} mm are inconsistent with the position of T1",
          legs[1], legs[3], legs[4], sides[0], sides[1], sides[2]);
    else
      result.message = "no real solution above the base plane";
  }
  return result;
}

DkpResult solve_dkp(const TriangleSides& base_sides, const TriangleSides& tool_sides,
                    const LegLengths<double>& legs) {
  if (const std::string problem = triangle_problem(base_sides); !problem.empty()) {
    DkpResult result;
    result.status = DkpStatus::BaseTriangleInvalid;
    result.message = "base fixture: " + problem;
    return result;
  }
  return solve_dkp(triangle_from_sides(base_sides.d12, base_sides.d23, base_sides.d31),
                   Eigen::Vector3d::UnitZ(), tool_sides, legs);
}

bool LegDesign::tool_mirrored() const {
  // A permutation of three is even exactly when it is cyclic.
  return !((tool[1] == (tool[0] + 1) % 3) && (tool[2] == (tool[0] + 2) % 3));
}

std::vector<LegDesign> all_leg_designs() {
  std::vector<LegDesign> designs;
  std::array<int, 3> base{0, 1, 2};
  do {
    std::array<int, 3> tool{0, 1, 2};
    do designs.push_back({base, tool});
    while (std::next_permutation(tool.begin(), tool.end()));
  } while (std::next_permutation(base.begin(), base.end()));
  return designs;
}

}  // namespace robcal::hexapod
