#pragma once
/// \file
/// A calibrated model file's text read without the file (Python's CalibratedRobot.from_dict):
/// the reader of load_calibrated_robot (calibrated_robot.hpp) on text; and written with its
/// statistics written straight into the file's emitter (no YAML text built and parsed again).

#include <functional>
#include <string>

#include "robcal/identify/calibrated_robot.hpp"

namespace YAML {  // NOLINT(readability-identifier-naming): yaml-cpp's namespace
class Emitter;
}

namespace robcal {

/// Writes one YAML value (a map) into the model file's emitter.
using YamlWriter = std::function<void(YAML::Emitter&)>;

/// Significant digits of the file's numbers: exact (round trip) for the parameters and every
/// number a writer does not round; the fit statistics are written to kStatisticsDigits.
inline constexpr int kExactDigits = 17;
inline constexpr int kStatisticsDigits = 9;

/// calibrated_robot_to_yaml with the statistics that `statistics` writes (without it, the
/// robot's own as read), followed in `reidentified` by the record `new_record` writes if given.
std::string calibrated_robot_to_yaml(const CalibratedRobot& robot, const YamlWriter& statistics,
                                     const YamlWriter& new_record = {});

/// A calibrated model file's text (YAML, or JSON: a YAML subset) read as load_calibrated_robot
/// reads the file; errors name `source` with the line and key.
CalibratedRobot parse_calibrated_robot(const std::string& text, const std::string& source);

}  // namespace robcal
