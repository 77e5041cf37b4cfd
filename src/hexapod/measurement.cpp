#include "robcal/hexapod/measurement.hpp"

#include <algorithm>

#include "robcal/core/error.hpp"

namespace robcal::hexapod {

FourCupDkpRequest readings_dkp_request(const FixtureDistances& base, const FixtureDistances& tool,
                                       const LegReadings& r) {
  FourCupDkpRequest request{base.sides, tool.sides, {}};
  for (size_t i = 0; i < kDesignLegs.size(); ++i)
    request.legs.push_back(
        {r.design.base[kDesignLegs[i].base], r.design.tool[kDesignLegs[i].tool], r.legs[i]});
  request.legs.insert(request.legs.end(), r.extra_legs.begin(), r.extra_legs.end());
  // Without a leg to it, a fourth cup's distances fix it only up to a mirror (the solver
  // refuses).
  const auto reached = [&](auto leg_reaches) {
    return std::any_of(r.extra_legs.begin(), r.extra_legs.end(), leg_reaches);
  };
  if (reached([](const MeasuredLeg& l) { return l.tool == 3; })) request.tool.fourth = tool.fourth;
  if (reached([](const MeasuredLeg& l) { return l.base == 3; })) request.base.fourth = base.fourth;
  return request;
}

Pose<double> measured_tool_pose(const FixtureDistances& base_fixture, const FixtureDistances& tool,
                                const LegReadings& r, const std::string& file) {
  const auto refuse = [&](const std::string& why) {
    return InputError({file, 0, 0, r.config}, "configuration " + r.config + ": " + why);
  };
  const Cups<double> base = fixture_cups(base_fixture.sides, "base fixture sides");
  const Cups<double> tool_cups = fixture_cups(tool.sides, "tool fixture sides");
  const DkpResult dkp = solve_dkp(design_base_cups(r.design, base), Eigen::Vector3d::UnitZ(),
                                  design_tool_sides(r.design, tool_cups), r.legs);
  const AssemblyModeSolution* solution = dkp.mode(r.mode);
  if (solution == nullptr)
    throw refuse(dkp.status == DkpStatus::Ok
                     ? "the legs have no solution in assembly mode " + std::to_string(r.mode)
                     : dkp.message);
  const Cups<double> closed_form = physical_tool_cups(r.design, solution->tool);
  if (r.extra_legs.empty()) return frame_from_cups(closed_form);
  // The least-squares solution of the planned mode: the one nearest the mode's closed form (a
  // start of another mode may converge to it first and carry that mode's number).
  const FourCupDkpResult fit = solve_four_cup_dkp(readings_dkp_request(base_fixture, tool, r));
  if (fit.status != FourCupDkpStatus::Ok) throw refuse(fit.message);
  const auto gap = [&](const FourCupSolution& s) {
    double g = 0;
    for (int j = 0; j < 3; ++j) g = std::max(g, (s.tool_cups[j] - closed_form[j]).norm());
    return g;
  };
  const FourCupSolution& nearest = *std::min_element(
      fit.solutions.begin(), fit.solutions.end(),
      [&](const FourCupSolution& a, const FourCupSolution& b) { return gap(a) < gap(b); });
  return frame_from_cups(
      Cups<double>{nearest.tool_cups[0], nearest.tool_cups[1], nearest.tool_cups[2]});
}

MeasurementSet pose_measurements(const FixtureDistances& base, const FixtureDistances& tool,
                                 const std::vector<LegReadings>& readings,
                                 const Pose<double>& robot_T_world, const std::string& file) {
  MeasurementSet set;
  set.kind = MeasurementKind::Poses;
  set.file = file;
  for (const LegReadings& r : readings) {
    PoseMeasurement m;
    m.config = r.config;
    m.joints = r.joints;
    m.world_T_tcp = robot_T_world * measured_tool_pose(base, tool, r, file);
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
