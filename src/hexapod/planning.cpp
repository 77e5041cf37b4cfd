#include "robcal/hexapod/planning.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "robcal/campaign/feasibility.hpp"
#include "robcal/core/error.hpp"

namespace robcal::hexapod {

Pose<double> default_tool_mount(const TriangleSides& tool_sides, double offset_mm) {
  const Cups<double> cups = fixture_cups(tool_sides, "tool fixture");
  Pose<double> flange_T_tool;
  flange_T_tool.p = Eigen::Vector3d(0, 0, offset_mm) - centroid(cups);
  return flange_T_tool;
}

Pose<double> workcell_T_robot(const RobotModel& model, const campaign::Cell& workcell) {
  // Only the base parameters differ: the flange poses at any joints differ by the base transform.
  const Vector6d zero = Vector6d::Zero();
  return flange_pose(model, PointMass{}, workcell.robot_params(model), zero) *
         flange_pose(model, PointMass{}, model.nominal(), zero).inverse();
}

std::string base_fixture_in_workcell(const RobotModel& model, const campaign::Cell& workcell,
                                     const std::vector<Eigen::Vector3d>& base_cups_robot) {
  const Pose<double> world_T_robot = workcell_T_robot(model, workcell);
  for (size_t i = 0; i < base_cups_robot.size(); ++i) {
    const Eigen::Vector3d p = world_T_robot * base_cups_robot[i];
    if (p.z() < workcell.floor_z_mm)
      return fmt::format(
          "base cup B{} at z = {:.1f} mm (cell world) is below the floor of {} ({} "
          "mm)",
          i + 1, p.z(), workcell.file, workcell.floor_z_mm);
    for (const campaign::KeepOutBox& box : workcell.keep_out)
      if (campaign::segment_box_distance(p, p, box) <= 0)
        return fmt::format(
            "base cup B{} ({:.1f}, {:.1f}, {:.1f} mm, cell world) is inside the "
            "keep-out box '{}' of {}",
            i + 1, p.x(), p.y(), p.z(), box.name, workcell.file);
  }
  return {};
}

Clearance check_clearance(const RobotModel& model, const CellSetup& cell,
                          const std::vector<Eigen::Vector3d>& base_cups_robot,
                          const Vector6d& joints) {
  const ParameterVector params = model.nominal();
  const auto frames = link_frames(model, PointMass{}, params.data(), joints.data());
  // The arm as a polyline: shoulder (Φ2), elbow (Φ3), wrist centre (Φ5), flange (Φ6).
  const std::array<Eigen::Vector3d, 4> joints_xyz{frames[1].p, frames[2].p, frames[4].p,
                                                  frames[5].p};
  for (int i = 1; i < 4; ++i)
    if (joints_xyz[i].z() < cell.table_z_mm + cell.table_clearance_mm) return Clearance::Table;
  const Pose<double> base_T_robot = cell.robot_T_base.inverse();
  Cups<double> cups_fixture;
  for (int i = 0; i < 3; ++i) cups_fixture[i] = base_T_robot * base_cups_robot[i];
  const Eigen::Vector3d c = centroid(cups_fixture);
  double radius = 0;
  for (const auto& cup : base_cups_robot)
    radius = std::max(radius, (base_T_robot * cup - c).head<2>().norm());
  radius += cell.fixture_margin_mm;
  constexpr int kSamples = 24;
  for (int i = 0; i + 1 < 4; ++i)
    for (int k = 0; k <= kSamples; ++k) {
      const Eigen::Vector3d x =
          base_T_robot *
          (joints_xyz[i] + (joints_xyz[i + 1] - joints_xyz[i]) * (double(k) / kSamples));
      if (x.z() < c.z() + cell.fixture_margin_mm && (x - c).head<2>().norm() < radius)
        return Clearance::BaseFixture;
    }
  if (cell.workcell) {
    Tool tool;
    for (int i = 0; i < 3; ++i)
      tool.targets.push_back({fmt::format("T{}", i + 1), cell.tool_cups_flange[i], true});
    switch (campaign::check_configuration(*cell.workcell, model, tool, joints).reason) {
      case campaign::Rejection::JointLimits:  // the IK solutions are within the limits already
      case campaign::Rejection::BelowFloor:
      case campaign::Rejection::Collision:
        return Clearance::Workcell;
      default:  // measurable, or a line-of-sight reason that the ballbar does not have
        break;
    }
  }
  return Clearance::Ok;
}

PlanSummary plan_poses(const RobotModel& model, const CellSetup& cell,
                       const Cups<double>& base_cups_fixture, const std::vector<HexapodPose>& poses,
                       const std::optional<Eigen::Vector3d>& base_cup4_fixture) {
  std::string why_not;
  const auto geometry = analyze_ortho_parallel(model, &why_not);
  if (!geometry)
    throw InputError({"", 0, 0, "robot"},
                     model.name + " has no closed-form inverse kinematics: " + why_not);
  std::vector<Eigen::Vector3d> cups_robot;
  for (const Eigen::Vector3d& cup : base_cups_fixture)
    cups_robot.push_back(cell.robot_T_base * cup);
  if (base_cup4_fixture) cups_robot.push_back(cell.robot_T_base * *base_cup4_fixture);
  const Pose<double> tool_T_flange = cell.flange_T_tool.inverse();
  PlanSummary summary;
  for (const HexapodPose& pose : poses) {
    PosePlan plan;
    plan.pose = pose;
    plan.robot_T_flange = cell.robot_T_base * pose.base_T_tool * tool_T_flange;
    const IkResult ik = nominal_ik(*geometry, plan.robot_T_flange);
    plan.ik_status = ik.status;
    // One configuration per arm branch: of the equivalent turns of wide-range joints, the one
    // closest to the joints' zero (the same arm shape, so the same clearance).
    std::array<const IkSolution*, 8> best{};
    for (const IkSolution& s : ik) {
      const IkSolution*& b = best[s.config.index()];
      if (b == nullptr || s.joints.cwiseAbs().sum() < b->joints.cwiseAbs().sum()) b = &s;
    }
    for (const IkSolution* s : best) {
      if (s == nullptr) continue;
      switch (check_clearance(model, cell, cups_robot, s->joints)) {
        case Clearance::Table:
          ++plan.rejected_table;
          break;
        case Clearance::BaseFixture:
          ++plan.rejected_fixture;
          break;
        case Clearance::Workcell:
          ++plan.rejected_workcell;
          break;
        case Clearance::Ok:
          plan.configurations.push_back({s->joints, s->config});
          break;
      }
    }
    summary.measurable_poses += plan.configurations.empty() ? 0 : 1;
    summary.configurations += static_cast<int>(plan.configurations.size());
    summary.poses.push_back(std::move(plan));
  }
  return summary;
}

}  // namespace robcal::hexapod
