#include "robcal/compensate/compensation_setup.hpp"

#include <fmt/format.h>

#include "robcal/core/error.hpp"

namespace robcal {

Compensation prepare_compensation(const CompensationSetup& setup) {
  CalibratedRobot robot = setup.robot;
  if (!setup.expected_robot.empty() && setup.expected_robot != robot.model.name)
    throw InputError({setup.model_file, 0, 0, "--robot"},
                     fmt::format("the model is a calibrated {}, not a {}", robot.model.name,
                                 setup.expected_robot));
  if (setup.tool) {
    robot.tool.flange_T_tcp = setup.tool->flange_T_tcp;
    robot.tool.payload = setup.tool->payload;
  }
  if (setup.payload) {
    // A payload beyond any industrial arm's rating is a unit mistake (g for kg), not a load.
    if (!(setup.payload->mass_kg >= 0 && setup.payload->mass_kg < 1e4))
      throw InputError({"", 0, 0, "--payload-mass-kg"}, "expected a mass in kg, 0 or more");
    if (!setup.payload->cog_mm.allFinite())
      throw InputError({"", 0, 0, "--payload-cog-mm"},
                       "expected a finite centre of gravity x,y,z in mm");
  }
  Compensation out{robot, make_compensator(robot, setup.payload, &setup.approach),
                   setup.pulses_per_degree};
  return out;
}

IkMethod ik_method_from_name(const std::string& name, const std::string& key) {
  if (name == "newton") return IkMethod::Newton;
  if (name == "pose-shift") return IkMethod::PoseShift;
  throw InputError({"", 0, 0, key}, "expected newton or pose-shift, found '" + name + "'");
}

const char* ik_method_name(IkMethod method) {
  return method == IkMethod::Newton ? "newton" : "pose-shift";
}

}  // namespace robcal
