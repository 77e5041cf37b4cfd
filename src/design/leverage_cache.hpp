#pragma once
/// \file
/// The M⁻¹-weighted leverage blocks of every candidate of a design
/// (docs/method/05-observability.md §3), the quantity the fast D-optimal selection scores with: for
/// candidate i with scaled rows A_i (r × m) and the information matrix M of the chosen set, G_i =
/// A_i M⁻¹ A_iᵀ (r × r). By the matrix determinant lemma adding candidate i multiplies det M by
/// det(I + G_i) and removing it by det(I − G_i), so scoring all candidates costs O(N r³) and no
/// factorisation.
///
/// Kept current under rank-r changes of M: when M⁻¹ becomes M⁻¹ − sign·W Wᵀ (Woodbury, W from
/// InformationMatrix::factor), every block becomes G_i − sign·b_i b_iᵀ with b_i = A_i W (r × r),
/// one O(N r² m) sweep over the candidates instead of O(N r m²) for a recomputation. The sweep
/// is split over two threads for large designs: the cache's own second thread, started at the
/// first large sweep and kept for all the others (a selection makes thousands of sweeps; a
/// thread started per sweep cost more than the sweep when the other core was busy). Every
/// candidate's arithmetic is independent of the split, so the result is the same on one thread
/// or two.

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <functional>
#include <memory>
#include <vector>

#include "robcal/design/design_matrix.hpp"

namespace robcal {

/// A second thread that runs one task at a time for its owner, started once.
class SweepWorker;

/// Leverage blocks of a design with R rows per candidate (instantiated for 1, 3 and 6).
template <int R>
class LeverageCache {
 public:
  using Block = Eigen::Matrix<double, R, R>;

  /// Blocks for M = ridge·I.
  LeverageCache(const DesignMatrix& design, double ridge);
  /// Blocks for M⁻¹ = `inverse` (m × m, symmetric positive definite).
  LeverageCache(const DesignMatrix& design, const Eigen::MatrixXd& inverse);
  LeverageCache(LeverageCache&&) noexcept;
  ~LeverageCache();

  /// Recomputes every block from M⁻¹ (O(N r m²); bounds the round-off of long update runs).
  void recompute(const Eigen::MatrixXd& inverse);
  /// b_i = A_i W for every candidate (W: m × R), kept for scoring a change before making it.
  void project(const Eigen::MatrixXd& W);
  /// G_i −= sign·b_i b_iᵀ with the last projection: M⁻¹ → M⁻¹ − sign·W Wᵀ.
  void apply(double sign);
  /// G_i −= sign·(A_i W)(A_i W)ᵀ in one sweep, without keeping the projections.
  void update(const Eigen::MatrixXd& W, double sign);

  /// Keeps the R-row blocks X_k of X (k·R rows × m) for cross(); with X_k = A_j M⁻¹ of the
  /// chosen configurations j, cross(i, k) is C_ij = A_i M⁻¹ A_jᵀ.
  void set_partners(const Eigen::MatrixXd& X);
  /// A_i X_kᵀ (R × R) with the blocks of the last set_partners.
  [[nodiscard]] Block cross(int i, int k) const;

  [[nodiscard]] int candidates() const { return n_; }
  [[nodiscard]] const Block& block(int i) const { return G_[static_cast<size_t>(i)]; }
  [[nodiscard]] const Block& projection(int i) const { return B_[static_cast<size_t>(i)]; }

 private:
  using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  using Blocks = std::vector<Block, Eigen::aligned_allocator<Block>>;

  /// Candidate i's rows (R × padded m, row-major).
  [[nodiscard]] const double* rows(int i) const;
  /// Wᵀ with A_'s padded row length.
  [[nodiscard]] RowMajorMatrix padded_transpose(const Eigen::MatrixXd& W) const;
  /// Runs f(begin, end) over the candidates, in two halves on two threads when large.
  template <typename F>
  void in_halves(F&& f) const;

  int n_ = 0, m_ = 0;
  /// Scaled rows, row-major so that every candidate's r × m block is contiguous, columns
  /// zero-padded to whole SIMD packets.
  RowMajorMatrix A_;
  RowMajorMatrix partners_;  ///< X of set_partners, padded like A_
  Blocks G_, B_;
  mutable std::unique_ptr<SweepWorker> worker_;  ///< the second thread of large sweeps
};

extern template class LeverageCache<1>;
extern template class LeverageCache<3>;
extern template class LeverageCache<6>;

}  // namespace robcal
