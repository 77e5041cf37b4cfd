#pragma once
/// \file
/// Direct kinematics of the ballbar hexapod (docs/method/07-hexapod.md §2): the tripod function Tri
/// and the three-step cascade of leg design 1^12 2^123 3^1, templated on the scalar so that Jets
/// give the sensitivity of every tool-cup coordinate to every measured distance.
///
/// Sign convention: a Tri solution x = p + s·k lies on the side `sign` of the plane through its
/// three vertices, sign = +1 along k = (v2 − v1) × (v3 − v1). The cascade makes three such
/// choices (signs[0..2]) hence 8 solutions. With the base cups in their own numbering (counter-
/// clockwise seen from above) signs[0] = +1 puts t1 above the base plane; the other two choose
/// the assembly mode: mode = 1 + 2·[signs[1] < 0] + [signs[2] < 0].

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "robcal/hexapod/fixture.hpp"

namespace robcal::hexapod {

/// One leg of the design: which base cup and which tool cup (0-based design roles).
struct LegRoles {
  int base = 0;
  int tool = 0;
};

/// The six legs of design 1^12 2^123 3^1 in measurement order: ρ11, ρ12, ρ21, ρ22, ρ23, ρ31.
inline constexpr std::array<LegRoles, 6> kDesignLegs{
    {{0, 0}, {0, 1}, {1, 0}, {1, 1}, {1, 2}, {2, 0}}};

/// Leg lengths ρ_ij (mm) in the order of kDesignLegs.
template <typename T>
using LegLengths = std::array<T, 6>;

/// Tri(v1, v2, v3, l1, l2, l3) of docs/method/07-hexapod.md §2: the point x with |x − v_i| = l_i on
/// side `sign` (±1) of the plane v1 v2 v3. Returns nullopt when the vertices are collinear or the
/// spheres do not meet (negative discriminant).
///
/// The formula of docs/method/07-hexapod.md §2 is evaluated with v1 moved to the origin (u = v2 −
/// v1, w = v3 − v1, so ξ1 = ½(l1² − l2² + u·u), ξ2 = ½(l1² − l3² + w·w) and v1·k = 0): the same
/// algebra without the cancellation of v·v terms of far-away vertices; s² = l1² − |p|² is formed as
/// (l1 − |p|)(l1 + |p|).
template <typename T>
std::optional<Vector3<T>> tripod(const Vector3<T>& v1, const Vector3<T>& v2, const Vector3<T>& v3,
                                 const T& l1, const T& l2, const T& l3, int sign) {
  using std::sqrt;
  const Vector3<T> u = v2 - v1;
  const Vector3<T> w = v3 - v1;
  const Vector3<T> n = u.cross(w);
  const T uu = u.dot(u);
  const T nn = n.dot(n);
  if (!(scalar_value(nn) > 1e-12 * scalar_value(uu) * scalar_value(w.dot(w)))) return std::nullopt;
  const T xi1 = T(0.5) * (l1 * l1 - l2 * l2 + uu);
  const T xi2 = T(0.5) * (l1 * l1 - l3 * l3 + w.dot(w));
  const Vector3<T> p = (xi1 / uu) * u + ((xi2 * uu - xi1 * u.dot(w)) / (uu * nn)) * n.cross(u);
  const T pn = p.norm();
  const T disc = (l1 - pn) * (l1 + pn);
  if (!(scalar_value(disc) >= 0)) return std::nullopt;
  return Vector3<T>(v1 + p + (T(sign) * sqrt(disc) / sqrt(nn)) * n);
}

/// One of the 8 cascade solutions.
template <typename T>
struct CascadeSolution {
  std::array<int, 3> signs{};  ///< the three Tri side choices
  bool real = false;           ///< false: some step had no real solution
  Cups<T> tool;                ///< t1, t2, t3 (design roles) in the base cups' frame
};

/// The cascade of docs/method/07-hexapod.md §2 for one sign triple:
/// t1 = Tri(b1,b2,b3, ρ11,ρ21,ρ31); t2 = Tri(b1,b2,t1, ρ12,ρ22,t12); t3 = Tri(t2,b2,t1,
/// t23,ρ23,t31). `tool_sides` = (t12, t23, t31) in design roles.
template <typename T>
CascadeSolution<T> cascade(const Cups<T>& b, const std::array<T, 3>& tool_sides,
                           const LegLengths<T>& rho, const std::array<int, 3>& signs) {
  CascadeSolution<T> out;
  out.signs = signs;
  const auto t1 = tripod(b[0], b[1], b[2], rho[0], rho[2], rho[5], signs[0]);
  if (!t1) return out;
  const auto t2 = tripod(b[0], b[1], *t1, rho[1], rho[3], tool_sides[0], signs[1]);
  if (!t2) return out;
  const auto t3 = tripod(*t2, b[1], *t1, tool_sides[1], rho[4], tool_sides[2], signs[2]);
  if (!t3) return out;
  out.real = true;
  out.tool = {*t1, *t2, *t3};
  return out;
}

/// All 8 solutions, signs in the order (+,+,+), (+,+,−), (+,−,+), …, (−,−,−). The steps shared by
/// solutions are computed once: 2 + 4 + 8 Tri calls instead of 24.
template <typename T>
std::array<CascadeSolution<T>, 8> cascade_all(const Cups<T>& b, const std::array<T, 3>& tool_sides,
                                              const LegLengths<T>& rho) {
  std::array<CascadeSolution<T>, 8> all;
  for (int i = 0; i < 8; ++i) all[i].signs = {(i & 4) ? -1 : 1, (i & 2) ? -1 : 1, (i & 1) ? -1 : 1};
  for (int s1 = 0; s1 < 2; ++s1) {
    const auto t1 = tripod(b[0], b[1], b[2], rho[0], rho[2], rho[5], s1 ? -1 : 1);
    if (!t1) continue;
    for (int s2 = 0; s2 < 2; ++s2) {
      const auto t2 = tripod(b[0], b[1], *t1, rho[1], rho[3], tool_sides[0], s2 ? -1 : 1);
      if (!t2) continue;
      for (int s3 = 0; s3 < 2; ++s3) {
        const auto t3 = tripod(*t2, b[1], *t1, tool_sides[1], rho[4], tool_sides[2], s3 ? -1 : 1);
        if (!t3) continue;
        CascadeSolution<T>& out = all[4 * s1 + 2 * s2 + s3];
        out.real = true;
        out.tool = {*t1, *t2, *t3};
      }
    }
  }
  return all;
}

/// Assembly mode 1..4 of the two last sign choices (docs/method/07-hexapod.md §2: 4 modes above the
/// base plane).
constexpr int assembly_mode(int sign2, int sign3) {
  return 1 + (sign2 < 0 ? 2 : 0) + (sign3 < 0 ? 1 : 0);
}
/// The signs (+1, sign2, sign3) of an assembly mode 1..4, for base cups in their own numbering.
constexpr std::array<int, 3> mode_signs(int mode) {
  return {1, ((mode - 1) & 2) ? -1 : 1, ((mode - 1) & 1) ? -1 : 1};
}

/// The Tri side choices that reproduce the given tool cups (design roles) from these base cups:
/// which of the 8 solutions a known configuration is.
std::array<int, 3> cascade_signs(const Cups<double>& base, const Cups<double>& tool);

/// Outcome of the direct kinematics on measured distances.
enum class DkpStatus { Ok, BaseTriangleInvalid, ToolTriangleInvalid, NoRealSolution };

/// One solution above the base plane.
struct AssemblyModeSolution {
  int mode = 0;                ///< 1..4
  std::array<int, 3> signs{};  ///< Tri side choices
  Cups<double> tool;           ///< t1..t3 (design roles) in the base cups' frame, mm
};

struct DkpResult {
  DkpStatus status = DkpStatus::Ok;
  std::string message;                          ///< what is wrong when status != Ok
  std::vector<AssemblyModeSolution> solutions;  ///< real and above the base plane, by mode

  /// The solution of this assembly mode, or nullptr when it is not real.
  [[nodiscard]] const AssemblyModeSolution* mode(int m) const {
    for (const auto& s : solutions)
      if (s.mode == m) return &s;
    return nullptr;
  }
};

/// Direct kinematics on measured distances (mm). `base` holds b1..b3 in design roles in any
/// frame, `up` the side of the base plane the tool is on (t1 must satisfy (t1 − b1)·up > 0).
/// Checks the tool triangle and the legs (positive, finite) and reports ill-posed inputs in the
/// status instead of throwing.
DkpResult solve_dkp(const Cups<double>& base, const Eigen::Vector3d& up,
                    const TriangleSides& tool_sides, const LegLengths<double>& legs);

/// Convenience: base cups from the measured base sides (b1 at the origin, up = +z), then
/// solve_dkp. The base triangle is checked too.
DkpResult solve_dkp(const TriangleSides& base_sides, const TriangleSides& tool_sides,
                    const LegLengths<double>& legs);

/// The six leg lengths of a configuration (design roles), the inverse of the direct kinematics.
LegLengths<double> leg_lengths(const Cups<double>& base, const Cups<double>& tool);

/// A leg design: which physical cup plays each design role. 6 base permutations × 6 tool
/// permutations = 36 designs; a tool permutation that is odd mirrors the tool triangle's
/// orientation, so only the 18 with a cyclic tool relabelling (a rotation of the fixture by
/// 0, ±120° about its normal) keep the cups facing the base.
struct LegDesign {
  std::array<int, 3> base{0, 1, 2};  ///< design B_i is physical base cup base[i]
  std::array<int, 3> tool{0, 1, 2};  ///< design T_j is physical tool cup tool[j]
  [[nodiscard]] bool tool_mirrored() const;
};

/// The 36 leg designs: base permutations in lexicographic order, for each the tool permutations
/// in lexicographic order.
std::vector<LegDesign> all_leg_designs();

}  // namespace robcal::hexapod
