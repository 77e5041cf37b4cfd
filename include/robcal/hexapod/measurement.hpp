#pragma once
/// \file
/// From hexapod readings to the records the identification uses (docs/method/07-hexapod.md §6): the
/// six legs of each measured configuration → direct kinematics in the planned assembly mode → the
/// tool fixture pose in the base fixture (world) frame → a `Poses` MeasurementSet whose TCP is the
/// tool fixture frame (Tool::flange_T_tcp = the fixture-to-flange transform, an input).
///
/// Frame of the records: the robot frame of the relative model (docs/method/03-error-model.md §1;
/// base parameters held at zero), reached from the world frame through the base cups: robot_T_world
/// is the world frame fitted to the points where the robot placed the cups (world_frame.hpp).

#include <string>
#include <vector>

#include "robcal/hexapod/four_cup_kinematics.hpp"
#include "robcal/hexapod/poses.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/model/tool.hpp"

namespace robcal::hexapod {

/// One measured configuration: which pose (leg design and assembly mode) and the six readings.
struct LegReadings {
  std::string config;                  ///< configuration label
  Vector6d joints = Vector6d::Zero();  ///< controller joints, rad
  LegDesign design;                    ///< physical cups in the design roles
  int mode = 1;                        ///< planned assembly mode
  LegLengths<double> legs{};           ///< ρ11, ρ12, ρ21, ρ22, ρ23, ρ31 in design roles, mm
  std::vector<MeasuredLeg> extra_legs{};  ///< beyond the design (physical cups): fourth cups'
};

/// The tool fixture frame (cups 1..3) in the base fixture frame from one configuration's readings,
/// or an InputError naming `file` and the configuration when the distances have no solution in
/// its mode. With extra legs, the over-determined DKP in least squares (four_cup_kinematics.hpp)
/// on every leg and the fixture distances, a fourth cup's included when a leg reaches it;
/// otherwise the closed-form cascade on B1..B3 and T1..T3.
Pose<double> measured_tool_pose(const FixtureDistances& base, const FixtureDistances& tool,
                                const LegReadings& readings, const std::string& file = "");

/// The over-determined DKP request of one configuration's readings (its design legs as physical
/// legs, then the extra ones; a fourth cup's distances only when a leg reaches it).
FourCupDkpRequest readings_dkp_request(const FixtureDistances& base, const FixtureDistances& tool,
                                       const LegReadings& readings);

/// Poses MeasurementSet (world_T_tcp expressed in the robot frame through `robot_T_world`) from
/// every configuration's readings; `file` names the source in messages.
MeasurementSet pose_measurements(const FixtureDistances& base, const FixtureDistances& tool,
                                 const std::vector<LegReadings>& readings,
                                 const Pose<double>& robot_T_world, const std::string& file);

/// The tool for those records: `payload`, the tool fixture as TCP (`flange_T_tool`), and the three
/// tool cups as known targets "T1".."T3" (flange frame).
Tool hexapod_tool(const PointMass& payload, const Pose<double>& flange_T_tool,
                  const TriangleSides& tool_sides);

}  // namespace robcal::hexapod
