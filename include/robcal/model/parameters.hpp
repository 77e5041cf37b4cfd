#pragma once
/// \file
/// The robot's parameter vector: every quantity the error model of docs/method/03-error-model.md §1
/// may identify, stored as absolute values in internal units (mm, rad, rad/(N·mm), unitless scale).
///
/// Layout (kParameterCount = 104):
///   [0, 6)   base.x base.y base.z (mm), base.alpha base.beta base.gamma (rad):
///            world_A_1 = Trans(x, y, d1 + z) · Rot_x(alpha) · Rot_y(beta) · Rot_z(gamma + θ1)
///   [6, 26)  linkI.alpha (rad), linkI.a (mm), linkI.theta (rad, the joint zero offset),
///            linkI.d (mm) for I = 2..6 (MDH, Craig)
///   [26, 31) jointI.compliance (rad per N·mm of gravity torque) for I = 2..6
///   [31, 37) jointI.scale (unitless, θ_real = scale · q + offset; level 1) for I = 1..6
///   [37, 61) jointI.periodicH.cos, jointI.periodicH.sin (rad) for I = 1..6, H = 1, 2: the
///            periodic joint error δθ_I = Σ_H (cos_H·cos(H·q_I) + sin_H·sin(H·q_I)), an opt-in
///            group (docs/method/03-error-model.md §5), zero and fixed unless asked for.
///   [61, 67) jointI.backlash (rad) for I = 1..6: the dead band b_I of the joint, θ_I shifted by
///            −s_I·b_I/2 for a joint approached from below (s = +1) or above (s = −1), an
///            opt-in group (docs/method/03-error-model.md §6).
///   [67]     joint1.compliance (rad per N·mm): joint 1 under gravity, loaded only when the
///            robot is not floor-mounted (inclined, wall, ceiling); an opt-in group
///            (docs/method/03-error-model.md §7).
///   [68, 73) linkI.expansion (1/K inside, ppm/K in files) for I = 2..6: thermal drift, a_I and
///            d_I scaled by (1 + e_I·ΔT), ΔT the row's temperature minus the robot's reference
///            temperature; an opt-in group (docs/method/03-error-model.md §8).
///   [73, 97) jointI.motor_periodicH.cos, jointI.motor_periodicH.sin (rad) for I = 1..6, H = 1, 2:
///            the periodic error of joint I's motor, δθ_I = Σ_H (cos_H·cos(H·r_I·q_I) +
///            sin_H·sin(H·r_I·q_I)), r_I the robot file's gear ratio of joint I; an opt-in group
///            for joints with a gear ratio (docs/method/03-error-model.md §9).
///   [97, 102) linkI.warmup_growth (mm) for I = 2..6: thermal drift without a temperature, the
///            growth of link I's length L_I = √(a_I² + d_I²) (nominal) at full warm-up, i.e. its
///            expansion coefficient times the warm-up's ΔT∞ times L_I; a_I, d_I scaled by
///            (1 + w_I·φ(t)/L_I), φ(t) = 1 − exp(−t/τ) of the row's time; an opt-in group
///            (docs/method/03-error-model.md §10).
///   [102, 104) gravity.tilt_a, gravity.tilt_b (rad): the direction of gravity identified, the
///            robot file's vector turned about two axes perpendicular to it, in the frame it is
///            given in (world, or base for an inclined, wall or ceiling mounting); seen through
///            the compliances only; an opt-in group (docs/method/03-error-model.md §11).
/// The 31 of the published full model are the first 31; scales are fixed unless asked for.

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace robcal {

inline constexpr int kJointCount = 6;
inline constexpr int kBaseParamCount = 6;
inline constexpr int kLinkParamOffset = 6;
inline constexpr int kComplianceOffset = 26;
inline constexpr int kScaleOffset = 31;
inline constexpr int kPeriodicOffset = 37;
inline constexpr int kPeriodicHarmonics = 2;  ///< first and second harmonic of the joint angle
inline constexpr int kPeriodicPerJoint = 2 * kPeriodicHarmonics;
inline constexpr int kBacklashOffset = kPeriodicOffset + kJointCount * kPeriodicPerJoint;
/// The mounting group (docs/method/03-error-model.md §7) follows the backlash group.
inline constexpr int kMountingOffset = kBacklashOffset + kJointCount;
inline constexpr int kJoint1Compliance = kMountingOffset;  ///< joint1.compliance
inline constexpr int kMountingParamCount = 1;
/// The thermal group (docs/method/03-error-model.md §8) follows the mounting group.
inline constexpr int kThermalOffset = kMountingOffset + kMountingParamCount;
inline constexpr int kThermalParamCount = kJointCount - 1;  ///< links 2..6
/// The motor-angle periodic group (docs/method/03-error-model.md §9) follows the thermal group.
inline constexpr int kMotorPeriodicOffset = kThermalOffset + kThermalParamCount;
/// The warm-up group (docs/method/03-error-model.md §10) follows the motor-angle periodic group.
inline constexpr int kWarmupOffset = kMotorPeriodicOffset + kJointCount * kPeriodicPerJoint;
/// The gravity group (docs/method/03-error-model.md §11) follows the warm-up group.
inline constexpr int kGravityOffset = kWarmupOffset + kThermalParamCount;
inline constexpr int kGravityTiltA = kGravityOffset;      ///< gravity.tilt_a
inline constexpr int kGravityTiltB = kGravityOffset + 1;  ///< gravity.tilt_b
inline constexpr int kParameterCount = kGravityOffset + 2;

/// Index of MDH quantity k (0 alpha, 1 a, 2 theta, 3 d) of link i (2..6).
constexpr int link_param(int link, int k) {
  return kLinkParamOffset + 4 * (link - 2) + k;
}
/// Index of the compliance of joint i (2..6; joint 1's is kJoint1Compliance, opt-in).
constexpr int compliance_param(int joint) {
  return joint == 1 ? kJoint1Compliance : kComplianceOffset + (joint - 2);
}
/// Index of the scale of joint i (1..6).
constexpr int scale_param(int joint) {
  return kScaleOffset + (joint - 1);
}

/// Index of the periodic error of joint i (1..6), harmonic h (1..kPeriodicHarmonics), cosine
/// (sine = false) or sine term.
constexpr int periodic_param(int joint, int harmonic, bool sine) {
  return kPeriodicOffset + kPeriodicPerJoint * (joint - 1) + 2 * (harmonic - 1) + (sine ? 1 : 0);
}

/// Index of the motor-angle periodic error of joint i (1..6), harmonic h (1..kPeriodicHarmonics),
/// cosine (sine = false) or sine term.
constexpr int motor_periodic_param(int joint, int harmonic, bool sine) {
  return kMotorPeriodicOffset + kPeriodicPerJoint * (joint - 1) + 2 * (harmonic - 1) +
         (sine ? 1 : 0);
}

/// Index of the backlash (dead band) of joint i (1..6).
constexpr int backlash_param(int joint) {
  return kBacklashOffset + (joint - 1);
}

/// Index of the thermal expansion coefficient of link i (2..6): a_i, d_i grow by e_i·ΔT.
constexpr int expansion_param(int link) {
  return kThermalOffset + (link - 2);
}

/// Index of the warm-up growth of link i (2..6): its length's growth (mm) at full warm-up.
constexpr int warmup_param(int link) {
  return kWarmupOffset + (link - 2);
}

enum class ParamKind { Length, Angle, Compliance, Scale, Expansion };

/// Name, kind and external unit of one parameter of the layout.
struct ParameterInfo {
  std::string name;  ///< stable dotted name, e.g. "link3.a", "joint5.compliance"
  ParamKind kind;
  std::string unit;  ///< external unit: "mm", "deg", "rad/N·mm", "1", "ppm/K"
  /// Factor from internal to external units (1 for mm, 180/π for angles, 10⁶ for 1/K → ppm/K).
  [[nodiscard]] double to_external() const;
};

/// The kParameterCount parameters in layout order.
const std::array<ParameterInfo, kParameterCount>& parameter_table();

/// Opt-in parameter groups (docs/method/03-error-model.md §5): parameters outside every
/// calibration level, enabled by pattern (`--identify 'joint6.periodic*'`), written to model
/// files and reported with their significance only when enabled.
struct ParameterGroup {
  std::string name;         ///< e.g. "joint6.periodic"
  std::vector<int> params;  ///< indices in the layout
};

/// The opt-in groups: one periodic group per joint ("joint1.periodic" .. "joint6.periodic"),
/// then one backlash group per joint ("joint1.backlash" .. "joint6.backlash"), then
/// "joint1.compliance" (docs/method/03-error-model.md §7), then "thermal" (the five
/// linkI.expansion, §8), then one motor-angle periodic group per joint ("joint1.motor_periodic" ..
/// "joint6.motor_periodic", §9), then "warmup" (the five linkI.warmup_growth, §10), then
/// "gravity" (gravity.tilt_a, gravity.tilt_b, §11).
const std::vector<ParameterGroup>& opt_in_groups();

/// The parameters of the opt-in groups a name selects (`--identify thermal`): one group's name
/// ("joint6.periodic", "thermal"), a family of them ("periodic", "backlash", "motor_periodic"),
/// "mounting" (joint1.compliance) or "groups" (every opt-in parameter); empty for any other name.
/// A family or "groups" selects motor_periodic groups only where they apply (the identification
/// leaves out joints without a gear ratio: selects_by_family).
std::vector<int> opt_in_group_parameters(std::string_view name);

/// True when the name selects opt-in groups as a family ("groups", "motor_periodic"), which
/// includes the motor-angle groups of the joints that have a gear ratio only, rather than by a
/// group's or a parameter's own name (a request for a gearless joint, refused).
bool selects_by_family(std::string_view name);

/// True for a parameter of an opt-in group.
bool is_opt_in(int index);

/// Index of a parameter by its dotted name, or -1.
int parameter_index(std::string_view name);

/// Indices whose names match a glob pattern ('*' and '?'), e.g. "link6.*", "*.compliance".
std::vector<int> match_parameters(std::string_view pattern);

/// Simple glob match ('*' any run, '?' one character), shared by every name filter.
bool glob_match(std::string_view pattern, std::string_view text);

}  // namespace robcal
