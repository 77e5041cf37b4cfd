#pragma once
/// \file
/// A circle in space fitted to the points a target traces while one joint turns (circle point
/// analysis: the circle's axis is the joint axis). Geometric least squares: for each point p,
/// the distance out of the circle's plane n·(p − c) and the radial distance |w| − r, w the part
/// of p − c in the plane; started from a plane fit (SVD) and an algebraic circle in that plane
/// (Kåsa), refined by Gauss-Newton with the analytic Jacobian.

#include <Eigen/Core>
#include <vector>

namespace robcal::campaign {

struct CircleFit {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();
  /// Unit normal of the circle's plane: the joint axis, turned so that the points advance
  /// counter-clockwise about it as the joint angle grows (right-hand rule).
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double radius_mm = 0;
  double rms_mm = 0;    ///< root mean square of the 2N residuals
  double sigma_mm = 0;  ///< residual σ with 2N − 6 degrees of freedom
  int points = 0;
  int iterations = 0;
};

/// Fits a circle to `points` (≥ 4, not all on one line) taken at joint angles `angles_rad`
/// (same size; they orient the axis).
/// \throws InputError when there are fewer than 4 points, the sizes differ, the points do not
///   span a plane (collinear) or the arc is too short to orient (all angles equal).
CircleFit fit_circle(const std::vector<Eigen::Vector3d>& points,
                     const std::vector<double>& angles_rad);

}  // namespace robcal::campaign
