#pragma once
/// \file
/// Simulated readings of a planned hexapod session (`robcal hexapod simulate-readings`): a true
/// robot and fixtures drawn from the seed for the plan's cell, the ballbar readings in the order
/// the session asks for them, the tool fixture as a tool, and laser-tracker validation points.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robcal/hexapod/plan_file.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/model/robot_model.hpp"
#include "robcal/model/tool.hpp"

namespace robcal::hexapod {

struct SimulatedReadingsRequest {
  std::string plan_file;  ///< where the plan was read from, named in errors
  /// What the true robot carries; empty: 2.6 kg at (50, 25, 100) mm in the flange frame, a
  /// typical tool of the robots the published procedure calibrates.
  std::optional<PointMass> payload;
  uint64_t seed = 1;   ///< of the true robot, the fixtures and the readings
  int validation = 0;  ///< laser-tracker validation configurations (≥ 0)
};

struct SimulatedReadings {
  /// Every answer of the session script in order (mm); nullopt: the leg was out of range.
  std::vector<std::optional<double>> readings;
  int out_of_range = 0;
  Tool tool;  ///< the payload, the plan's tool mount and the true tool sides' cups
  /// Tracker points (σ 0.022 mm) of the SMR in tool cup T1, robot frame of the hexapod's world.
  MeasurementSet validation;
  uint64_t seed = 1;  ///< the request's
};

/// Simulates the session of `plan`. Plans of the same cell and seed (a first pass and its
/// re-plan) see the same true robot and cups. Throws InputError when the plan has no cell or
/// the validation count is negative.
SimulatedReadings simulate_readings(const HexapodPlan& plan, const RobotModel& model,
                                    const SimulatedReadingsRequest& request);

/// The readings as the session reads them on its input: one answer a line
/// (session_answers.hpp).
std::string readings_text(const SimulatedReadings& simulated);

/// The validation points' CSV (io/measurement_file.hpp), its comment naming the instrument and
/// the seed.
std::string validation_csv(const SimulatedReadings& simulated);

/// What `robcal hexapod simulate-readings` reports: {seed, readings (count), legs_out_of_range,
/// out, tool, validation (the files written, "" for none)}.
nlohmann::json simulated_readings_json(const SimulatedReadings& simulated, const std::string& out,
                                       const std::string& tool_out,
                                       const std::string& validation_out);

}  // namespace robcal::hexapod
