#include "robcal/identify/parameter_csv.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

namespace robcal {

std::string parameter_table_csv(const CalibratedRobot& robot) {
  std::string csv = "name,unit,nominal,value,std,status\n";
  // Link 1's row is the model's (its placement errors are the base parameters').
  const MdhRow& link1 = robot.model.mdh[0];
  const double deg = 180 / std::numbers::pi;
  for (const auto& [name, unit, value] :
       {std::tuple{"link1.alpha", "deg", link1.alpha * deg}, std::tuple{"link1.a", "mm", link1.a},
        std::tuple{"link1.theta", "deg", link1.theta_offset * deg},
        std::tuple{"link1.d", "mm", link1.d}})
    csv += fmt::format("{},{},{},{},0,fixed\n", name, unit, value, value);
  std::array<bool, kParameterCount> shown;
  shown.fill(true);
  const std::vector<GroupSignificance> groups = group_significance(robot);
  for (size_t g = 0; g < groups.size(); ++g)
    for (int i : opt_in_groups()[g].params) shown[static_cast<size_t>(i)] = groups[g].enabled;
  const ParameterVector nominal = robot.model.nominal();
  const bool has_covariance = robot.covariance.rows() == kParameterCount;
  const auto& table = parameter_table();
  for (int i = 0; i < kParameterCount; ++i) {
    const auto s = static_cast<size_t>(i);
    if (!shown[s]) continue;
    const double f = table[s].to_external();
    const double variance = has_covariance ? std::max(0.0, robot.covariance(i, i)) : 0.0;
    csv += fmt::format("{},{},{},{},{},{}\n", table[s].name, table[s].unit, nominal[i] * f,
                       robot.params[i] * f, std::sqrt(variance) * f, status_name(robot.status[s]));
  }
  return csv;
}

}  // namespace robcal
