#include "robcal/validate/error_statistics.hpp"

#include <algorithm>
#include <cmath>

namespace robcal {

ErrorStatistics error_statistics(std::span<const double> errors) {
  ErrorStatistics stats;
  if (errors.empty()) return stats;
  stats.count = errors.size();
  const auto [min, max] = std::minmax_element(errors.begin(), errors.end());
  stats.min = *min;
  stats.max = *max;
  double sum = 0;
  for (double e : errors) sum += e;
  stats.mean = sum / static_cast<double>(errors.size());
  double squares = 0;
  for (double e : errors) squares += (e - stats.mean) * (e - stats.mean);
  stats.std = std::sqrt(squares / static_cast<double>(errors.size()));
  return stats;
}

}  // namespace robcal
