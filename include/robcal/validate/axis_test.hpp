#pragma once
/// \file
/// Per-axis test (the published per-joint test, docs/method/09-validation.md): one joint moves
/// through its range with the others fixed while a target on the arm is measured; every position is
/// reached once from below and once from above. The target then runs on a circle about the joint's
/// axis:
///
/// 1. plane: least-squares plane through all positions (smallest singular vector n of the
///    centred positions); axial error e_a = n·(p − p̄);
/// 2. circle: in the plane, the centre c and radius r minimising Σ(|q − c| − r)² (algebraic
///    start, then Gauss–Newton); radial error e_r = |q − c| − r;
/// 3. angle: φ, the target's angle about c in the plane (unwrapped in joint order), fitted by
///    φ = φ0 + g·θ + β·[approached from above] (least squares; g ≈ 1 is the joint's scale,
///    n is oriented so that g > 0); the backlash is β/g (joint angle); tangential error
///    e_t = r·(φ − φ̂).
/// σ: the backlash's from the covariance of the angle fit, σ² = RSS/(N − 3)·(AᵀA)⁻¹; the
/// axis tilt's from the plane fit, σ_tilt = s_a·√(1/S_1 + 1/S_2) with s_a the axial residual
/// std (N − 3 degrees of freedom) and S_k the positions' scatter along the plane's two axes.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/validate/error_statistics.hpp"

namespace robcal {

/// One commanded move of the test: go to `approach_from`, then to `joints`.
struct AxisTestMove {
  Vector6d joints = Vector6d::Zero();         ///< controller joints, rad
  Vector6d approach_from = Vector6d::Zero();  ///< where the move starts
  bool from_above = false;
};

struct AxisTestPlanRequest {
  Vector6d home = Vector6d::Zero();  ///< the fixed joints (rad)
  int joint = 0;                     ///< 0-based joint that moves
  double from_rad = 0, to_rad = 0;   ///< its range
  int steps = 12;                    ///< positions (≥ 3), each reached from both sides
  double approach_rad =
      0.0873;  ///< 5°, as docs/method/05-observability.md §4 approaches configurations
};

/// The moves: positions from → to, each from below then from above.
/// \throws InputError for fewer than 3 steps, an empty range, an approach distance <= 0 or a
/// joint outside 0..5
std::vector<AxisTestMove> axis_test_moves(const AxisTestPlanRequest& request);

struct AxisTestSample {
  double joint_rad = 0;  ///< commanded angle of the moving joint
  bool from_above = false;
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();
};

struct AxisTestResult {
  int samples = 0;
  Eigen::Vector3d axis_direction = Eigen::Vector3d::UnitZ();  ///< unit; positive joint sense
  Eigen::Vector3d axis_point_mm = Eigen::Vector3d::Zero();    ///< the circle's centre
  double radius_mm = 0;
  double scale = 1;  ///< g: dφ/dθ
  double backlash_deg = 0, backlash_sigma_deg = 0;
  double tilt_sigma_deg = 0;  ///< σ of the axis direction (angle)
  /// Residuals (mm): absolute-value statistics and the residual standard deviation.
  ErrorStatistics tangential_mm, radial_mm, axial_mm;
  double tangential_sigma_mm = 0, radial_sigma_mm = 0, axial_sigma_mm = 0;
};

/// The moves as CSV `move,side,j1..j6` (degrees; side approach, below or above): measure the
/// target after every "below" and "above" move.
std::string axis_test_moves_csv(const std::vector<AxisTestMove>& moves);

/// Reads measured positions: CSV `joint_deg,side,x,y,z` (side below or above; mm, degrees).
/// InputError naming file, line, column for anything else.
std::vector<AxisTestSample> read_axis_test_samples(const std::string& path);
std::vector<AxisTestSample> parse_axis_test_samples(const std::string& text,
                                                    const std::string& file);

/// Fits the circle, the angle law and the backlash.
/// \throws InputError for fewer than 6 samples, no sample from one of the two sides, or
///   positions that do not span a circle (all on one line, or the joint range under 1°)
AxisTestResult axis_test_analyse(const std::vector<AxisTestSample>& samples);

/// Angle (deg) between the fitted axis and a reference direction, as lines (0..90°).
double axis_tilt_deg(const AxisTestResult& result, const Eigen::Vector3d& reference_direction);

}  // namespace robcal
