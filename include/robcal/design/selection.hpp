#pragma once
/// \file
/// Choosing `count` calibration configurations among the candidates
/// (docs/method/05-observability.md §3):
/// - the published exchange: a random start of 11, then remove/add single configurations
///   while the observability index O1 improves, O1 recomputed by SVD for every trial;
/// - a fast D-optimal greedy + exchange (+ Fedorov's exchange and restarts, see
///   select_d_optimal): the information matrix M = Σ A_iᵀA_i of the chosen
///   set is kept with its inverse through rank-r updates (Woodbury) and every candidate's
///   r×r matrix A_i M⁻¹ A_iᵀ is kept current by one product with the update factor, so the
///   gain of adding candidate i, log det(I + A_i M⁻¹ A_iᵀ) (matrix determinant lemma), costs
///   O(r³) and no SVD or factorisation is recomputed per candidate.
/// At a fixed count, maximising det M maximises O1 = det(M)^(1/2m)/√n.

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <vector>

#include "robcal/design/design_matrix.hpp"

namespace robcal {

/// Information matrix M = ridge·I + Σ A_kᵀA_k of a design, its inverse and log-determinant,
/// kept exactly under rank-r additions and removals (Sherman–Morrison–Woodbury and the
/// matrix determinant lemma).
class InformationMatrix {
 public:
  /// M = ridge·I; a small ridge keeps M invertible while the design has fewer than m rows.
  InformationMatrix(int parameters, double ridge);
  /// From a given symmetric positive definite M.
  explicit InformationMatrix(const Eigen::MatrixXd& M);

  /// log det(M + AᵀA) − log det M = log det(I + A M⁻¹ Aᵀ).
  [[nodiscard]] double gain(const Eigen::Ref<const Eigen::MatrixXd>& A) const;
  /// log det(M − AᵀA) − log det M = log det(I − A M⁻¹ Aᵀ); −∞ when M − AᵀA is singular.
  [[nodiscard]] double loss(const Eigen::Ref<const Eigen::MatrixXd>& A) const;

  /// The change M → M + sign·AᵀA without applying it: (M + sign·AᵀA)⁻¹ = M⁻¹ − sign·W Wᵀ
  /// and log det changes by `log_det_change`. M + sign·AᵀA must be positive definite.
  struct Update {
    Eigen::MatrixXd W;  ///< m × r
    double log_det_change = 0;
  };
  [[nodiscard]] Update factor(const Eigen::Ref<const Eigen::MatrixXd>& A, double sign) const;
  /// Applies an update computed by factor(A, sign) for the current state.
  void apply(const Eigen::Ref<const Eigen::MatrixXd>& A, double sign, const Update& update);

  /// M += AᵀA. Returns W (m × r) with the new M⁻¹ = old M⁻¹ − W Wᵀ.
  Eigen::MatrixXd add(const Eigen::Ref<const Eigen::MatrixXd>& A);
  /// M −= AᵀA (must stay positive definite). Returns W with the new M⁻¹ = old M⁻¹ + W Wᵀ.
  Eigen::MatrixXd remove(const Eigen::Ref<const Eigen::MatrixXd>& A);
  /// Recomputes M⁻¹ and log det M from M by Cholesky (bounds the round-off of long update runs).
  void refresh();

  [[nodiscard]] const Eigen::MatrixXd& matrix() const { return M_; }
  [[nodiscard]] const Eigen::MatrixXd& inverse() const { return P_; }
  [[nodiscard]] double log_det() const { return log_det_; }

 private:
  Eigen::MatrixXd M_, P_;
  double log_det_ = 0;
};

struct Selection {
  std::vector<int> chosen;  ///< candidate indices
  double log_det = 0;       ///< log det of the scaled information matrix of the chosen set
  int exchanges = 0;        ///< accepted exchange (or remove/add) steps after the first fill
  int restarts = 0;         ///< fast D-optimal: perturbed restarts made
};

struct DOptimalOptions {
  /// Restarts after the first descent; negative: by candidate count (5 up to 800 candidates,
  /// ⌊4000 / candidates⌋ above, none from 4000 on: each costs about one descent).
  int restarts = -1;
  uint64_t seed = 1;  ///< of the restarts' random starts
};

/// The published exchange algorithm on O1 (docs/method/05-observability.md §3): start from
/// `start_size` random candidates; repeatedly remove the configuration whose removal most increases
/// O1 (if any does) and add the candidate whose addition most increases O1 (below `count` the best
/// one is added even when O1 does not increase, since that many are asked for); stop at `count`
/// when no removal improves O1 or a removed configuration would be added straight back.
/// Every trial recomputes O1 by an SVD of the stacked Jacobian.
Selection select_published_exchange(const DesignMatrix& design, int count, std::mt19937_64& rng,
                                    int start_size = 11);

/// Fast D-optimal design: greedy additions from a small ridge, then a descent to a local
/// optimum: cheap exchanges (remove the least-informative chosen configuration and add the
/// best candidate; add the best candidate and remove the least-informative) while det M
/// increases, then Fedorov's exchange (the best swap over all chosen × candidate pairs, pairs
/// pruned by a bound) until no single swap increases det M. Then `restarts` more descents,
/// each greedy from a few random candidates; the best set found is returned. The descents are
/// shared between two threads; the result is deterministic for a given seed.
Selection select_d_optimal(const DesignMatrix& design, int count,
                           const DOptimalOptions& options = {});

/// The D-optimal continuous design (weights on candidates) by the multiplicative algorithm
/// (Titterington 1976; Silvey, Titterington & Torsney 1978), accelerated (exponent 2, safeguarded
/// by the classical step), with the Harman–Pronzato (2007) rule that discards candidates which
/// cannot support the optimum.
struct ContinuousDesign {
  Eigen::VectorXd weights;  ///< per candidate, sum 1
  double log_det = 0;       ///< log det Σ w_i A_iᵀA_i
  /// max_i tr(A_i M⁻¹ A_iᵀ)/m − 1 ≥ 0: by the equivalence theorem the optimum's log det is
  /// at most log_det + m·gap.
  double gap = 0;
  int iterations = 0;
  int retreats = 0;  ///< accelerated steps that lowered log det, taken again classically
  bool converged = false;
};

/// \param step_power  exponent λ of the step w_i ← w_i (d_i/m)^λ; λ = 1 is the classical,
/// monotone step, a step with λ > 1 that lowers log det is taken again with λ = 1.
ContinuousDesign d_optimal_continuous(const DesignMatrix& design, double tolerance = 1e-3,
                                      int max_iterations = 20000, double step_power = 2);

/// Certified D-efficiency of an exact design against the continuous optimum:
/// (det(M_S/n) / det M*)^(1/m) with det M* bounded above through the equivalence theorem,
/// so the true efficiency is at least this value.
double d_efficiency(const DesignMatrix& design, const std::vector<int>& subset,
                    const ContinuousDesign& optimum);

/// log det of the scaled information matrix of a subset (−∞ when singular).
double information_log_det(const DesignMatrix& design, const std::vector<int>& subset);

}  // namespace robcal
