#include "robcal/design/task_selection.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "leverage_cache.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/progress.hpp"

namespace robcal {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// As the D-optimal selection's (selection.cpp): columns have unit RMS norm per candidate, so a
// full-rank design's information is O(1) and more per direction and 1e-6 only orders the
// first picks.
constexpr double kRidge = 1e-6;
constexpr int kRefreshEvery = 25;
// An exchange must lower Φ by this fraction: smaller steps change the predicted error by less
// than its own round-off in the report (4 digits) and would only cost time.
constexpr double kMinImprovement = 1e-4;

/// A factor L with B = L Lᵀ of the symmetric positive semi-definite B (eigen-decomposition,
/// round-off negatives clamped: B is singular when a parameter does not move the TCP).
Eigen::MatrixXd psd_factor(const Eigen::MatrixXd& B) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(B);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

template <int R>
class ISearch {
 public:
  using Block = Eigen::Matrix<double, R, R>;

  ISearch(const DesignMatrix& design, const Eigen::MatrixXd& B, const std::vector<Vector6d>& joints,
          const SelectionGuard& guard, int count, const std::vector<char>& in_task)
      : A_(design.rows),
        n_(design.candidates()),
        m_(design.columns()),
        L_(psd_factor(B)),
        B_(B),
        joints_(joints),
        guard_(guard),
        edge_limit_(guard_edge_limit(guard, count)),
        cache_(design, kRidge),
        in_set_(static_cast<size_t>(n_), 0),
        edge_(static_cast<size_t>(n_), 0),
        task_(in_task.empty() ? std::vector<char>(static_cast<size_t>(n_), 0) : in_task),
        count_(count) {
    const long task_candidates = std::count(task_.begin(), task_.end(), 1);
    task_needed_ =
        guard.enabled
            ? std::min<int>(static_cast<int>(task_candidates),
                            static_cast<int>(std::ceil(guard.min_task_share * count - 1e-9)))
            : 0;
    for (int i = 0; i < n_; ++i)
      edge_[static_cast<size_t>(i)] =
          guard.enabled && near_joint_edge(guard, joints[static_cast<size_t>(i)]) ? 1 : 0;
    P_ = Eigen::MatrixXd::Identity(m_, m_) / kRidge;
    V_ = A_ * L_ / kRidge;
    phi_ = (P_ * B_).trace();
  }

  /// Lowering of Φ by adding candidate i.
  [[nodiscard]] double gain(int i) const {
    const Block C = Block::Identity() + cache_.block(i);
    const Eigen::LLT<Block> llt(C);
    return llt.matrixL()
        .solve(V_.template middleRows<R>(static_cast<Eigen::Index>(i) * R))
        .squaredNorm();
  }
  /// Rise of Φ by removing chosen candidate i (+∞ when the rest is singular).
  [[nodiscard]] double loss(int i) const {
    const Block C = Block::Identity() - cache_.block(i);
    const Eigen::LLT<Block> llt(C);
    if (llt.info() != Eigen::Success || !(llt.matrixLLT().diagonal().minCoeff() > 1e-9))
      return kInf;
    return llt.matrixL()
        .solve(V_.template middleRows<R>(static_cast<Eigen::Index>(i) * R))
        .squaredNorm();
  }

  /// Whether candidate i may join the chosen set by the guard's cap and task share (cheap).
  [[nodiscard]] bool eligible(int i) const {
    if (in_set_[static_cast<size_t>(i)]) return false;
    if (!guard_.enabled) return true;
    if (edge_[static_cast<size_t>(i)] && edge_count_ >= edge_limit_) return false;
    const int slots = count_ - static_cast<int>(chosen_.size());
    return task_[static_cast<size_t>(i)] || task_needed_ - task_count_ < slots;
  }
  /// Whether candidate i keeps the guard's spacing from every chosen configuration.
  [[nodiscard]] bool spaced(int i) const {
    if (!guard_.enabled) return true;
    for (int j : chosen_)
      if (joint_spacing(guard_, joints_[static_cast<size_t>(i)], joints_[static_cast<size_t>(j)]) <
          guard_.min_spacing)
        return false;
    return true;
  }

  /// The admissible (eligible and spaced) candidate with the greatest gain, or −1. The spacing,
  /// a pass over the chosen set, is checked only for a candidate that would lead.
  [[nodiscard]] std::pair<int, double> best_addition() const {
    return best_addition([&](int i) { return gain(i); });
  }
  template <typename Gain>
  [[nodiscard]] std::pair<int, double> best_addition(Gain&& gain_of) const {
    int best = -1;
    double best_gain = -kInf;
    for (int i = 0; i < n_; ++i) {
      if (!eligible(i)) continue;
      const double g = gain_of(i);
      if (g > best_gain && spaced(i)) best = i, best_gain = g;
    }
    return {best, best_gain};
  }

  [[nodiscard]] const std::vector<int>& chosen() const { return chosen_; }
  [[nodiscard]] double phi() const { return phi_; }

  /// One exchange: the chosen configurations in order of their loss, each removed and the best
  /// admissible candidate added when that lowers Φ; returns whether one was made. A removal is
  /// scored without being made: after it S_k becomes S_k + b_k b_kᵀ and V_k becomes
  /// V_k + b_k WᵀL (b_k = A_k W, factor()), so a refused exchange costs one sweep, not two.
  bool exchange() {
    std::vector<std::pair<double, int>> order;
    for (int j : chosen_) order.emplace_back(loss(j), j);
    std::sort(order.begin(), order.end());
    for (const auto& [lost, j] : order) {
      if (lost == kInf) break;
      const double before = phi_;
      leave(j);
      const Change removal = factor(j, -1.0);
      cache_.project(removal.W);
      const Eigen::Matrix<double, R, Eigen::Dynamic> WL = removal.W.transpose() * L_;
      const Block WLLW = WL * WL.transpose();
      const auto [k, gained] = best_addition([&](int i) {
        const auto V = V_.template middleRows<R>(static_cast<Eigen::Index>(i) * R);
        const Block& b = cache_.projection(i);
        const Block VWL = V.lazyProduct(WL.transpose());
        // V'V'ᵀ of V' = V + b WL, and gain = tr((I + S')⁻¹ V'V'ᵀ).
        const Block VV = V.lazyProduct(V.transpose()) + b * VWL.transpose() + VWL * b.transpose() +
                         b * WLLW * b.transpose();
        const Block C = Block::Identity() + cache_.block(i) + b * b.transpose();
        return Eigen::LLT<Block>(C).solve(VV).trace();
      });
      if (k >= 0 && k != j && before + removal.phi_rise - gained < before * (1 - kMinImprovement)) {
        apply(removal, -1.0, /*projected=*/true);
        insert(k);
        return true;
      }
      enter(j);
    }
    return false;
  }

  // The set changes before P does, so that a refresh inside apply() sees the new set.
  void insert(int i) {
    enter(i);
    apply(factor(i, +1.0), +1.0, /*projected=*/false);
  }
  void remove(int i) {
    leave(i);
    apply(factor(i, -1.0), -1.0, /*projected=*/false);
  }

 private:
  void enter(int i) {
    in_set_[static_cast<size_t>(i)] = 1;
    edge_count_ += edge_[static_cast<size_t>(i)];
    task_count_ += task_[static_cast<size_t>(i)];
    chosen_.push_back(i);
  }
  void leave(int i) {
    in_set_[static_cast<size_t>(i)] = 0;
    edge_count_ -= edge_[static_cast<size_t>(i)];
    task_count_ -= task_[static_cast<size_t>(i)];
    chosen_.erase(std::find(chosen_.begin(), chosen_.end(), i));
  }

  /// M → M + sign·A_iᵀA_i: P → P − sign·W Wᵀ with W = P A_iᵀ C⁻ᵀᐟ², C = I + sign·A_i P A_iᵀ
  /// (Woodbury), Φ rises by −sign·tr(Wᵀ B W).
  struct Change {
    Eigen::Matrix<double, Eigen::Dynamic, R> W;
    double phi_rise = 0;
  };
  [[nodiscard]] Change factor(int i, double sign) const {
    const auto Ai = A_.template middleRows<R>(static_cast<Eigen::Index>(i) * R);
    const Eigen::Matrix<double, Eigen::Dynamic, R> PAt = P_ * Ai.transpose();
    const Block C = Block::Identity() + sign * (Ai * PAt);
    const Eigen::LLT<Block> llt(C);
    Change out;
    out.W = llt.matrixL().solve(PAt.transpose()).transpose();
    out.phi_rise = -sign * (out.W.transpose() * B_ * out.W).trace();
    return out;
  }
  /// Makes a change: every S_j and V_j follow with b_j = A_j W (the cache's projections: its
  /// packed rows give them without the copy of every row a general matrix product makes);
  /// `projected`: the cache holds them already.
  void apply(const Change& u, double sign, bool projected) {
    const auto& W = u.W;
    phi_ += u.phi_rise;
    P_.noalias() -= sign * (W * W.transpose());
    if (!projected) cache_.project(W);
    cache_.apply(sign);
    const Eigen::Matrix<double, R, Eigen::Dynamic> WL = sign * (W.transpose() * L_);
    for (int j = 0; j < n_; ++j)
      V_.template middleRows<R>(static_cast<Eigen::Index>(j) * R).noalias() -=
          cache_.projection(j) * WL;
    if (++updates_ % kRefreshEvery == 0) refresh();
  }

  /// Recomputes P, every S_j, V and Φ from the chosen set (bounds the round-off of updates).
  void refresh() {
    Eigen::MatrixXd M = Eigen::MatrixXd::Identity(m_, m_) * kRidge;
    for (int j : chosen_) {
      const auto Aj = A_.template middleRows<R>(static_cast<Eigen::Index>(j) * R);
      M.noalias() += Aj.transpose() * Aj;
    }
    P_ = M.llt().solve(Eigen::MatrixXd::Identity(m_, m_));
    cache_.recompute(P_);
    V_.noalias() = A_ * (P_ * L_);
    phi_ = (P_ * B_).trace();
  }

  const Eigen::MatrixXd& A_;
  int n_, m_;
  Eigen::MatrixXd L_, B_;
  const std::vector<Vector6d>& joints_;
  SelectionGuard guard_;
  int edge_limit_;
  /// S_j = A_j P A_jᵀ for every candidate, kept under the rank-R changes of P.
  LeverageCache<R> cache_;
  std::vector<char> in_set_, edge_, task_;
  int count_;
  int edge_count_ = 0, task_needed_ = 0, task_count_ = 0;
  std::vector<int> chosen_;
  Eigen::MatrixXd P_;
  /// V = A P L, row-major so that every candidate's R rows are contiguous.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> V_;
  double phi_ = 0;
  long updates_ = 0;
};

template <int R>
TaskSelection run_i_optimal(const DesignMatrix& design, const Eigen::MatrixXd& B, int count,
                            const std::vector<Vector6d>& joints, const SelectionGuard& guard,
                            const std::vector<char>& in_task, const std::vector<int>& start) {
  ISearch<R> search(design, B, joints, guard, count, in_task);
  for (int i : start) search.insert(i);
  Progress progress("choosing configurations (I-optimal)", count);
  while (static_cast<int>(search.chosen().size()) < count) {
    const auto [best, gained] = search.best_addition();
    if (best < 0)
      throw InputError(
          {"", 0, 0, "--count"},
          fmt::format("the robustness guard admits only {} of the {} candidates for {} "
                      "configurations (at most {} near a joint-range edge, {:.0f} % of each "
                      "range apart); draw more candidates, choose fewer, or turn the guard off",
                      search.chosen().size(), design.candidates(), count,
                      guard_edge_limit(guard, count), 100 * guard.min_spacing));
    search.insert(best);
    progress.advance();
  }
  TaskSelection out;
  const int max_exchanges = 5 * count;
  while (out.exchanges < max_exchanges && search.exchange()) ++out.exchanges;
  out.chosen = search.chosen();
  out.criterion = i_criterion(design, B, out.chosen);
  for (int i : out.chosen)
    out.near_edge += near_joint_edge(guard, joints[static_cast<size_t>(i)]) ? 1 : 0;
  return out;
}

}  // namespace

Eigen::MatrixXd task_information(const DesignMatrix& design, const Eigen::MatrixXd& task_jacobian) {
  const Eigen::MatrixXd Js = task_jacobian * design.column_scale.asDiagonal();
  const double t = std::max<double>(1.0, static_cast<double>(task_jacobian.rows()) / 3.0);
  return Js.transpose() * Js / t;
}

bool near_joint_edge(const SelectionGuard& guard, const Vector6d& joints) {
  for (int k = 0; k < kJointCount; ++k) {
    const JointLimit& r = guard.box[static_cast<size_t>(k)];
    const double width = r.upper - r.lower;
    if (!(width > 0)) continue;
    if (std::min(joints[k] - r.lower, r.upper - joints[k]) < guard.edge_margin * width) return true;
  }
  return false;
}

double joint_spacing(const SelectionGuard& guard, const Vector6d& a, const Vector6d& b) {
  double out = 0;
  for (int k = 0; k < kJointCount; ++k) {
    const JointLimit& r = guard.box[static_cast<size_t>(k)];
    const double width = r.upper - r.lower;
    if (width > 0) out = std::max(out, std::abs(a[k] - b[k]) / width);
  }
  return out;
}

int guard_edge_limit(const SelectionGuard& guard, int count) {
  return guard.enabled ? static_cast<int>(std::floor(guard.max_edge_share * count + 1e-9)) : count;
}

double i_criterion(const DesignMatrix& design, const Eigen::MatrixXd& task_information,
                   const std::vector<int>& subset) {
  const Eigen::MatrixXd A = design.stacked(subset);
  const Eigen::MatrixXd M =
      A.transpose() * A + kRidge * Eigen::MatrixXd::Identity(design.columns(), design.columns());
  const Eigen::LLT<Eigen::MatrixXd> llt(M);
  if (llt.info() != Eigen::Success) return kInf;
  return llt.solve(task_information).trace();
}

TaskSelection select_i_optimal(const DesignMatrix& design, const Eigen::MatrixXd& task_information,
                               int count, const std::vector<Vector6d>& joints,
                               const SelectionGuard& guard, const std::vector<char>& in_task,
                               const std::vector<int>& start) {
  if (count <= 0 || count > design.candidates())
    throw InputError(
        {"", 0, 0, "--count"},
        fmt::format("expected 1 to {} configurations (the feasible candidates), got {}",
                    design.candidates(), count));
  if (static_cast<int>(joints.size()) != design.candidates() ||
      task_information.rows() != design.columns() || task_information.cols() != design.columns() ||
      (!in_task.empty() && static_cast<int>(in_task.size()) != design.candidates()))
    throw std::invalid_argument("select_i_optimal: sizes of joints or task information differ");
  std::vector<int> distinct = start;
  std::sort(distinct.begin(), distinct.end());
  if (static_cast<int>(start.size()) > count ||
      std::adjacent_find(distinct.begin(), distinct.end()) != distinct.end() ||
      (!distinct.empty() && (distinct.front() < 0 || distinct.back() >= design.candidates())))
    throw std::invalid_argument("select_i_optimal: start is not a set of at most count candidates");
  switch (design.rows_per_candidate) {
    case 1:
      return run_i_optimal<1>(design, task_information, count, joints, guard, in_task, start);
    case 3:
      return run_i_optimal<3>(design, task_information, count, joints, guard, in_task, start);
    case 6:
      return run_i_optimal<6>(design, task_information, count, joints, guard, in_task, start);
    default:
      throw std::invalid_argument(
          fmt::format("select_i_optimal: {} rows per candidate (expected 1, 3 or 6)",
                      design.rows_per_candidate));
  }
}

}  // namespace robcal
