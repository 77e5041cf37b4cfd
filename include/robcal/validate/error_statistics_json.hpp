#pragma once
/// \file
/// The one JSON form of ErrorStatistics, shared by validate, report and the hexapod end-to-end
/// report: every key carries its unit (`mean_mm`, `std_deg`, ...) so that a reader never has to
/// guess it from the parent key.

#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>

#include "robcal/validate/error_statistics.hpp"

namespace robcal {

/// `s` as {count, mean_<unit>, std_<unit>, mean_plus_3std_<unit>, min_<unit>, max_<unit>}, with
/// `unit` "mm" or "deg"; the numbers rounded to `decimals` places when given, else full precision.
nlohmann::json error_statistics_json(const ErrorStatistics& s, std::string_view unit,
                                     std::optional<int> decimals = std::nullopt);

}  // namespace robcal
