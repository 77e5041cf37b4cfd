#pragma once
/// \file
/// The robot library as `robcal robots` and `robcal robot show` list it, and Python's
/// robot_catalogue / robot_description: one serializer per listing.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "robcal/model/robot_model.hpp"

namespace robcal {

struct RobotEntry {
  std::string name;  ///< the built-in name (file stem)
  std::string model;
  std::string manufacturer;
  double reach_mm = 0;  ///< 0: not given in the file
};

/// Every built-in robot, loaded (a broken robot file throws InputError naming it).
std::vector<RobotEntry> robot_catalogue();

/// [{name, model, manufacturer, reach_mm}].
nlohmann::json robot_catalogue_json(const std::vector<RobotEntry>& entries);

/// {name, manufacturer, source, mdh: [{link, alpha_deg, a_mm, theta_offset_deg, d_mm}],
/// joint_limits_deg: [[lower, upper]…], link_masses_kg, joint_map_identity}, angles rounded
/// to 1e-9 deg.
nlohmann::json robot_description_json(const RobotModel& model);

}  // namespace robcal
