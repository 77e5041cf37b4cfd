#pragma once
/// \file
/// Fixed-range histograms of errors and their text rendering for terminals.

#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace robcal {

/// Counts over [lower, upper) in equal bins. Values below `lower` count in the first bin and
/// values at or above `upper` in the last, so the counts always sum to the number of values.
struct Histogram {
  double lower = 0;
  double upper = 1;
  std::vector<uint64_t> counts;

  [[nodiscard]] double bin_width() const {
    return (upper - lower) / static_cast<double>(counts.size());
  }
  [[nodiscard]] uint64_t total() const;
};

/// The bin of `value`: floor((value − lower) · scale) clamped to [0, bins − 1], with
/// scale = bins / (upper − lower). Shared by every histogram so that bins agree bit for bit.
inline int histogram_bin(double value, double lower, double scale, int bins) {
  const double position = (value - lower) * scale;
  if (!(position > 0)) return 0;
  return position >= bins ? bins - 1 : static_cast<int>(position);
}

/// Histogram of `values` with `bins` bins over [lower, upper) (upper > lower, bins ≥ 1).
Histogram make_histogram(std::span<const double> values, int bins, double lower, double upper);

/// Adds up groups of `factor` neighbouring bins; `factor` must divide the number of bins.
Histogram merge_bins(const Histogram& histogram, int factor);

/// One line per bin, "  0.0100 – 0.0200 mm |########            |   123  12.3%", bars scaled
/// to the fullest bin; empty bins after the last non-empty one are left out.
std::string histogram_text(const Histogram& histogram, std::string_view unit, int bar_width = 40);

}  // namespace robcal
