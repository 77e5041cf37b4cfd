#include "robcal/identify/identifiability.hpp"

#include <Eigen/Dense>
#include <algorithm>

namespace robcal {

double RankAnalysis::condition_number() const {
  if (singular_values.size() == 0 || singular_values.minCoeff() <= 0) return 0;
  return singular_values.maxCoeff() / singular_values.minCoeff();
}

RankAnalysis analyse_rank(const Eigen::MatrixXd& J, const std::vector<int>& order,
                          double tolerance) {
  RankAnalysis out;
  const Eigen::Index m = J.rows();
  Eigen::MatrixXd Q(m, 0);  // orthonormal basis of the kept columns (Gram–Schmidt, twice)
  std::vector<int> pending;
  for (int c : order) {
    const double norm = J.col(c).norm();
    if (norm == 0.0) {
      out.dropped.push_back({c, {}});
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
  // Scaled kept columns; each dropped column's least-squares combination of them is its
  // null-space vector (e_dropped − Σ w·e_kept).
  Eigen::MatrixXd K(m, static_cast<Eigen::Index>(out.kept.size()));
  for (size_t k = 0; k < out.kept.size(); ++k)
    K.col(static_cast<Eigen::Index>(k)) = J.col(out.kept[k]) / J.col(out.kept[k]).norm();
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(K);
  for (int c : pending) {
    const Eigen::VectorXd w = qr.solve(J.col(c) / J.col(c).norm());
    Dependency dep{c, {}};
    for (Eigen::Index k = 0; k < w.size(); ++k)
      if (std::abs(w[k]) >= 1e-3)
        dep.depends_on.emplace_back(out.kept[static_cast<size_t>(k)], w[k]);
    std::sort(dep.depends_on.begin(), dep.depends_on.end(),
              [](const auto& a, const auto& b) { return std::abs(a.second) > std::abs(b.second); });
    out.dropped.push_back(dep);
  }
  out.singular_values = K.cols() > 0
                            ? Eigen::VectorXd(Eigen::JacobiSVD<Eigen::MatrixXd>(K).singularValues())
                            : Eigen::VectorXd();
  return out;
}

}  // namespace robcal
