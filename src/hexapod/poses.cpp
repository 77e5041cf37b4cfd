#include "robcal/hexapod/poses.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/hexapod/fixture.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::hexapod {
namespace {

/// A fourth cup's distances: solvable, and reproduced by the trilaterated position (d14 and d24
/// are by construction, d34 only when a point has all three). `flag` names the setting.
void check_fourth_cup(const FixtureDistances& fixture, const std::string& what, char letter,
                      const std::string& flag) {
  if (const std::string problem = fixture_problem(fixture, what); !problem.empty())
    throw InputError({"", 0, 0, flag}, problem);
  const std::vector<Eigen::Vector3d> cups = fixture_cup_positions(fixture);
  const std::array<double, 3>& d = *fixture.fourth;
  const double d34 = (cups[3] - cups[2]).norm();
  if (std::abs(d34 - d[2]) > 1e-3)
    throw InputError({"", 0, 0, flag},
                     fmt::format("no point is {} mm from {}1 and {} mm from {}2 and {} mm from {}3 "
                                 "(the nearest in the fixture plane is {:.3f} mm from {}3)",
                                 d[0], letter, d[1], letter, d[2], letter, d34, letter));
}

}  // namespace

std::string PhysicalLeg::name() const {
  return fmt::format("B{}-T{}", base + 1, tool + 1);
}

std::string HexapodPose::description() const {
  return fmt::format("mode {}, tool {:+}°{}, base B{} B{} B{}", mode, rotation_deg,
                     design.tool_mirrored() ? " mirrored" : "", design.base[0] + 1,
                     design.base[1] + 1, design.base[2] + 1);
}

Cups<double> physical_tool_cups(const LegDesign& design, const Cups<double>& design_tool) {
  Cups<double> physical;
  for (int j = 0; j < 3; ++j) physical[design.tool[j]] = design_tool[j];
  return physical;
}

Cups<double> design_base_cups(const LegDesign& design, const Cups<double>& physical_base) {
  return {physical_base[design.base[0]], physical_base[design.base[1]],
          physical_base[design.base[2]]};
}

TriangleSides design_tool_sides(const LegDesign& design, const Cups<double>& physical_tool) {
  const auto d = [&](int i, int j) {
    return (physical_tool[design.tool[i]] - physical_tool[design.tool[j]]).norm();
  };
  return {d(0, 1), d(1, 2), d(2, 0)};
}

std::optional<Cups<double>> planned_tool_cups(const Cups<double>& base, const Cups<double>& tool,
                                              const LegDesign& design, int mode, double leg_mm) {
  LegLengths<double> legs;
  legs.fill(leg_mm);
  const DkpResult dkp = solve_dkp(design_base_cups(design, base), Eigen::Vector3d::UnitZ(),
                                  design_tool_sides(design, tool), legs);
  const AssemblyModeSolution* solution = dkp.mode(mode);
  if (solution == nullptr) return std::nullopt;
  return physical_tool_cups(design, solution->tool);
}

std::optional<LegDesign> design_of_legs(const std::vector<PhysicalLeg>& legs) {
  if (legs.size() < kDesignLegs.size()) return std::nullopt;
  // Roles as in kDesignLegs: B1 of ρ11, B2 of ρ21, B3 of ρ31; T1 of ρ11, T2 of ρ12, T3 of ρ23.
  const LegDesign design{{legs[0].base, legs[2].base, legs[5].base},
                         {legs[0].tool, legs[1].tool, legs[4].tool}};
  for (const std::array<int, 3>& roles : {design.base, design.tool})
    if (!std::is_permutation(roles.begin(), roles.end(), std::array<int, 3>{0, 1, 2}.begin()))
      return std::nullopt;
  for (size_t i = 0; i < kDesignLegs.size(); ++i)
    if (legs[i].base != design.base[kDesignLegs[i].base] ||
        legs[i].tool != design.tool[kDesignLegs[i].tool])
      return std::nullopt;
  return design;
}

std::vector<HexapodPose> enumerate_poses(const HexapodGeometry& geometry,
                                         ToolRelabelling relabelling) {
  const Cups<double> base = fixture_cups(geometry.base, "base fixture");
  const Cups<double> tool = fixture_cups(geometry.tool, "tool fixture");
  // Cyclic relabellings of the tool cups: design T1 is physical cup shift+1. Turning the fixture
  // by −120° about its normal brings T2 where T1 was.
  static constexpr std::array<int, 3> kRotationDeg{0, -120, 120};
  std::vector<HexapodPose> poses;
  for (int mode = 1; mode <= 4; ++mode)
    for (int shift = 0; shift < 3; ++shift) {
      std::array<int, 3> perm{0, 1, 2};
      do {
        LegDesign design{perm, {shift, (shift + 1) % 3, (shift + 2) % 3}};
        std::optional<Cups<double>> cups =
            planned_tool_cups(base, tool, design, mode, geometry.leg_mm);
        const auto faces_base = [&] {
          return (centroid(base) - centroid(*cups)).dot(frame_from_cups(*cups).R.col(2)) > 0;
        };
        if (cups && relabelling == ToolRelabelling::FacingBase && !faces_base()) {
          std::swap(design.tool[1], design.tool[2]);  // the mirrored numbering, same T1
          cups = planned_tool_cups(base, tool, design, mode, geometry.leg_mm);
          if (cups && !faces_base()) continue;
        }
        if (!cups) continue;
        HexapodPose pose;
        pose.index = static_cast<int>(poses.size()) + 1;
        pose.label = fmt::format("P{:02d}", pose.index);
        pose.mode = mode;
        pose.rotation_deg = kRotationDeg[shift];
        pose.design = design;
        pose.tool_cups = *cups;
        pose.base_T_tool = frame_from_cups(pose.tool_cups);
        for (const LegRoles& roles : kDesignLegs)
          pose.legs.push_back({design.base[roles.base], design.tool[roles.tool]});
        poses.push_back(pose);
      } while (std::next_permutation(perm.begin(), perm.end()));
    }
  return poses;
}

std::vector<HexapodPose> prune_redundant(const std::vector<HexapodPose>& poses,
                                         double max_angle_rad, double max_distance_mm) {
  std::vector<HexapodPose> kept;
  for (const HexapodPose& pose : poses) {
    const bool redundant = std::any_of(kept.begin(), kept.end(), [&](const HexapodPose& k) {
      return rotation_distance(k.base_T_tool.R, pose.base_T_tool.R) < max_angle_rad &&
             (centroid(k.tool_cups) - centroid(pose.tool_cups)).norm() < max_distance_mm;
    });
    if (!redundant) kept.push_back(pose);
  }
  return kept;
}

std::vector<Eigen::Vector3d> pose_tool_cups(const HexapodPose& pose,
                                            const HexapodGeometry& geometry) {
  std::vector<Eigen::Vector3d> cups(pose.tool_cups.begin(), pose.tool_cups.end());
  if (geometry.tool_cup4_mm)
    cups.push_back(pose.base_T_tool * fixture_cup_positions(geometry.tool_fixture())[3]);
  return cups;
}

std::vector<Eigen::Vector3d> base_cup_positions(const HexapodGeometry& geometry) {
  return fixture_cup_positions(geometry.base_fixture());
}

void add_fourth_cup_legs(std::vector<HexapodPose>& poses, const HexapodGeometry& geometry,
                         double tolerance_mm) {
  if (!geometry.tool_cup4_mm && !geometry.base_cup4_mm) return;
  const std::vector<Eigen::Vector3d> base = base_cup_positions(geometry);
  for (HexapodPose& pose : poses) {
    const std::vector<Eigen::Vector3d> tool = pose_tool_cups(pose, geometry);
    const auto add_if_in_reach = [&](int b, int t) {
      if (std::abs((base[b] - tool[t]).norm() - geometry.leg_mm) <= tolerance_mm)
        pose.legs.push_back({b, t});
    };
    if (geometry.tool_cup4_mm)
      for (int b = 0; b < 3; ++b) add_if_in_reach(b, 3);
    if (geometry.base_cup4_mm)
      for (int t = 0; t < static_cast<int>(tool.size()); ++t) add_if_in_reach(3, t);
  }
}

void check_geometry(const HexapodGeometry& geometry) {
  fixture_cups(geometry.base, "--base-mm");
  fixture_cups(geometry.tool, "--tool-mm");
  if (geometry.tool_cup4_mm)
    check_fourth_cup(geometry.tool_fixture(), "tool fixture", 'T', "--tool-cup4-mm");
  if (geometry.base_cup4_mm)
    check_fourth_cup(geometry.base_fixture(), "base fixture", 'B', "--base-cup4-mm");
  if (!(geometry.leg_mm > 0) || !std::isfinite(geometry.leg_mm))
    throw InputError({"", 0, 0, "--leg-mm"}, "expected a positive length in mm");
}

}  // namespace robcal::hexapod
