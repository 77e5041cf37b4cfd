#pragma once
// The reference set's true robot as a calibrated robot (world frame known, level "full") with
// the set's tool and the true payload: the validation and report tests' "after" model.

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal::test {

inline CalibratedRobot reference_true_robot() {
  const ReferenceTruth truth = load_reference_truth();
  CalibratedRobot robot =
      CalibratedRobot::nominal(truth.model, load_tool(data_path("irb120-published/tool.yaml")));
  robot.params = truth.params;
  robot.tool.payload = truth.payload;
  robot.base_fitted = true;
  robot.level = "full";
  return robot;
}

}  // namespace robcal::test
