#pragma once
/// \file
/// Encoder pulses per degree of a robot's joints: Yaskawa jobs store joint positions in pulses.
/// A robot file may give them as `pulses_per_degree: [p1, ..., p6]` (six numbers, > 0 and below
/// 1e7, checked whenever the file is read); they are not part of the kinematic model.

#include <array>
#include <string>

#include "robcal/model/robot_model.hpp"

namespace robcal {

/// The pulses per degree of a built-in robot or robot file; all zero when it gives none.
/// InputError (file, line, column, key) as load_robot.
std::array<double, kJointCount> robot_pulses_per_degree(const std::string& name_or_path);

}  // namespace robcal
