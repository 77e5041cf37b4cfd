#include "robcal/validate/error_statistics_json.hpp"

#include <string>

#include "robcal/core/rounding.hpp"

namespace robcal {

nlohmann::json error_statistics_json(const ErrorStatistics& s, std::string_view unit,
                                     std::optional<int> decimals) {
  const auto number = [&](double v) { return rounded_if(v, decimals); };
  const auto key = [&](std::string_view name) {
    return std::string(name) + "_" + std::string(unit);
  };
  return {{"count", s.count},          {key("mean"), number(s.mean)},
          {key("std"), number(s.std)}, {key("mean_plus_3std"), number(s.mean_plus_3std())},
          {key("min"), number(s.min)}, {key("max"), number(s.max)}};
}

}  // namespace robcal
