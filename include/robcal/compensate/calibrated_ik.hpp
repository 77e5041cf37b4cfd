#pragma once
/// \file
/// Inverse kinematics of the calibrated robot (docs/method/10-compensation.md, 02-frames.md §7):
/// the controller joints that put the TCP at a wanted world pose on the calibrated model,
/// compliance included, in a chosen arm configuration. Two iterations, both seeded by the nominal
/// closed form (kinematics/inverse_kinematics.hpp):
///
/// - Newton: j ← j + J⁻¹·e with the exact Jacobian of calibrated_chain.hpp and the world pose
///   error e = (p* − p, log(R*·Rᵀ)), the first step from the seed corrected to second order by
///   the chain's curvature (calibrated_jacobian_derivative); 2 iterations in 98 % of the
///   cases (IRB 120, ≥ 5° from singularities), 2.4 on average without the correction.
/// - Pose shift: needs only the nominal inverse and the calibrated forward model. With T the
///   pose commanded to the nominal inverse and F(T) the calibrated TCP pose its joints give,
///   T ← T · F(T)⁻¹ · T*; linear convergence (errors of a world frame are absorbed in one step).
///
/// Every answer is checked by the calibrated forward model before it is reported Converged;
/// anything else (no nominal seed, a singular Jacobian, a step that leaves the configuration,
/// a joint limit) comes back as a status, never as joints that miss the pose.

#include <cstdint>
#include <optional>
#include <string>

#include "robcal/compensate/calibrated_chain.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/kinematics/closed_form_ik.hpp"

namespace robcal {

/// Half the accuracy asked of compensation (1e-6 mm and 1e-6°, issue 7), as a margin.
struct CalibratedIkOptions {
  int max_iterations = 12;
  double position_tolerance_mm = 5e-7;
  double orientation_tolerance_rad = 8.7e-9;  ///< ≈ 5e-7°
  /// An iterate further than this from its nominal seed (any joint, rad) is abandoned: it is
  /// heading for another turn or branch. Converged answers are also checked to be in the arm
  /// configuration asked for (calibrated_ik_newton: the seed's).
  double max_joint_change_rad = 1.0;
};

enum class CalibratedIkStatus : std::uint8_t {
  Converged,          ///< within tolerance, inside the joint limits
  NoNominalSolution,  ///< the configuration asked for does not reach the pose (nominal model)
  Singular,           ///< the Jacobian (or the step) degenerated: at or near a singularity
  LeftConfiguration,  ///< drifted beyond max_joint_change_rad, or converged in another branch
  NotConverged,       ///< max_iterations reached
  OutsideLimits,      ///< reaches the pose, but a joint is outside its limits (already the
                      ///< nominal seed when it lies beyond a limit by kSeedLimitMarginRad)
};

const char* to_string(CalibratedIkStatus status);

enum class IkMethod : std::uint8_t { Newton, PoseShift };

struct CalibratedIkResult {
  CalibratedIkStatus status = CalibratedIkStatus::NoNominalSolution;
  Vector6d joints = Vector6d::Zero();  ///< controller joints, rad
  /// The iteration that produced `joints`: calibrated_ik with Newton hands over to pose shift
  /// when Newton leaves the configuration.
  IkMethod method = IkMethod::Newton;
  int iterations = 0;            ///< forward-model evaluations after the seed
  double position_error_mm = 0;  ///< at `joints`, calibrated model
  double orientation_error_rad = 0;
  [[nodiscard]] bool ok() const { return status == CalibratedIkStatus::Converged; }
};

/// How far (rad) the nominal seed may lie beyond a joint limit and still be iterated: the
/// calibrated solution differs from the nominal one by a fraction of a degree, and by a few
/// degrees in θ4, θ6 near the wrist singularity and θ1 near axis 1, so a seed beyond a limit
/// can have its answer inside; the verdict is taken on the calibrated joints.
inline constexpr double kSeedLimitMarginRad = 0.175;  // 10°

/// How targets are reached, as far as the opt-in groups care (docs/method/03-error-model.md
/// §6–§8): the compensator of each distinct condition is made once.
struct ReachCondition {
  /// The side each joint reaches the targets from (+1 below, −1 above, 0 unknown): the backlash
  /// group's sign (§6).
  Vector6d approach = Vector6d::Ones();
  /// The targets' temperature minus the robot's reference (K): the thermal group's ΔT (§8).
  double temperature_rise_k = 0;
  /// How far the arm has warmed up, φ = 1 − exp(−t/τ) (1 warm, 0 cold): the warm-up group's
  /// factor (§10).
  double warmup_fraction = 0;
  /// The time φ is of (s since the arm started working; ∞: fully warm); none: cold, or φ given
  /// directly. Recorded for the corrected targets and the closed-loop check.
  std::optional<double> warmup_time_s;
  PointMass payload;  ///< the payload the compliance is computed for (§3, §7)
  /// Its name among the tool's `payloads`; empty: the tool's `payload` or one given by mass.
  std::string payload_name;

  [[nodiscard]] bool operator==(const ReachCondition& other) const {
    return approach == other.approach && temperature_rise_k == other.temperature_rise_k &&
           warmup_fraction == other.warmup_fraction && warmup_time_s == other.warmup_time_s &&
           payload.mass_kg == other.payload.mass_kg && payload.cog_mm == other.payload.cog_mm &&
           payload_name == other.payload_name;
  }
};

/// Everything the calibrated inverse needs for one robot, tool and reach condition. Immutable.
struct Compensator {
  RobotModel model;
  CalibratedChain chain;
  ClosedFormIk geometry;       ///< the nominal robot's closed form (closed_form_ik.hpp)
  ClosedFormIk seed_geometry;  ///< the same, limits widened by kSeedLimitMarginRad
  /// The wrist is spherical (axes 4–6 meet): Newton solves its steps through the wrist
  /// partition; otherwise (UR family) by a pivoted LU of the whole Jacobian.
  bool spherical_wrist = true;
  /// The controller's base frame in the world: where the nominal base sits when frame Φ1 is
  /// where the calibrated model puts it, world_T_base = world_A_1(q1=0) · base_A_1(q1=0)⁻¹.
  Pose<double> world_T_base;
  Pose<double> base_T_world;  ///< its inverse
  Pose<double> flange_T_tcp;
  Pose<double> tcp_T_flange;  ///< its inverse
  ReachCondition condition;   ///< the chain is built for it
};

/// Builds the compensator of a calibrated robot; `payload` overrides the tool's (the
/// compliance re-compensates for it). InputError when the robot has no closed-form nominal
/// inverse (neither ortho-parallel nor of the UR family) or a parameter is not finite.
/// `row`: the side each joint reaches its targets from (+1 below, −1 above; null: from below,
/// the measurement programs' practice), for the backlash group (docs/method/03-error-model.md
/// §6), their temperature rise over the robot's reference, for the thermal group (§8), and the
/// arm's warm-up, for the warm-up group (§10).
Compensator make_compensator(const CalibratedRobot& robot,
                             const std::optional<PointMass>& payload = std::nullopt,
                             const RowConditions& row = {});
/// The same for targets reached under `condition` (its payload replaces the tool's).
Compensator make_compensator(const CalibratedRobot& robot, const ReachCondition& condition);

/// The nominal solution (controller joints, rad) of `base_T_tcp` in configuration `config`
/// inside the limits, of the turn nearest to `near` (wide-range joints), or nullopt.
std::optional<Vector6d> nominal_solution(const Compensator& comp, const Pose<double>& base_T_tcp,
                                         const ArmConfig& config, const Vector6d& near);

/// TCP pose (controller base frame) of the nominal model: what the controller displays.
Pose<double> nominal_tcp_pose(const Compensator& comp, const Vector6d& joints);

/// Newton iteration on the calibrated model from `seed` (controller joints, rad).
CalibratedIkResult calibrated_ik_newton(const Compensator& comp, const Pose<double>& world_T_tcp,
                                        const Vector6d& seed,
                                        const CalibratedIkOptions& options = {});

/// Pose-shift iteration, each step a nominal closed-form solve in configuration `config`
/// nearest to the previous joints, starting from `seed`.
CalibratedIkResult calibrated_ik_pose_shift(const Compensator& comp,
                                            const Pose<double>& world_T_tcp,
                                            const ArmConfig& config, const Vector6d& seed,
                                            const CalibratedIkOptions& options = {});

/// Seeds from the nominal solution (world pose taken into the base frame) and iterates; when
/// Newton leaves the configuration asked for, pose shift from the same seed.
CalibratedIkResult calibrated_ik(const Compensator& comp, const Pose<double>& world_T_tcp,
                                 const ArmConfig& config, const Vector6d& near,
                                 IkMethod method = IkMethod::Newton,
                                 const CalibratedIkOptions& options = {});

/// calibrated_ik when the nominal solution of `config` is at hand (`seed`, within the joint
/// limits: the caller solved the branch to read its configuration data): the same answer
/// without a second nominal solve.
CalibratedIkResult calibrated_ik_from_seed(const Compensator& comp, const Pose<double>& world_T_tcp,
                                           const ArmConfig& config, const Vector6d& seed,
                                           IkMethod method = IkMethod::Newton,
                                           const CalibratedIkOptions& options = {});

}  // namespace robcal
