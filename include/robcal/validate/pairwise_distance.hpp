#pragma once
/// \file
/// Distance errors over every pair of validation rows (docs/method/09-validation.md §2):
/// e_ij = | |m_i − m_j| − |p_i − p_j| | for i < j, m measured and p modelled positions.
/// Distances do not depend on the world frame, so this also rates a model whose base was never
/// fitted. 10,000 rows give 50 million pairs; the work is spread over threads in fixed blocks of
/// rows and the block results are combined in a fixed order, so the statistics and the
/// histogram are bit-identical for any number of threads. Memory is O(N). Each e_ij is
/// computed to a relative kPairErrorRelativeAccuracy whatever the lengths (see the kernel),
/// plus an absolute kPairErrorResidualRounding·(|m_i − p_i| + |m_j − p_j|).

#include <Eigen/Core>

#include "robcal/validate/error_statistics.hpp"
#include "robcal/validate/histogram.hpp"

namespace robcal {

/// Bound on the relative error of each pair error e_ij: three single-precision roundings in
/// the denominator of (|a|² − |b|²)/(|a| + |b|), the numerator being exact to double rounding.
inline constexpr double kPairErrorRelativeAccuracy = 3e-7;

/// Absolute error of e_ij per mm of |m_i − p_i| + |m_j − p_j|: the residuals r = m − p are
/// rounded to double (2⁻⁵³ relative) before r_i − r_j enters the numerator. Nothing when the
/// model's frame agrees with the instrument's; 2e-13 mm when they are a metre apart.
inline constexpr double kPairErrorResidualRounding = 2.3e-16;

struct PairwiseDistanceErrors {
  ErrorStatistics stats;  ///< of e_ij over all N(N−1)/2 pairs (count = pairs)
  /// Signed errors |m_i − m_j| − |p_i − p_j| (positive: the measured distance is the longer, as
  /// the published tables count them): their mean, and how many are positive.
  double signed_mean = 0;
  uint64_t positive_pairs = 0;
  /// Share of positive signed errors, 0..1 (0 without pairs).
  [[nodiscard]] double positive_share() const {
    return stats.count == 0
               ? 0.0
               : static_cast<double>(positive_pairs) / static_cast<double>(stats.count);
  }
  /// Over [0, bound): bound = r_1 + r_2, the two largest residuals |m_i − (R p_i + t)| after the
  /// rigid best fit (R, t) of the modelled points to the measured ones, which no e_ij can exceed
  /// (e_ij ≤ |d_i − d_j| for d_i = m_i − R p_i − t, since |R(p_i − p_j)| = |p_i − p_j|).
  Histogram histogram;
};

/// Statistics and histogram of the pair distance errors.
/// \param measured_mm, modelled_mm  3×N positions, same N, finite (std::invalid_argument if not)
/// \param threads  worker threads (≥ 1); results do not depend on it
/// \param bins     histogram bins (≥ 1)
PairwiseDistanceErrors pairwise_distance_errors(const Eigen::Matrix3Xd& measured_mm,
                                                const Eigen::Matrix3Xd& modelled_mm,
                                                int threads = 2, int bins = 128);

}  // namespace robcal
