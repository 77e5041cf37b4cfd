#pragma once
/// \file
/// Which unknowns the measurements can determine (METHOD §3, §5): a rank-revealing QR of the
/// column-scaled identification Jacobian that keeps columns in a preferred order, so that of a
/// dependent group the later one is dropped (`link3.d`, not `link2.d`, on a robot whose axes
/// 2 and 3 are parallel), and the null-space vector of each dropped column names what it
/// depends on.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace robcal {

/// A dropped column and its null-space vector: col(dropped) = Σ weight·col(kept), in the
/// scaled columns (each normalised to unit length), largest weights first.
struct Dependency {
  int column = 0;
  std::vector<std::pair<int, double>> depends_on;  ///< (column, weight), |weight| ≥ 1e-3
};

struct RankAnalysis {
  std::vector<int> kept;            ///< columns kept, in the order examined
  std::vector<Dependency> dropped;  ///< columns dropped
  Eigen::VectorXd singular_values;  ///< of the kept scaled columns, descending
  [[nodiscard]] double condition_number() const;
};

/// Relative tolerance: a unit column whose component orthogonal to the kept ones is shorter is
/// dependent. Exact dependencies give ~1e-15; identifiable but weakly observed ones ≥ 1e-6.
inline constexpr double kRankTolerance = 1e-8;

/// Examines the columns of J in `order` (indices into J's columns); zero columns are dropped
/// with an empty dependency (the measurements do not see them).
RankAnalysis analyse_rank(const Eigen::MatrixXd& J, const std::vector<int>& order,
                          double tolerance = kRankTolerance);

}  // namespace robcal
