#include "robcal/identify/calibrated_robot.hpp"

namespace robcal {

CalibratedRobot CalibratedRobot::nominal(const RobotModel& model, const Tool& tool) {
  CalibratedRobot robot;
  robot.model = model;
  robot.params = model.nominal();
  robot.status.fill(ParameterStatus::Fixed);
  robot.tool = tool;
  robot.level = "nominal";
  return robot;
}

}  // namespace robcal
