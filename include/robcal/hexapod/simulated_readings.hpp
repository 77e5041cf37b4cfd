#pragma once
/// \file
/// Simulated readings of a planned hexapod session (`robcal hexapod simulate-readings`): a true
/// robot and fixtures drawn from the seed for the plan's cell, the ballbar readings in the order
/// the session asks for them, the tool fixture as a tool, and laser-tracker validation points.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "robcal/hexapod/plan_file.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/model/robot_model.hpp"
#include "robcal/model/tool.hpp"

namespace robcal::hexapod {

struct SimulatedReadings {
  /// Every answer of the session script in order (mm); nullopt: the leg was out of range.
  std::vector<std::optional<double>> readings;
  int out_of_range = 0;
  Tool tool;  ///< the payload, the plan's tool mount and the true tool sides' cups
  /// Tracker points (σ 0.022 mm) of the SMR in tool cup T1, robot frame of the hexapod's world.
  MeasurementSet validation;
};

/// Simulates the session of `plan` (read from `plan_file`, named in errors). Plans of the same
/// cell and seed (a first pass and its re-plan) see the same true robot and cups. Throws
/// InputError when the plan has no cell or `validation` is negative.
SimulatedReadings simulate_readings(const HexapodPlan& plan, const std::string& plan_file,
                                    const RobotModel& model, const PointMass& payload,
                                    uint64_t seed, int validation);

/// The readings as the session reads them on its input: one number or "out" per line.
std::string readings_text(const SimulatedReadings& simulated);

}  // namespace robcal::hexapod
