#include "robcal/identify/identifiability.hpp"

#include <Eigen/Dense>
#include <algorithm>

namespace robcal {
namespace {

/// The columns `columns` of J, each scaled to unit length.
Eigen::MatrixXd unit_columns(const Eigen::MatrixXd& J, const std::vector<int>& columns) {
  Eigen::MatrixXd K(J.rows(), static_cast<Eigen::Index>(columns.size()));
  for (size_t k = 0; k < columns.size(); ++k)
    K.col(static_cast<Eigen::Index>(k)) = J.col(columns[k]) / J.col(columns[k]).norm();
  return K;
}

/// Column `c`'s least-squares combination of the unit columns `kept` (factored in `qr`): its
/// null-space vector e_c − Σ w·e_kept when the dependency is exact.
Dependency combination(const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr,
                       const Eigen::VectorXd& column, const std::vector<int>& kept, int c) {
  const Eigen::VectorXd w = qr.solve(column / column.norm());
  Dependency dep{c, {}, 1.0, {}};
  for (Eigen::Index k = 0; k < w.size(); ++k)
    if (std::abs(w[k]) >= 1e-3) dep.depends_on.emplace_back(kept[static_cast<size_t>(k)], w[k]);
  std::sort(dep.depends_on.begin(), dep.depends_on.end(),
            [](const auto& a, const auto& b) { return std::abs(a.second) > std::abs(b.second); });
  return dep;
}

}  // namespace

double RankAnalysis::condition_number() const {
  if (singular_values.size() == 0 || singular_values.minCoeff() <= 0) return 0;
  return singular_values.maxCoeff() / singular_values.minCoeff();
}

RankAnalysis analyse_rank(const Eigen::MatrixXd& J, const std::vector<int>& order, double tolerance,
                          double negligible_norm) {
  RankAnalysis out;
  const Eigen::Index m = J.rows();
  Eigen::MatrixXd Q(m, 0);  // orthonormal basis of the kept columns (Gram–Schmidt, twice)
  std::vector<int> pending;
  for (int c : order) {
    const double norm = J.col(c).norm();
    if (norm <= negligible_norm) {
      out.dropped.push_back({c, {}, 1.0, {}});
      continue;
    }
    Eigen::VectorXd v = J.col(c) / norm;
    for (int pass = 0; pass < 2; ++pass) v -= Q * (Q.transpose() * v);
    const double rest = v.norm();
    if (rest < tolerance) {
      pending.push_back(c);
      continue;
    }
    Q.conservativeResize(Eigen::NoChange, Q.cols() + 1);
    Q.col(Q.cols() - 1) = v / rest;
    out.kept.push_back(c);
  }
  const Eigen::MatrixXd K = unit_columns(J, out.kept);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(K);
  for (int c : pending) out.dropped.push_back(combination(qr, J.col(c), out.kept, c));
  out.singular_values = K.cols() > 0
                            ? Eigen::VectorXd(Eigen::JacobiSVD<Eigen::MatrixXd>(K).singularValues())
                            : Eigen::VectorXd();
  return out;
}

}  // namespace robcal

namespace robcal {

std::vector<Dependency> near_dependencies(const Eigen::MatrixXd& J, const std::vector<int>& order,
                                          double noise_mm, double threshold) {
  std::vector<Dependency> out;
  std::vector<int> remaining = order;
  const double inflation_limit = 1.0 / (1.0 - threshold * threshold);
  while (remaining.size() > 1) {
    const Eigen::MatrixXd K = unit_columns(J, remaining);
    const Eigen::MatrixXd N = K.transpose() * K;
    const Eigen::VectorXd inflation =
        N.ldlt().solve(Eigen::MatrixXd::Identity(N.rows(), N.cols())).diagonal();
    Eigen::Index worst = -1;
    for (Eigen::Index k = 0; k < inflation.size(); ++k) {
      const double sigma =
          noise_mm * std::sqrt(inflation[k]) / J.col(remaining[static_cast<size_t>(k)]).norm();
      // The latest in `order` of the near-dependent ones, or of those the data barely see.
      if ((inflation[k] >= inflation_limit && sigma > 1.0) || sigma > kUndeterminedFactor)
        worst = k;
    }
    if (worst < 0) break;
    const int c = remaining[static_cast<size_t>(worst)];
    remaining.erase(remaining.begin() + worst);
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(unit_columns(J, remaining));
    Dependency dep = combination(qr, J.col(c), remaining, c);
    dep.correlation = std::sqrt(std::max(0.0, 1.0 - 1.0 / inflation[worst]));
    out.push_back(dep);
  }
  return out;
}

}  // namespace robcal
