#include <Eigen/Cholesky>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/identify/identification.hpp"

namespace robcal {

std::vector<GroupSignificance> group_significance(const CalibratedRobot& robot) {
  const ParameterVector nominal = robot.model.nominal();
  const bool has_covariance = robot.covariance.rows() == kParameterCount;
  std::vector<GroupSignificance> out;
  for (const ParameterGroup& group : opt_in_groups()) {
    GroupSignificance g;
    g.group = group.name;
    std::vector<int> identified;
    for (int i : group.params) {
      g.enabled = g.enabled || robot.params[i] != nominal[i] ||
                  robot.status[static_cast<size_t>(i)] != ParameterStatus::Fixed;
      if (robot.status[static_cast<size_t>(i)] == ParameterStatus::Identified && has_covariance)
        identified.push_back(i);
    }
    g.identified = static_cast<int>(identified.size());
    if (g.identified > 0) {
      const auto n = static_cast<Eigen::Index>(identified.size());
      Eigen::MatrixXd C(n, n);
      Eigen::VectorXd d(n);
      for (Eigen::Index a = 0; a < n; ++a) {
        d[a] = robot.params[identified[a]] - nominal[identified[a]];
        for (Eigen::Index b = 0; b < n; ++b)
          C(a, b) = robot.covariance(identified[a], identified[b]);
      }
      const Eigen::LDLT<Eigen::MatrixXd> ldlt(C);
      if (ldlt.info() == Eigen::Success && ldlt.isPositive()) {
        g.wald = d.dot(ldlt.solve(d));
        g.p_value = chi_square_upper_tail(g.wald, g.identified);
        g.significant = g.p_value < kGroupSignificanceLevel;
      }
    }
    out.push_back(g);
  }
  return out;
}

}  // namespace robcal
