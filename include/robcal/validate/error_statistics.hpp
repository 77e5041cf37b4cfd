#pragma once
/// \file
/// Summary statistics of absolute errors as the published validation tables give them
/// (docs/method/09-validation.md §1): mean, standard deviation, mean + 3·std, minimum and maximum.

#include <cstdint>
#include <span>

namespace robcal {

struct ErrorStatistics {
  uint64_t count = 0;
  double mean = 0;
  double std = 0;  ///< population standard deviation (divides by count, like numpy.std)
  double min = 0;
  double max = 0;
  /// The published "mean + 3σ" accuracy figure.
  [[nodiscard]] double mean_plus_3std() const { return mean + 3 * std; }
};

/// Statistics of `errors` (two passes: mean, then squared deviations). All zero when empty.
ErrorStatistics error_statistics(std::span<const double> errors);

}  // namespace robcal
