#pragma once
/// \file
/// The "true" robot of a simulation: a CalibratedRobot whose parameters are the real arm's
/// (docs/method/11-published-results.md §3's identified IRB 120, or random errors within bounds),
/// plus effects the error model of docs/method/03-error-model.md §1 does not contain, so that
/// simulated results are honest about model error:
///
/// - backlash: a joint approached from above stops `backlash_deg` away from where a joint
///   approached from below does (docs/method/05-observability.md §4 approaches every configuration
///   from q − 5°);
/// - a periodic error of joint 6: δθ6 = A·sin(h·q6 + φ) (gearbox eccentricity);
/// - mass error: the true masses and centres of gravity differ from the model's (the truth's
///   RobotModel and payload hold the true ones; the pipeline uses the robot file's);
/// - thermal drift: link lengths a_i, d_i grow by α·ΔT(t), ΔT(t) = ΔT∞·(1 − e^(−t/τ)).
///
/// Frames: the truth's base parameters place the robot in the measurement (world) frame, the
/// frame every simulated reading is expressed in.

#include <array>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/io/yaml_support.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"

namespace robcal {

struct UnmodelledEffects {
  bool backlash = false;
  std::array<double, kJointCount> backlash_deg{0.01, 0.01, 0.01, 0.015, 0.015, 0.015};

  bool j6_periodic = false;
  double j6_amplitude_deg = 0.01;
  double j6_harmonic = 2;  ///< cycles per turn of joint 6
  double j6_phase_deg = 0;

  /// Relative error of masses and CoG drawn for the truth (0 = none); informative only, the
  /// drawn values are in the truth's model and payload.
  double mass_error = 0;

  bool thermal = false;
  double expansion_per_kelvin = 23e-6;  ///< aluminium arm
  double temperature_rise_k = 3;        ///< ΔT∞
  double time_constant_s = 1800;        ///< τ

  [[nodiscard]] bool any() const { return backlash || j6_periodic || mass_error > 0 || thermal; }
};

struct TrueRobot {
  CalibratedRobot robot;  ///< true parameters, true masses (model) and true payload (tool)
  UnmodelledEffects effects;
  std::string origin;  ///< "published", "random (seed N)" or the truth file's path
};

/// Where and how a configuration is reached: what backlash and thermal drift depend on.
struct MotionState {
  bool from_below = true;      ///< every joint approached from below (the published practice)
  Vector6d previous_joints{};  ///< controller joints before the move (when !from_below), rad
  double time_s = 0;           ///< time since the robot started moving (thermal drift)
  /// The arm's temperature rise when it is set (a target reached warm, K); none: the warm-up's
  /// at `time_s`.
  std::optional<double> temperature_rise_k;
  int payload = -1;  ///< carried payload: index into the tool's payloads, -1 its own
};

/// Temperature rise (K) of the thermal drift after `time_s` of operation: first-order warm-up
/// ΔT∞·(1 − e^(−t/τ)), what a thermometer on the arm reads above the robot's reference.
double temperature_rise(const UnmodelledEffects& effects, double time_s);

/// Controller joints (rad) the true arm actually sits at when commanded to `joints`, and the
/// parameters it actually has at `motion.time_s` (the unmodelled effects applied).
struct EffectiveState {
  Vector6d joints;
  ParameterVector params;
};
EffectiveState effective_state(const TrueRobot& truth, const Vector6d& joints,
                               const MotionState& motion);

/// True flange pose (world frame) when the controller is commanded to `joints` (rad).
Pose<double> true_flange_pose(const TrueRobot& truth, const Vector6d& joints,
                              const MotionState& motion = {});

/// The base placement of the reference data set (tests/data/irb120-published/truth.yaml): a
/// laser tracker 1.7 m in front of the robot at the origin of the world,
/// docs/method/11-published-results.md §3's robot. Values x, y, z (mm), alpha, beta, gamma (deg).
std::array<double, 6> default_base_placement();

/// The default tool for simulations: the reference data set's tool (payload 2.6 kg at
/// (−23, 0, 100) mm, SMRs "1", "2", "3").
Tool default_simulation_tool();

/// The identified IRB 120 of docs/method/11-published-results.md §3 placed at `base` (x, y, z mm,
/// alpha, beta, gamma deg). `model` must be the ABB IRB 120 (InputError otherwise).
TrueRobot published_irb120_truth(const RobotModel& model, const Tool& tool,
                                 const std::array<double, 6>& base = default_base_placement());

/// Bounds of random error parameters (uniform in ±bound around nominal; compliance in
/// [0, compliance_max]).
struct ErrorBounds {
  double length_mm = 0.3;        ///< a_i, d_i of links 2..6
  double angle_deg = 0.1;        ///< alpha_i, theta offsets of links 2..6
  double compliance_max = 1e-6;  ///< rad per N·mm, joints 2..6
  double base_length_mm = 1.0;   ///< added to the placement
  double base_angle_deg = 0.1;
};

/// A random true robot: `model`'s nominal geometry plus errors drawn within `bounds`, placed
/// at `base` plus a random base error.
TrueRobot random_truth(const RobotModel& model, const Tool& tool, const ErrorBounds& bounds,
                       std::mt19937_64& rng,
                       const std::array<double, 6>& base = default_base_placement());

/// Draws the true masses and centres of gravity (model links and tool payload) within
/// ±fraction of the given ones, and records the fraction in the effects.
void apply_mass_error(TrueRobot& truth, double fraction, std::mt19937_64& rng);

/// Turns on the unmodelled effects named on the command line: "backlash", "j6-periodic",
/// "mass-error" (draws masses and CoG within ±10 %), "thermal". InputError naming `flag` for an
/// unknown name.
void enable_effects(TrueRobot& truth, const std::vector<std::string>& names, std::mt19937_64& rng,
                    const std::string& flag = "--effects");

/// Truth file (YAML, mm and degrees), a superset of tests/data/irb120-published/truth.yaml:
/// robot (built-in name or full description), base, links 2..6 [alpha, a, theta, d,
/// compliance], scales, true masses, payload, targets and the unmodelled effects.
std::string truth_to_yaml(const TrueRobot& truth, const std::string& robot_name);

/// Reads a truth file. `robot` is used when the file names none and `tool` gives the targets
/// and payload when it lists none (the reference set's file has neither). Errors name the
/// file, line and key.
TrueRobot load_truth(const std::string& path, const std::string& robot = "abb-irb120",
                     const Tool& tool = default_simulation_tool());
TrueRobot parse_truth(const yaml::Node& root, const std::string& robot = "abb-irb120",
                      const Tool& tool = default_simulation_tool());

}  // namespace robcal
