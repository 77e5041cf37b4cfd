#include "robcal/validate/pairwise_distance.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <thread>
#include <vector>

#include "robcal/core/progress.hpp"

namespace robcal {
namespace {

// The pair loop is the hot spot (50 million pairs for 10,000 rows). It is compiled for AVX-512,
// AVX2 and baseline x86-64 and the best is picked at load time; it calls no libm function
// (errno handling would block vectorising). One machine always runs the same clone, so results
// do not depend on the thread count; across machines they may differ in the last bits (the
// AVX-512 clone fuses multiply-adds).
#if defined(__GNUC__) && defined(__x86_64__) && defined(__ELF__)
#define ROBCAL_PAIR_KERNEL __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define ROBCAL_PAIR_KERNEL
#endif

constexpr int kRowsPerBlock = 16;  ///< fixed work unit; blocks are combined in this order
constexpr int kChunk = 512;        ///< pairs computed at once (a multiple of kLanes)
constexpr int kLanes = 8;          ///< independent partial sums (vector lanes)
constexpr int kVector = 16;        ///< pairs per iteration of the vectorised pair loop
static_assert(kChunk % (2 * kLanes) == 0 && kChunk % kVector == 0);
constexpr int kHistogramCopies = 4;  ///< interleaved copies break store-to-load chains

/// Count, mean and sum of squared deviations; merged with Chan et al.'s pairwise formula.
struct Moments {
  double n = 0;
  double mean = 0;
  double m2 = 0;
  void merge(const Moments& other) {
    if (other.n == 0) return;
    const double total = n + other.n;
    const double delta = other.mean - mean;
    mean += delta * (other.n / total);
    m2 += other.m2 + delta * delta * (n * other.n / total);
    n = total;
  }
};

struct BlockResult {
  Moments moments;
  double min = std::numeric_limits<double>::infinity();
  double max = 0;
  double signed_sum = 0;  ///< Σ (|m_i − m_j| − |p_i − p_j|)
  uint64_t positive = 0;  ///< pairs whose measured distance is the longer
};

/// Measured positions m, modelled positions p and residuals r = m − p as coordinate arrays
/// (structure of arrays for the vector loop), padded with kChunk zeros so that the pair loop
/// always runs a whole chunk.
struct Coordinates {
  std::array<std::vector<double>, 3> m, p, r;
  Coordinates(const Eigen::Matrix3Xd& measured, const Eigen::Matrix3Xd& modelled) {
    const size_t n = static_cast<size_t>(measured.cols());
    for (int axis = 0; axis < 3; ++axis) {
      m[axis].assign(n + kChunk, 0.0);
      p[axis].assign(n + kChunk, 0.0);
      r[axis].assign(n + kChunk, 0.0);
      for (size_t i = 0; i < n; ++i) {
        m[axis][i] = measured(axis, static_cast<Eigen::Index>(i));
        p[axis][i] = modelled(axis, static_cast<Eigen::Index>(i));
        r[axis][i] = m[axis][i] - p[axis][i];
      }
    }
  }
};

/// Errors of the pairs (i, j), j in [begin, begin + kChunk), into `e`, and their histogram
/// bins over [0, bins/scale) into `bin` (entries past the last row are computed against the
/// zero padding and ignored by the caller).
///
/// With a = m_i − m_j and b = p_i − p_j, |a| − |b| = (|a|² − |b|²)/(|a| + |b|) and
/// |a|² − |b|² = (a − b)·(a + b) with a − b = r_i − r_j: the difference of two large, nearly
/// equal lengths is never formed. The numerator is exact to double rounding; the denominator
/// only scales it, so single precision (relative 2⁻²⁴ per operation) gives e_ij to a relative
/// 3e-7 — 3e-9 mm on a 0.01 mm error, far below any instrument — while the square roots and
/// the division run 16 to a vector on the hardware divider instead of as Newton iterations.
/// The direct formula |a| − |b| in double would lose ulp(|a|) ≈ 1e-13 mm absolute, which is
/// worse for tiny errors. This file is built with -fno-math-errno -fno-trapping-math
/// (CMakeLists.txt) so that this loop vectorises.
ROBCAL_PAIR_KERNEL
void pair_errors(const Coordinates& c, int i, int begin, int count, double scale, int bins,
                 double* __restrict e, double* __restrict signed_e, int32_t* __restrict bin) {
  const double last_bin = bins - 1;
  const size_t row = static_cast<size_t>(i), first = static_cast<size_t>(begin);
  const double mxi = c.m[0][row], myi = c.m[1][row], mzi = c.m[2][row];
  const double pxi = c.p[0][row], pyi = c.p[1][row], pzi = c.p[2][row];
  const double rxi = c.r[0][row], ryi = c.r[1][row], rzi = c.r[2][row];
  const double* __restrict mx = c.m[0].data() + first;
  const double* __restrict my = c.m[1].data() + first;
  const double* __restrict mz = c.m[2].data() + first;
  const double* __restrict px = c.p[0].data() + first;
  const double* __restrict py = c.p[1].data() + first;
  const double* __restrict pz = c.p[2].data() + first;
  const double* __restrict rx = c.r[0].data() + first;
  const double* __restrict ry = c.r[1].data() + first;
  const double* __restrict rz = c.r[2].data() + first;
  // Whole vectors only (padding lies beyond the last row), so no scalar epilogue runs.
  const int end = (count + kVector - 1) / kVector * kVector;
  for (int k = 0; k < end; ++k) {
    const double ax = mxi - mx[k], ay = myi - my[k], az = mzi - mz[k];
    const double bx = pxi - px[k], by = pyi - py[k], bz = pzi - pz[k];
    const auto s = static_cast<float>(ax * ax + ay * ay + az * az);  // |a|²
    const auto t = static_cast<float>(bx * bx + by * by + bz * bz);  // |b|²
    const double difference =
        (rxi - rx[k]) * (ax + bx) + (ryi - ry[k]) * (ay + by) + (rzi - rz[k]) * (az + bz);
    const float sum = std::sqrt(s) + std::sqrt(t);  // |a| + |b|
    // sum is 0 only for |a|, |b| < 1e-19 mm, where the numerator is below 1e-19 mm too:
    // dividing by 1 instead keeps e finite and that small.
    const float inverse = 1.0F / (sum > 0 ? sum : 1.0F);
    // |a| − |b|: the measured distance minus the modelled one (its sign is the difference's).
    const double signed_error = difference * static_cast<double>(inverse);
    const double error = std::fabs(signed_error);
    e[k] = error;
    signed_e[k] = signed_error;
    // histogram_bin for error ≥ 0 and lower = 0, without branches (std::min is one vminpd).
    bin[k] = static_cast<int32_t>(std::min(error * scale, last_bin));
  }
}

/// Lane accumulators of one row.
struct RowSums {
  std::array<double, kLanes> sum{}, squares{}, max{}, signed_sum{}, positive{};
  std::array<double, kLanes> min;
  RowSums() { min.fill(std::numeric_limits<double>::infinity()); }
};

/// Adds the first `count` errors to the row's lanes and their bins to the histogram copies.
/// Chunks start at multiples of kChunk within the row and hold whole pairs of lane groups, so
/// pair k of a row always goes to lane k mod kLanes of set (k / kLanes) mod 2: the order of
/// additions depends only on the data.
ROBCAL_PAIR_KERNEL
void accumulate(const double* __restrict e, const double* __restrict signed_e,
                const int32_t* __restrict bin, int count, int bins, RowSums& sums,
                uint64_t* __restrict histogram) {
  // Two sets of lanes, even and odd groups of kLanes, so that the multiply-add chains of the
  // squares overlap; merged at the end of the chunk.
  RowSums even = sums, odd;
  const auto add = [](RowSums& to, int l, double v, double s) {
    to.signed_sum[l] += s;
    to.positive[l] += s > 0 ? 1.0 : 0.0;  // exact: a row has far fewer than 2⁵³ pairs
    to.sum[l] += v;
    to.squares[l] += v * v;
    to.min[l] = v < to.min[l] ? v : to.min[l];
    to.max[l] = v > to.max[l] ? v : to.max[l];
  };
  int k = 0;
  for (; k + 2 * kLanes <= count; k += 2 * kLanes)
    for (int l = 0; l < kLanes; ++l) {
      add(even, l, e[k + l], signed_e[k + l]);
      add(odd, l, e[k + kLanes + l], signed_e[k + kLanes + l]);
    }
  if (k + kLanes <= count) {
    for (int l = 0; l < kLanes; ++l) add(even, l, e[k + l], signed_e[k + l]);
    k += kLanes;
  }
  for (int l = 0; l < kLanes; ++l)  // constant lane indices keep the lanes in registers
    if (k + l < count) add(even, l, e[k + l], signed_e[k + l]);
  for (int l = 0; l < kLanes; ++l) {
    even.sum[l] += odd.sum[l];
    even.signed_sum[l] += odd.signed_sum[l];
    even.positive[l] += odd.positive[l];
    even.squares[l] += odd.squares[l];
    even.min[l] = std::min(even.min[l], odd.min[l]);
    even.max[l] = std::max(even.max[l], odd.max[l]);
  }
  sums = even;
  static_assert(kHistogramCopies == 4);
  uint64_t* __restrict copy0 = histogram;
  uint64_t* __restrict copy1 = histogram + bins;
  uint64_t* __restrict copy2 = copy1 + bins;
  uint64_t* __restrict copy3 = copy2 + bins;
  for (k = 0; k + kHistogramCopies <= count; k += kHistogramCopies) {
    ++copy0[bin[k]];
    ++copy1[bin[k + 1]];
    ++copy2[bin[k + 2]];
    ++copy3[bin[k + 3]];
  }
  for (; k < count; ++k) ++copy0[bin[k]];
}

BlockResult process_block(const Coordinates& c, int block, int rows, double scale, int bins,
                          uint64_t* histogram) {
  alignas(64) double e[kChunk];
  alignas(64) double signed_e[kChunk];
  alignas(64) int32_t bin[kChunk];
  BlockResult result;
  const int row_end = std::min(rows, (block + 1) * kRowsPerBlock);
  for (int i = block * kRowsPerBlock; i < row_end; ++i) {
    RowSums sums;
    for (int begin = i + 1; begin < rows; begin += kChunk) {
      const int count = std::min(kChunk, rows - begin);
      pair_errors(c, i, begin, count, scale, bins, e, signed_e, bin);
      accumulate(e, signed_e, bin, count, bins, sums, histogram);
    }
    const double n = rows - 1 - i;
    if (n == 0) continue;
    double sum = 0, squares = 0, positive = 0;
    for (size_t lane = 0; lane < kLanes; ++lane) {
      result.signed_sum += sums.signed_sum[lane];
      positive += sums.positive[lane];
      sum += sums.sum[lane];
      squares += sums.squares[lane];
      result.min = std::min(result.min, sums.min[lane]);
      result.max = std::max(result.max, sums.max[lane]);
    }
    // One row holds at most N − 1 errors of similar size: its own Σe² − (Σe)²/n is accurate;
    // rows are then merged with the stable pairwise formula.
    result.moments.merge({n, sum / n, std::max(0.0, squares - sum * sum / n)});
    result.positive += static_cast<uint64_t>(positive);
  }
  return result;
}

/// r_1 + r_2 after the rigid best fit: no pair error can exceed it (see the header).
double pair_error_bound(const Eigen::Matrix3Xd& measured, const Eigen::Matrix3Xd& modelled) {
  const Eigen::Matrix4d fit = Eigen::umeyama(modelled, measured, false);
  const Eigen::Matrix3Xd residual =
      measured - ((fit.topLeftCorner<3, 3>() * modelled).colwise() + fit.topRightCorner<3, 1>());
  double first = 0, second = 0;
  for (Eigen::Index i = 0; i < residual.cols(); ++i) {
    const double r = residual.col(i).norm();
    if (r > first) {
      second = first;
      first = r;
    } else if (r > second) {
      second = r;
    }
  }
  return first + second;
}

}  // namespace

PairwiseDistanceErrors pairwise_distance_errors(const Eigen::Matrix3Xd& measured_mm,
                                                const Eigen::Matrix3Xd& modelled_mm, int threads,
                                                int bins) {
  if (measured_mm.cols() != modelled_mm.cols())
    throw std::invalid_argument(
        fmt::format("pairwise_distance_errors: {} measured and {} modelled "
                    "positions",
                    measured_mm.cols(), modelled_mm.cols()));
  // The kernel squares distances in single precision (up to 3e38): 1e12 mm leaves room.
  constexpr double kMaxCoordinate = 1e12;
  if (!measured_mm.allFinite() || !modelled_mm.allFinite() ||
      (measured_mm.cols() > 0 && (measured_mm.cwiseAbs().maxCoeff() > kMaxCoordinate ||
                                  modelled_mm.cwiseAbs().maxCoeff() > kMaxCoordinate)))
    throw std::invalid_argument(
        "pairwise_distance_errors: positions must be finite and within ±1e12 mm");
  if (threads < 1 || bins < 1)
    throw std::invalid_argument(fmt::format(
        "pairwise_distance_errors: threads ({}) and bins ({}) must be >= 1", threads, bins));
  if (measured_mm.cols() > std::numeric_limits<int>::max())
    throw std::invalid_argument("pairwise_distance_errors: too many rows");
  const int rows = static_cast<int>(measured_mm.cols());

  PairwiseDistanceErrors out;
  out.histogram.counts.assign(static_cast<size_t>(bins), 0);
  if (rows < 2) return out;
  // Bound inflated past rounding in the fit; a bound of zero means every error is (near) zero.
  out.histogram.upper = std::max(pair_error_bound(measured_mm, modelled_mm) * (1 + 1e-9), 1e-9);
  const double scale = bins / out.histogram.upper;

  const Coordinates coordinates(measured_mm, modelled_mm);
  const int blocks = (rows + kRowsPerBlock - 1) / kRowsPerBlock;
  std::vector<BlockResult> results(static_cast<size_t>(blocks));
  const int workers = std::min(threads, blocks);
  std::vector<std::vector<uint64_t>> histograms(
      static_cast<size_t>(workers),
      std::vector<uint64_t>(static_cast<size_t>(bins) * kHistogramCopies, 0));
  std::atomic<int> next_block{0};
  Progress progress("distance errors over every pair of rows",
                    static_cast<std::int64_t>(rows) * (rows - 1) / 2);
  const auto work = [&](int worker) {
    for (int block = next_block++; block < blocks; block = next_block++) {
      results[static_cast<size_t>(block)] = process_block(
          coordinates, block, rows, scale, bins, histograms[static_cast<size_t>(worker)].data());
      // Block b holds the pairs of rows 16b … 16b + 15 with every later row.
      const auto first = static_cast<std::int64_t>(block) * kRowsPerBlock;
      const auto last = std::min<std::int64_t>(rows, first + kRowsPerBlock);
      progress.advance((last - first) * (2 * rows - first - last - 1) / 2);
    }
  };
  std::vector<std::thread> pool;
  for (int worker = 1; worker < workers; ++worker) pool.emplace_back(work, worker);
  work(0);
  for (std::thread& t : pool) t.join();

  // Fixed order: blocks by index; histogram counts are integers, so their order is free.
  Moments moments;
  double min = std::numeric_limits<double>::infinity(), max = 0, signed_sum = 0;
  for (const BlockResult& r : results) {
    moments.merge(r.moments);
    signed_sum += r.signed_sum;
    out.positive_pairs += r.positive;
    min = std::min(min, r.min);
    max = std::max(max, r.max);
  }
  for (const auto& h : histograms)
    for (size_t k = 0; k < h.size(); ++k)
      out.histogram.counts[k % static_cast<size_t>(bins)] += h[k];
  out.stats.count = static_cast<uint64_t>(rows) * static_cast<uint64_t>(rows - 1) / 2;
  out.stats.mean = moments.mean;
  out.stats.std = std::sqrt(moments.m2 / moments.n);
  out.stats.min = min;
  out.stats.max = max;
  out.signed_mean = signed_sum / static_cast<double>(out.stats.count);
  return out;
}

}  // namespace robcal
