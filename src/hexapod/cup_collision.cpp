#include "robcal/hexapod/cup_collision.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "robcal/core/error.hpp"

namespace robcal::hexapod {
namespace {

double segment_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((c - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - c).norm();
}

Eigen::Vector3d open_side(const std::vector<Eigen::Vector3d>& c) {
  return (c[1] - c[0]).cross(c[2] - c[0]).normalized();
}

}  // namespace

std::string cup_collision(const std::vector<Eigen::Vector3d>& base,
                          const std::vector<Eigen::Vector3d>& tool,
                          const std::vector<PhysicalLeg>& legs, const CupClearance& clearance) {
  const double d = clearance.cup_diameter_mm;
  for (size_t j = 0; j < tool.size(); ++j)
    for (size_t i = 0; i < base.size(); ++i)
      if (const double gap = (tool[j] - base[i]).norm(); gap < d)
        return fmt::format(
            "tool cup T{} is {:.1f} mm from base cup B{}, closer than a cup diameter ({} mm): the "
            "cups {}",
            j + 1, gap, i + 1, d, gap < 1e-3 ? "coincide" : "collide");
  const Eigen::Vector3d base_up = open_side(base);
  const Eigen::Vector3d tool_up = open_side(tool);
  for (const PhysicalLeg& leg : legs) {
    const Eigen::Vector3d& b = base[leg.base];
    const Eigen::Vector3d& t = tool[leg.tool];
    const std::string name = fmt::format("leg B{}-T{}", leg.base + 1, leg.tool + 1);
    // Each fixture is a plate with its cups on one face: a ballbar leaving a cup towards the
    // other face goes through the plate.
    if ((t - b).dot(base_up) <= 0)
      return name +
             " crosses the base fixture: the tool cup is on the closed side of the base plane";
    if ((b - t).dot(tool_up) <= 0)
      return name +
             " crosses the tool fixture: the base cup is on the closed side of the tool plane";
    const auto hits = [&](const std::vector<Eigen::Vector3d>& cups, char letter,
                          size_t end) -> std::string {
      for (size_t k = 0; k < cups.size(); ++k)
        if (k != end)
          if (const double gap = segment_distance(b, t, cups[k]); gap < d / 2)
            return fmt::format("{} passes {:.1f} mm from cup {}{}, within a cup radius ({} mm)",
                               name, gap, letter, k + 1, d / 2);
      return {};
    };
    if (std::string hit = hits(base, 'B', leg.base); !hit.empty()) return hit;
    if (std::string hit = hits(tool, 'T', leg.tool); !hit.empty()) return hit;
  }
  return {};
}

PoseScreening screen_poses(const std::vector<HexapodPose>& poses, const HexapodGeometry& geometry,
                           double max_angle_rad, double max_distance_mm,
                           const CupClearance& clearance) {
  if (!std::isfinite(clearance.cup_diameter_mm) || clearance.cup_diameter_mm <= 0)
    throw InputError(
        {"", 0, 0, "--cup-diameter-mm (cup_diameter_mm)"},
        fmt::format("expected a positive cup diameter in mm, found {}", clearance.cup_diameter_mm));
  fixture_cups(geometry.base, "base fixture");
  const std::vector<Eigen::Vector3d> base_cups = base_cup_positions(geometry);
  const auto check_fourth = [&](const std::optional<std::array<double, 3>>& distances, char letter,
                                const char* flag) {
    if (!distances) return;
    for (int j = 0; j < 3; ++j)
      if (const double gap = (*distances)[j]; gap < clearance.cup_diameter_mm)
        throw InputError(
            {"", 0, 0, flag},
            fmt::format("{} cup {}4 is {} mm from {}{}, closer than a cup diameter "
                        "({} mm): the cups {}",
                        letter == 'T' ? "tool" : "base", letter, gap, letter, j + 1,
                        clearance.cup_diameter_mm, gap < 1e-3 ? "coincide" : "collide"));
  };
  check_fourth(geometry.tool_cup4_mm, 'T', "--tool-cup4-mm");
  check_fourth(geometry.base_cup4_mm, 'B', "--base-cup4-mm");
  PoseScreening out;
  std::vector<HexapodPose> possible;
  for (const HexapodPose& pose : poses) {
    const std::vector<Eigen::Vector3d> tool = pose_tool_cups(pose, geometry);
    if (std::string reason = cup_collision(base_cups, tool, pose.legs, clearance); !reason.empty())
      out.refused.push_back({pose, std::move(reason)});
    else
      possible.push_back(pose);
  }
  out.kept = prune_redundant(possible, max_angle_rad, max_distance_mm);
  return out;
}

}  // namespace robcal::hexapod
