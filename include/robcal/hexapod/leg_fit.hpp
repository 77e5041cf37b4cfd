#pragma once
/// \file
/// Identification straight from the raw ballbar readings (beyond the published method, which
/// fits poses from the DKP): one Ceres fit whose residuals are the measured distances —
/// every leg |B_a − H(q)·T_b| and the fixture sides — and whose unknowns are the robot's
/// parameters (relative model, docs/method/03-error-model.md §1: base held), the base cups in the
/// robot frame, the tool cups in the flange frame and the ballbar's length offset at its leg
/// set-up. Several base-fixture placements each bring their own base cups (their world-frame
/// unknowns, docs/method/08-world-frame.md §4); the robot, the tool cups and the offset are
/// shared.
///
/// Dependencies handled by name: with free tool cups, link6.d and link6.theta only move the cups
/// (a shift along and a turn about the flange axis) and are held; any further rank deficiency of
/// the column-scaled Jacobian (rank-revealing QR) holds the dependent unknowns and names them.

#include <optional>
#include <string>
#include <vector>

#include "robcal/hexapod/measurement.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal::hexapod {

struct LegFitOptions {
  std::vector<int> free_parameters;  ///< model parameter indices to identify (never base.*)
  bool fit_length_offset = true;     ///< the ballbar's offset at its leg set-up length
  int max_iterations = 100;
};

struct LegFitResult {
  ParameterVector params = ParameterVector::Zero();
  std::vector<Cups<double>> base_cups_robot;  ///< per placement, robot frame, mm
  /// Per placement: its fourth base cup's, robot frame, mm (when its fixture has one).
  std::vector<std::optional<Eigen::Vector3d>> base_cup4_robot;
  Cups<double> tool_cups_flange;                      ///< flange frame, mm
  std::optional<Eigen::Vector3d> tool_cup4_flange{};  ///< a fourth tool cup's, flange frame, mm
  double length_offset_mm = 0;    ///< true length = reading + offset (leg set-up)
  std::vector<int> identified;    ///< model parameters fitted
  std::vector<std::string> held;  ///< unknowns held, each with why
  int residuals = 0;
  double initial_rms_mm = 0;
  double rms_mm = 0;
  int iterations = 0;
  bool converged = false;
  std::string message;  ///< Ceres' termination reason
  /// The fitted unknowns, as indices into the model parameters followed by the extras: per
  /// placement 3 coordinates (x y z) of each base cup (B1..B3, then B4), 3 per tool cup (T1..T3,
  /// then T4) and the offset.
  std::vector<int> unknowns;
  double sigma_mm = 0;         ///< a-posteriori σ̂ of one reading, √(RSS / (m − n))
  Eigen::MatrixXd covariance;  ///< σ̂²(JᵀJ)⁻¹ of `unknowns` at the solution (internal units)
};

/// One base-fixture placement's data: its measured distances (a fourth cup's too), the readings
/// taken there and the world frame its cups B1..B3 were placed in (robot frame; world_frame.hpp).
struct LegPlacement {
  FixtureDistances base;
  std::vector<LegReadings> readings;
  Pose<double> robot_T_world;
};

/// Fits from the readings of one or more placements. Start: `start_params`, each placement's base
/// cups where its world frame puts them (`robot_T_world` × its measured base fixture: a fourth
/// base cup is unknowns of its placement, its distances residuals at their own set-up), the tool
/// cups (a fourth one too: its legs are the readings' extra legs, its distances residuals like the
/// sides) from the measured tool fixture through `flange_T_tool`, offset 0. Throws InputError when
/// a start index is a base parameter or no placement is given.
LegFitResult fit_from_legs(const RobotModel& model, const PointMass& payload,
                           const FixtureDistances& tool,
                           const std::vector<LegPlacement>& placements,
                           const ParameterVector& start_params, const Pose<double>& flange_T_tool,
                           const LegFitOptions& options);

/// One placement.
LegFitResult fit_from_legs(const RobotModel& model, const PointMass& payload,
                           const FixtureDistances& base, const FixtureDistances& tool,
                           const std::vector<LegReadings>& readings,
                           const ParameterVector& start_params, const Pose<double>& robot_T_world,
                           const Pose<double>& flange_T_tool, const LegFitOptions& options);

/// The leg fit as a calibrated robot in the frame of the pose fit: the world frame the (first
/// placement's) base cups define seen from the robot frame through `robot_T_world`
/// (world_frame.hpp). The fitted base cups give that world frame in the fit's own robot frame; the
/// six base parameters carry the difference, written exactly as world_A_1 = Trans(x, y, d1 + z) ·
/// Rx Ry Rz(γ + θ1), and the gravity vector is turned with them (the compliance sees the same
/// torques). Its tool: the fitted tool cups as targets T1..T3, the tool fixture frame they define
/// as TCP. Its covariance is the fit's, carried to the six base parameters through the first
/// placement's base cups they are computed from.
CalibratedRobot leg_fit_robot(const RobotModel& model, const PointMass& payload,
                              const LegFitResult& fit, const Pose<double>& robot_T_world);

}  // namespace robcal::hexapod
