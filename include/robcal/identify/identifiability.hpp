#pragma once
/// \file
/// Which unknowns the measurements can determine (docs/method/03-error-model.md §2,
/// 04-identification.md): a rank-revealing QR of the column-scaled identification Jacobian that
/// keeps columns in a preferred order, so that of a dependent group the later one is dropped
/// (`link3.d`, not `link2.d`, on a robot whose axes 2 and 3 are parallel), and the null-space
/// vector of each dropped column names what it depends on.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace robcal {

/// A dropped column and its null-space vector: col(dropped) = Σ weight·col(kept), in the
/// scaled columns (each normalised to unit length), largest weights first.
struct Dependency {
  int column = 0;
  std::vector<std::pair<int, double>> depends_on;  ///< (column, weight), |weight| ≥ 1e-3
  /// Multiple correlation of the column with the kept ones (1 for an exact dependency).
  double correlation = 1.0;
  /// Why, when not a linear dependency (e.g. "gravity torque about axis 4 is below …").
  std::string reason;
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

/// Examines the columns of J in `order` (indices into J's columns); zero columns, and columns
/// whose norm is at most `negligible_norm`, are dropped with an empty dependency (the
/// measurements do not see them).
RankAnalysis analyse_rank(const Eigen::MatrixXd& J, const std::vector<int>& order,
                          double tolerance = kRankTolerance, double negligible_norm = 0.0);

/// Effect (mm, summed in quadrature over every residual) below which an unknown's plausible
/// error (UnknownLayout::plausible_error) counts as not seen: 1 nm is rounding, not a signal
/// (a target on joint 6's axis gives link6.theta a column of ~1e-13 mm/rad, not zero).
inline constexpr double kNegligibleEffectMm = 1e-6;

/// σ, in plausible errors, past which the data do not determine an unknown at all: 10 mm or
/// 10 mrad (0.6°) is beyond any real arm's error, so a fitted value would be noise.
inline constexpr double kUndeterminedFactor = 10.0;

/// Measurement noise (mm per residual) assumed when deciding near-dependence before a fit and no
/// instrument σ is stated: a laser tracker's 0.02–0.05 mm, taken at its upper end.
inline constexpr double kReferenceNoiseMm = 0.05;

/// Multiple correlation past which a column counts as nearly dependent on the others: with
/// unit columns K, [(KᵀK)⁻¹]_jj = 1/(1 − R_j²) is the factor by which the others inflate the
/// variance of unknown j; R_j ≥ 0.999 inflates it ≥ 500 times (σ ≥ 22 times what the column
/// alone gives), the regime where a fit returns a parameter degrees off with an equally large σ
/// (one target on the tool axis: link5.theta with link6.a at R = 0.99999). Pairs of the
/// published three-target designs stay below 0.99.
inline constexpr double kNearDependenceCorrelation = 0.999;

/// Near-dependent columns of a full-rank J whose columns are the effects (mm) of each unknown's
/// plausible error, examined in `order` (indices into J's columns): while some remaining column
/// has a multiple correlation with the others of at least `threshold` and is determined worse
/// than its plausible error (σ = noise_mm·√VIF/‖column‖ > 1: a fit could move it beyond any
/// real arm's error), the latest such column in `order` is removed, with its least-squares
/// combination of the remaining ones (weights as in analyse_rank) and its correlation; so is a
/// column determined worse than kUndeterminedFactor plausible errors whatever its correlation
/// (a target 0.02 mm off joint 6's axis barely sees link6.theta). A well-determined parameter
/// stays however correlated: holding it would bias the model.
std::vector<Dependency> near_dependencies(const Eigen::MatrixXd& J, const std::vector<int>& order,
                                          double noise_mm,
                                          double threshold = kNearDependenceCorrelation);

}  // namespace robcal
