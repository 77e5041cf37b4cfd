#include "robcal/hexapod/measurement.hpp"

#include "robcal/core/error.hpp"

namespace robcal::hexapod {

Pose<double> measured_tool_pose(const TriangleSides& base_sides, const TriangleSides& tool_sides,
                                const LegReadings& r, const std::string& file) {
  const Cups<double> base = fixture_cups(base_sides, "base fixture sides");
  const Cups<double> tool = fixture_cups(tool_sides, "tool fixture sides");
  const DkpResult dkp = solve_dkp(design_base_cups(r.design, base), Eigen::Vector3d::UnitZ(),
                                  design_tool_sides(r.design, tool), r.legs);
  const AssemblyModeSolution* solution = dkp.mode(r.mode);
  if (solution == nullptr)
    throw InputError(
        {file, 0, 0, r.config},
        "configuration " + r.config + ": " +
            (dkp.status == DkpStatus::Ok
                 ? "the legs have no solution in assembly mode " + std::to_string(r.mode)
                 : dkp.message));
  return frame_from_cups(physical_tool_cups(r.design, solution->tool));
}

MeasurementSet pose_measurements(const TriangleSides& base_sides, const TriangleSides& tool_sides,
                                 const std::vector<LegReadings>& readings,
                                 const Pose<double>& robot_T_world, const std::string& file) {
  MeasurementSet set;
  set.kind = MeasurementKind::Poses;
  set.file = file;
  for (const LegReadings& r : readings) {
    PoseMeasurement m;
    m.config = r.config;
    m.joints = r.joints;
    m.world_T_tcp = robot_T_world * measured_tool_pose(base_sides, tool_sides, r, file);
    set.poses.push_back(m);
  }
  return set;
}

Tool hexapod_tool(const PointMass& payload, const Pose<double>& flange_T_tool,
                  const TriangleSides& tool_sides) {
  Tool tool;
  tool.payload = payload;
  tool.flange_T_tcp.linear() = flange_T_tool.R;
  tool.flange_T_tcp.translation() = flange_T_tool.p;
  const Cups<double> cups = fixture_cups(tool_sides, "tool fixture sides");
  for (int j = 0; j < 3; ++j)
    tool.targets.push_back({"T" + std::to_string(j + 1), flange_T_tool * cups[j], true});
  return tool;
}

}  // namespace robcal::hexapod
