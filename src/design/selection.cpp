#include "robcal/design/selection.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "robcal/core/error.hpp"
#include "robcal/design/observability.hpp"

namespace robcal {

namespace {
constexpr double kMinusInf = -std::numeric_limits<double>::infinity();

double log_det_spd(const Eigen::MatrixXd& A) {
  const Eigen::LLT<Eigen::MatrixXd> llt(A);
  if (llt.info() != Eigen::Success) return kMinusInf;
  const auto d = llt.matrixL().nestedExpression().diagonal();
  if (!(d.minCoeff() > 0)) return kMinusInf;
  return 2 * d.array().log().sum();
}
}  // namespace

InformationMatrix::InformationMatrix(int parameters, double ridge)
    : M_(Eigen::MatrixXd::Identity(parameters, parameters) * ridge),
      P_(Eigen::MatrixXd::Identity(parameters, parameters) / ridge),
      log_det_(parameters * std::log(ridge)) {}

InformationMatrix::InformationMatrix(const Eigen::MatrixXd& M) : M_(M) {
  refresh();
}

double InformationMatrix::gain(const Eigen::Ref<const Eigen::MatrixXd>& A) const {
  const Eigen::MatrixXd C = Eigen::MatrixXd::Identity(A.rows(), A.rows()) + A * P_ * A.transpose();
  return log_det_spd(C);
}

double InformationMatrix::loss(const Eigen::Ref<const Eigen::MatrixXd>& A) const {
  const Eigen::MatrixXd C = Eigen::MatrixXd::Identity(A.rows(), A.rows()) - A * P_ * A.transpose();
  return log_det_spd(C);
}

const Eigen::MatrixXd& InformationMatrix::update(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                                 double sign) {
  // C = I ± A P Aᵀ = L Lᵀ; W = P Aᵀ L⁻ᵀ; (M ± AᵀA)⁻¹ = P ∓ W Wᵀ; det(M ± AᵀA) = det M · det C.
  const Eigen::MatrixXd PAt = P_ * A.transpose();
  const Eigen::MatrixXd C = Eigen::MatrixXd::Identity(A.rows(), A.rows()) + sign * (A * PAt);
  const Eigen::LLT<Eigen::MatrixXd> llt(C);
  W_ = llt.matrixL().solve(PAt.transpose()).transpose();
  log_det_ += 2 * llt.matrixL().nestedExpression().diagonal().array().log().sum();
  M_.noalias() += sign * (A.transpose() * A);
  P_.noalias() -= sign * (W_ * W_.transpose());
  return W_;
}

const Eigen::MatrixXd& InformationMatrix::add(const Eigen::Ref<const Eigen::MatrixXd>& A) {
  return update(A, +1.0);
}

const Eigen::MatrixXd& InformationMatrix::remove(const Eigen::Ref<const Eigen::MatrixXd>& A) {
  return update(A, -1.0);
}

void InformationMatrix::refresh() {
  const Eigen::LLT<Eigen::MatrixXd> llt(M_);
  P_ = llt.solve(Eigen::MatrixXd::Identity(M_.rows(), M_.cols()));
  log_det_ = 2 * llt.matrixL().nestedExpression().diagonal().array().log().sum();
}

double information_log_det(const DesignMatrix& design, const std::vector<int>& subset) {
  const Eigen::MatrixXd J = design.stacked(subset);
  return log_det_spd(J.transpose() * J);
}

// ---------------------------------------------------------------------------------------
// Published exchange: O1 by SVD for every trial.

namespace {

// O1 of a trial set recomputed from scratch: singular values as the square roots of the
// eigenvalues of JᵀJ (4× faster than an SVD of the stacked J here, and as accurate for these
// well-conditioned scaled designs).
double index_o1(const DesignMatrix& design, const std::vector<int>& subset) {
  const Eigen::MatrixXd J = design.stacked(subset);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(J.transpose() * J,
                                                           Eigen::EigenvaluesOnly);
  return observability_from_singular_values(eig.eigenvalues().cwiseMax(0).cwiseSqrt(),
                                            static_cast<int>(subset.size()))
      .O1;
}

void check_count(const DesignMatrix& design, int count) {
  if (count > design.candidates())
    throw InputError({"", 0, 0, "--count"},
                     fmt::format("asked for {} configurations but only {} feasible candidates "
                                 "exist; raise --candidates or relax the constraints",
                                 count, design.candidates()));
  const int needed = (design.columns() + design.rows_per_candidate - 1) / design.rows_per_candidate;
  if (count < needed)
    throw InputError(
        {"", 0, 0, "--count"},
        fmt::format("{} configurations give {} equations for {} identifiable "
                    "parameters; at least {} configurations are needed",
                    count, count * design.rows_per_candidate, design.columns(), needed));
}

}  // namespace

Selection select_published_exchange(const DesignMatrix& design, int count, std::mt19937_64& rng,
                                    int start_size) {
  check_count(design, count);
  const int n = design.candidates();
  start_size = std::min(start_size, count);
  std::vector<int> all(static_cast<size_t>(n));
  std::iota(all.begin(), all.end(), 0);
  std::shuffle(all.begin(), all.end(), rng);
  Selection out;
  out.chosen.assign(all.begin(), all.begin() + start_size);
  std::vector<char> in_set(static_cast<size_t>(n), 0);
  for (int c : out.chosen) in_set[static_cast<size_t>(c)] = 1;

  double current = index_o1(design, out.chosen);
  const int max_rounds = 20 * count;
  for (int round = 0; round < max_rounds; ++round) {
    // Removal that most increases O1 (never below the start size).
    int removed = -1;
    if (static_cast<int>(out.chosen.size()) > start_size) {
      double best = current;
      size_t best_pos = 0;
      for (size_t k = 0; k < out.chosen.size(); ++k) {
        std::vector<int> trial = out.chosen;
        trial.erase(trial.begin() + static_cast<long>(k));
        const double o1 = index_o1(design, trial);
        if (o1 > best) best = o1, best_pos = k;
      }
      if (best > current) {
        removed = out.chosen[best_pos];
        out.chosen.erase(out.chosen.begin() + static_cast<long>(best_pos));
        in_set[static_cast<size_t>(removed)] = 0;
        current = best;
      }
    }
    if (static_cast<int>(out.chosen.size()) == count) break;  // nothing improves at count
    // Addition that most increases O1 (taken below `count` even without improvement).
    double best = kMinusInf;
    int best_candidate = -1;
    std::vector<int> trial = out.chosen;
    trial.push_back(0);
    for (int i = 0; i < n; ++i) {
      if (in_set[static_cast<size_t>(i)]) continue;
      trial.back() = i;
      const double o1 = index_o1(design, trial);
      if (o1 > best) best = o1, best_candidate = i;
    }
    out.chosen.push_back(best_candidate);
    in_set[static_cast<size_t>(best_candidate)] = 1;
    current = best;
    if (removed >= 0) ++out.exchanges;
    if (best_candidate == removed) break;  // the removed one came straight back: a fixed point
  }
  out.log_det = information_log_det(design, out.chosen);
  return out;
}

// ---------------------------------------------------------------------------------------
// Fast D-optimal greedy + exchange with rank-R updates.

namespace {

template <int R>
class DOptimalSearch {
 public:
  using Block = Eigen::Matrix<double, R, R>;

  DOptimalSearch(const DesignMatrix& design, double ridge)
      : A_(design.rows),
        n_(design.candidates()),
        info_(design.columns(), ridge),
        G_(A_.rows(), R),
        in_set_(static_cast<size_t>(n_), 0) {
    recompute_cache();
  }

  /// Every candidate's G_i = A_i M⁻¹ A_iᵀ from the current inverse (O(N r m²)).
  void recompute_cache() {
    const Eigen::MatrixXd B = A_ * info_.inverse();
    for (int i = 0; i < n_; ++i)
      G_.template middleRows<R>(i * R) =
          B.middleRows(i * R, R) * A_.middleRows(i * R, R).transpose();
    updates_since_refresh_ = 0;
  }

  [[nodiscard]] double gain(int i) const {
    return std::log((Block::Identity() + G_.template middleRows<R>(i * R)).determinant());
  }
  [[nodiscard]] double loss(int i) const {
    const double det = (Block::Identity() - G_.template middleRows<R>(i * R)).determinant();
    return det > 0 ? std::log(det) : kMinusInf;
  }

  void add(int i) {
    apply(info_.add(A_.middleRows(i * R, R)), -1.0);
    in_set_[static_cast<size_t>(i)] = 1;
    chosen_.push_back(i);
  }
  void remove(int i) {
    apply(info_.remove(A_.middleRows(i * R, R)), +1.0);
    in_set_[static_cast<size_t>(i)] = 0;
    chosen_.erase(std::find(chosen_.begin(), chosen_.end(), i));
  }

  [[nodiscard]] int best_addition() const {
    int best = -1;
    double best_gain = kMinusInf;
    for (int i = 0; i < n_; ++i) {
      if (in_set_[static_cast<size_t>(i)]) continue;
      const double g = gain(i);
      if (g > best_gain) best_gain = g, best = i;
    }
    return best;
  }
  [[nodiscard]] int best_removal() const {
    int best = -1;
    double best_loss = kMinusInf;
    for (int i : chosen_) {
      const double l = loss(i);
      if (l > best_loss) best_loss = l, best = i;
    }
    return best;
  }

  /// Replaces the ridge by the exact information of the chosen set (once it has full rank).
  void drop_ridge() {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(A_.cols(), A_.cols());
    for (int i : chosen_)
      M.noalias() += A_.middleRows(i * R, R).transpose() * A_.middleRows(i * R, R);
    if (log_det_spd(M) == kMinusInf) return;
    info_ = InformationMatrix(M);
    recompute_cache();
  }

  [[nodiscard]] const std::vector<int>& chosen() const { return chosen_; }
  [[nodiscard]] double log_det() const { return info_.log_det(); }

 private:
  // G_i ∓= (A_i W)(A_i W)ᵀ for every candidate: one (N r × m)·(m × r) product.
  void apply(const Eigen::MatrixXd& W, double sign) {
    const Eigen::MatrixXd B = A_ * W;
    for (int i = 0; i < n_; ++i) {
      const auto b = B.middleRows(i * R, R);
      G_.template middleRows<R>(i * R).noalias() += sign * (b * b.transpose());
    }
    if (++updates_since_refresh_ >= kRefreshEvery) {
      info_.refresh();
      recompute_cache();
    }
  }

  static constexpr int kRefreshEvery = 64;
  const Eigen::MatrixXd& A_;
  int n_;
  InformationMatrix info_;
  Eigen::Matrix<double, Eigen::Dynamic, R> G_;
  std::vector<char> in_set_;
  std::vector<int> chosen_;
  int updates_since_refresh_ = 0;
};

template <int R>
Selection run_d_optimal(const DesignMatrix& design, int count) {
  // The ridge only orders the first picks while M has fewer than m rows; it is replaced by the
  // exact information before the exchanges. Columns have unit RMS norm per candidate, so
  // 1e-6 is far below any real eigenvalue of a full-rank design.
  DOptimalSearch<R> search(design, 1e-6);
  while (static_cast<int>(search.chosen().size()) < count) search.add(search.best_addition());
  search.drop_ridge();
  Selection out;
  const int max_exchanges = 50 * count;
  bool improved = true;
  while (improved && out.exchanges < max_exchanges) {
    improved = false;
    // Remove the least informative, add the best (possibly the same one back: no change).
    const int j = search.best_removal();
    if (j >= 0 && search.loss(j) > kMinusInf) {
      const double before = search.log_det();
      search.remove(j);
      const int i = search.best_addition();
      search.add(i);
      if (i != j && search.log_det() > before + 1e-12) improved = true, ++out.exchanges;
    }
    // Add the best, remove the least informative (possibly the one just added).
    const double before = search.log_det();
    const int i = search.best_addition();
    search.add(i);
    const int k = search.best_removal();
    search.remove(k);
    if (k != i && search.log_det() > before + 1e-12) improved = true, ++out.exchanges;
  }
  out.chosen = search.chosen();
  out.log_det = information_log_det(design, out.chosen);
  return out;
}

}  // namespace

Selection select_d_optimal(const DesignMatrix& design, int count) {
  check_count(design, count);
  switch (design.rows_per_candidate) {
    case 1:
      return run_d_optimal<1>(design, count);
    case 3:
      return run_d_optimal<3>(design, count);
    case 6:
      return run_d_optimal<6>(design, count);
    default:
      throw std::invalid_argument(
          fmt::format("select_d_optimal: {} rows per candidate (expected 1, 3 or 6)",
                      design.rows_per_candidate));
  }
}

// ---------------------------------------------------------------------------------------
// Continuous D-optimal design.

ContinuousDesign d_optimal_continuous(const DesignMatrix& design, double tolerance,
                                      int max_iterations) {
  const int n = design.candidates();
  const int r = design.rows_per_candidate;
  const double m = design.columns();
  ContinuousDesign out;
  out.weights = Eigen::VectorXd::Constant(n, 1.0 / n);
  std::vector<int> active(static_cast<size_t>(n));
  std::iota(active.begin(), active.end(), 0);
  Eigen::MatrixXd A, B;
  Eigen::VectorXd d;
  for (out.iterations = 0; out.iterations < max_iterations; ++out.iterations) {
    // Rows of the active candidates weighted by √w: M = AᵀA.
    const auto rows = static_cast<Eigen::Index>(active.size()) * r;
    A.resize(rows, design.columns());
    for (size_t k = 0; k < active.size(); ++k)
      A.middleRows(static_cast<Eigen::Index>(k) * r, r) =
          std::sqrt(out.weights[active[k]]) * design.block(active[k]);
    const Eigen::MatrixXd M = A.transpose() * A;
    const Eigen::LLT<Eigen::MatrixXd> llt(M);
    out.log_det = 2 * llt.matrixL().nestedExpression().diagonal().array().log().sum();
    // Variance function d_i = tr(A_i M⁻¹ A_iᵀ) of the unweighted blocks.
    B = llt.solve(A.transpose()).transpose();  // (√w A_i) M⁻¹ per row
    const Eigen::VectorXd row_d = B.cwiseProduct(A).rowwise().sum();
    d.resize(static_cast<Eigen::Index>(active.size()));
    for (size_t k = 0; k < active.size(); ++k)
      d[static_cast<Eigen::Index>(k)] =
          row_d.segment(static_cast<Eigen::Index>(k) * r, r).sum() / out.weights[active[k]];
    out.gap = d.maxCoeff() / m - 1;
    if (out.gap <= tolerance) {
      out.converged = true;
      break;
    }
    // Multiplicative step w_i ← w_i d_i / m (keeps Σw = 1 since Σ w_i d_i = m).
    for (size_t k = 0; k < active.size(); ++k)
      out.weights[active[k]] *= d[static_cast<Eigen::Index>(k)] / m;
    // Harman & Pronzato (2007): a candidate with d_i < m·h(ε) carries no weight at the optimum.
    const double eps = out.gap;
    const double h = 1 + eps / 2 - std::sqrt(eps * (4 + eps - 4 / m)) / 2;
    std::vector<int> kept;
    double removed_weight = 0;
    for (size_t k = 0; k < active.size(); ++k) {
      if (d[static_cast<Eigen::Index>(k)] < m * h) {
        removed_weight += out.weights[active[k]];
        out.weights[active[k]] = 0;
      } else {
        kept.push_back(active[k]);
      }
    }
    if (removed_weight > 0)
      for (int i : kept) out.weights[i] /= 1 - removed_weight;
    active.swap(kept);
  }
  return out;
}

double d_efficiency(const DesignMatrix& design, const std::vector<int>& subset,
                    const ContinuousDesign& optimum) {
  const double m = design.columns();
  const double log_det_exact =
      information_log_det(design, subset) - m * std::log(static_cast<double>(subset.size()));
  if (log_det_exact == kMinusInf) return 0;
  return std::exp((log_det_exact - optimum.log_det - m * optimum.gap) / m);
}

}  // namespace robcal
