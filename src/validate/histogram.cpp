#include "robcal/validate/histogram.hpp"

#include <fmt/format.h>

#include <numeric>
#include <stdexcept>

namespace robcal {

uint64_t Histogram::total() const {
  return std::accumulate(counts.begin(), counts.end(), uint64_t{0});
}

Histogram make_histogram(std::span<const double> values, int bins, double lower, double upper) {
  if (bins < 1 || !(upper > lower))
    throw std::invalid_argument(
        fmt::format("histogram needs bins >= 1 and upper > lower, got {} bins over [{}, {})", bins,
                    lower, upper));
  Histogram h{lower, upper, std::vector<uint64_t>(static_cast<size_t>(bins), 0)};
  const double scale = bins / (upper - lower);
  for (double v : values) ++h.counts[static_cast<size_t>(histogram_bin(v, lower, scale, bins))];
  return h;
}

Histogram merge_bins(const Histogram& histogram, int factor) {
  const size_t n = histogram.counts.size();
  if (factor < 1 || n % static_cast<size_t>(factor) != 0)
    throw std::invalid_argument(
        fmt::format("merge_bins: factor {} does not divide {} bins", factor, n));
  Histogram merged{histogram.lower, histogram.upper,
                   std::vector<uint64_t>(n / static_cast<size_t>(factor), 0)};
  for (size_t i = 0; i < n; ++i)
    merged.counts[i / static_cast<size_t>(factor)] += histogram.counts[i];
  return merged;
}

std::string histogram_text(const Histogram& histogram, std::string_view unit, int bar_width) {
  const uint64_t total = histogram.total();
  if (total == 0) return "  (no values)\n";
  const uint64_t fullest = *std::max_element(histogram.counts.begin(), histogram.counts.end());
  size_t last = histogram.counts.size();
  while (last > 0 && histogram.counts[last - 1] == 0) --last;
  // Enough decimals to tell neighbouring bin edges apart.
  const double width = histogram.bin_width();
  const int decimals = std::clamp(static_cast<int>(std::ceil(-std::log10(width))) + 1, 1, 9);
  std::string out;
  for (size_t i = 0; i < last; ++i) {
    const double from = histogram.lower + width * static_cast<double>(i);
    const uint64_t count = histogram.counts[i];
    const int bar = static_cast<int>(
        std::lround(static_cast<double>(count) * bar_width / static_cast<double>(fullest)));
    out += fmt::format("  {:>{}.{}f} – {:>{}.{}f} {} |{:<{}}| {:>10}  {:5.1f}%\n", from,
                       decimals + 5, decimals, from + width, decimals + 5, decimals, unit,
                       std::string(static_cast<size_t>(bar), '#'), bar_width, count,
                       100.0 * static_cast<double>(count) / static_cast<double>(total));
  }
  return out;
}

}  // namespace robcal
