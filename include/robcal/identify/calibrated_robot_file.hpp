#pragma once
/// \file
/// A calibrated model file's text read without the file (Python's CalibratedRobot.from_dict):
/// the reader of load_calibrated_robot (calibrated_robot.hpp) on text.

#include <string>

#include "robcal/identify/calibrated_robot.hpp"

namespace robcal {

/// A calibrated model file's text (YAML, or JSON: a YAML subset) read as load_calibrated_robot
/// reads the file; errors name `source` with the line and key.
CalibratedRobot parse_calibrated_robot(const std::string& text, const std::string& source);

}  // namespace robcal
