#include "robcal/io/robot_catalogue.hpp"

#include <nlohmann/json.hpp>

#include "robcal/core/rounding.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal {

std::vector<RobotEntry> robot_catalogue() {
  std::vector<RobotEntry> out;
  for (const std::string& name : builtin_robot_names()) {
    const RobotModel model = load_robot(name);
    out.push_back({name, model.name, model.manufacturer, model.reach_mm});
  }
  return out;
}

nlohmann::json robot_catalogue_json(const std::vector<RobotEntry>& entries) {
  nlohmann::json out = nlohmann::json::array();
  for (const RobotEntry& e : entries)
    out.push_back({{"name", e.name},
                   {"model", e.model},
                   {"manufacturer", e.manufacturer},
                   {"reach_mm", e.reach_mm}});
  return out;
}

nlohmann::json robot_description_json(const RobotModel& model) {
  nlohmann::json out = {
      {"name", model.name}, {"manufacturer", model.manufacturer}, {"source", model.source}};
  for (int i = 0; i < kJointCount; ++i) {
    const MdhRow& row = model.mdh[i];
    out["mdh"].push_back({{"link", i + 1},
                          {"alpha_deg", rounded(rad2deg(row.alpha))},
                          {"a_mm", row.a},
                          {"theta_offset_deg", rounded(rad2deg(row.theta_offset))},
                          {"d_mm", row.d}});
    out["joint_limits_deg"].push_back(
        {rounded(rad2deg(model.limits[i].lower)), rounded(rad2deg(model.limits[i].upper))});
    out["link_masses_kg"].push_back(model.link_masses[i].mass_kg);
  }
  out["joint_map_identity"] = model.joint_map.is_identity();
  return out;
}

}  // namespace robcal
