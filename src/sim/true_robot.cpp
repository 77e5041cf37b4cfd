#include "robcal/sim/true_robot.hpp"

#include <fmt/format.h>

#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/yaml_checks.hpp"
#include "yaml_list.hpp"

namespace robcal {
namespace {

void set_base(ParameterVector& params, const std::array<double, 6>& base) {
  for (int k = 0; k < 3; ++k) params[k] = base[static_cast<size_t>(k)];
  for (int k = 3; k < 6; ++k) params[k] = deg2rad(base[static_cast<size_t>(k)]);
}

TrueRobot make_truth(const RobotModel& model, const Tool& tool, std::string origin) {
  TrueRobot truth;
  truth.robot = CalibratedRobot::nominal(model, tool);
  truth.robot.base_fitted = true;
  truth.robot.level = "truth";
  truth.origin = std::move(origin);
  return truth;
}

}  // namespace

double temperature_rise(const UnmodelledEffects& effects, double time_s) {
  return effects.temperature_rise_k * (1.0 - std::exp(-time_s / effects.time_constant_s));
}

EffectiveState effective_state(const TrueRobot& truth, const Vector6d& joints,
                               const MotionState& motion) {
  const UnmodelledEffects& fx = truth.effects;
  EffectiveState state{joints, truth.robot.params};
  if (fx.backlash && !motion.from_below)
    for (int i = 0; i < kJointCount; ++i)
      if (joints[i] < motion.previous_joints[i])  // arrived from above: the other gear flank
        state.joints[i] += deg2rad(fx.backlash_deg[static_cast<size_t>(i)]);
  if (fx.j6_periodic)
    state.joints[5] += deg2rad(fx.j6_amplitude_deg) *
                       std::sin(fx.j6_harmonic * joints[5] + deg2rad(fx.j6_phase_deg));
  if (fx.thermal) {
    const double growth = 1.0 + fx.expansion_per_kelvin * motion.temperature_rise_k.value_or(
                                                              temperature_rise(fx, motion.time_s));
    for (int link = 2; link <= kJointCount; ++link) {
      state.params[link_param(link, 1)] *= growth;
      state.params[link_param(link, 3)] *= growth;
    }
  }
  return state;
}

Pose<double> true_flange_pose(const TrueRobot& truth, const Vector6d& joints,
                              const MotionState& motion) {
  const PointMass& payload = truth.robot.tool.payload_of(motion.payload);
  if (!truth.effects.backlash && !truth.effects.j6_periodic && !truth.effects.thermal)
    return flange_pose(truth.robot.model, payload, truth.robot.params, joints);
  const EffectiveState state = effective_state(truth, joints, motion);
  return flange_pose(truth.robot.model, payload, state.params, state.joints);
}

std::array<double, 6> default_base_placement() {
  return {-812.25, 1503.5, -95.0, 0.25, -0.4, -57.0};
}

Tool default_simulation_tool() {
  Tool tool;
  tool.payload = {2.6, Eigen::Vector3d(-23, 0, 100)};
  tool.targets = {{"1", Eigen::Vector3d(0, 0, 125), true},
                  {"2", Eigen::Vector3d(75, 93.675, 215), true},
                  {"3", Eigen::Vector3d(150, 0, 125), true}};
  return tool;
}

TrueRobot published_irb120_truth(const RobotModel& model, const Tool& tool,
                                 const std::array<double, 6>& base) {
  const auto& m = model.mdh;
  const bool is_irb120 = m[0].d == 290 && m[2].a == 270 && m[3].a == 70 && m[3].d == 302 &&
                         m[5].d == 72 && m[1].a == 0;
  if (!is_irb120)
    throw InputError({"", 0, 0, "--truth"},
                     fmt::format("the published identified model "
                                 "(docs/method/11-published-results.md) is an ABB IRB 120; "
                                 "robot '{}' is not: use --truth random or a truth file",
                                 model.name));
  TrueRobot truth = make_truth(model, tool, "published");
  ParameterVector& x = truth.robot.params;
  set_base(x, base);
  // docs/method/11-published-results.md §3, links 2..6: alpha (deg), a (mm), theta offset (deg), d
  // (mm), compliance.
  const double links[5][5] = {{-90.006, 0.134, -89.909, 0.000, 0.032e-6},
                              {-0.011, 270.236, 0.054, 0.006, 0.130e-6},
                              {-90.009, 70.138, -0.027, 302.246, 0.605e-6},
                              {89.984, -0.061, 0.067, -0.067, 0.419e-6},
                              {-89.969, 0.022, 179.913, 72.050, 0.647e-6}};
  for (int link = 2; link <= kJointCount; ++link) {
    const double* row = links[link - 2];
    x[link_param(link, 0)] = deg2rad(row[0]);
    x[link_param(link, 1)] = row[1];
    x[link_param(link, 2)] = deg2rad(row[2]);
    x[link_param(link, 3)] = row[3];
    x[compliance_param(link)] = row[4];
  }
  return truth;
}

TrueRobot random_truth(const RobotModel& model, const Tool& tool, const ErrorBounds& bounds,
                       std::mt19937_64& rng, const std::array<double, 6>& base) {
  TrueRobot truth = make_truth(model, tool, "random");
  ParameterVector& x = truth.robot.params;
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  set_base(x, base);
  for (int k = 0; k < 3; ++k) x[k] += bounds.base_length_mm * unit(rng);
  for (int k = 3; k < 6; ++k) x[k] += deg2rad(bounds.base_angle_deg) * unit(rng);
  for (int link = 2; link <= kJointCount; ++link) {
    x[link_param(link, 0)] += deg2rad(bounds.angle_deg) * unit(rng);
    x[link_param(link, 1)] += bounds.length_mm * unit(rng);
    x[link_param(link, 2)] += deg2rad(bounds.angle_deg) * unit(rng);
    x[link_param(link, 3)] += bounds.length_mm * unit(rng);
    x[compliance_param(link)] = bounds.compliance_max * 0.5 * (1.0 + unit(rng));
  }
  return truth;
}

void apply_mass_error(TrueRobot& truth, double fraction, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto perturb = [&](PointMass& mass) {
    mass.mass_kg *= 1.0 + fraction * unit(rng);
    for (int k = 0; k < 3; ++k) mass.cog_mm[k] *= 1.0 + fraction * unit(rng);
  };
  for (PointMass& link : truth.robot.model.link_masses) perturb(link);
  perturb(truth.robot.tool.payload);
  truth.effects.mass_error = fraction;
}

void enable_effects(TrueRobot& truth, const std::vector<std::string>& names, std::mt19937_64& rng,
                    const std::string& flag) {
  for (const std::string& name : names) {
    if (name == "backlash")
      truth.effects.backlash = true;
    else if (name == "j6-periodic")
      truth.effects.j6_periodic = true;
    else if (name == "mass-error")
      apply_mass_error(truth, 0.10, rng);
    else if (name == "thermal")
      truth.effects.thermal = true;
    else
      throw InputError({"", 0, 0, flag},
                       fmt::format("unknown effect '{}'; expected backlash, j6-periodic, "
                                   "mass-error or thermal",
                                   name));
  }
}

namespace {

void emit_mass(YAML::Emitter& out, const PointMass& mass) {
  out << YAML::Flow << YAML::BeginSeq << mass.mass_kg << YAML::Flow << as_list(mass.cog_mm)
      << YAML::EndSeq;
}

PointMass parse_mass(const yaml::Node& node) {
  PointMass mass{node.at(size_t{0}).as_double(), node.at(size_t{1}).as_vector3()};
  if (mass.mass_kg < 0) throw node.error("mass must not be negative");
  return mass;
}

/// `key`: joint → [cos 1, sin 1, cos 2, sin 2] (deg) of the periodic terms at `offset` (the
/// joints' own or their motors'), the joints that have one.
void emit_periodic(YAML::Emitter& out, const char* key, const ParameterVector& x, int offset) {
  const auto row_of = [&](int joint) {
    std::vector<double> row(kPeriodicPerJoint);
    for (int k = 0; k < kPeriodicPerJoint; ++k)
      row[static_cast<size_t>(k)] = rad2deg(x[offset + kPeriodicPerJoint * (joint - 1) + k]);
    return row;
  };
  const std::vector<double> zero(kPeriodicPerJoint, 0.0);
  bool any = false;
  for (int joint = 1; joint <= kJointCount; ++joint) any = any || row_of(joint) != zero;
  if (!any) return;
  out << YAML::Key << key << YAML::Value << YAML::BeginMap;
  for (int joint = 1; joint <= kJointCount; ++joint)
    if (row_of(joint) != zero)
      out << YAML::Key << joint << YAML::Value << YAML::Flow << row_of(joint);
  out << YAML::EndMap;
}

/// Reads what emit_periodic writes; a motor's term needs the joint's gear ratio in the robot
/// file (docs/method/03-error-model.md §9).
void parse_periodic(const yaml::Node& root, const char* key, const RobotModel& model, int offset,
                    ParameterVector& x) {
  if (!root.has(key)) return;
  const yaml::Node periodic = root.at(key);
  for (const std::string& name : periodic.keys()) {
    const int joint = name.size() == 1 ? name[0] - '0' : 0;
    if (joint < 1 || joint > kJointCount)
      throw periodic.at(name).error("expected a joint number 1..6");
    if (offset == kMotorPeriodicOffset && model.gear_ratio[static_cast<size_t>(joint - 1)] == 0.0)
      throw periodic.at(name).error(fmt::format(
          "joint {} has no gear_ratio in the robot file: its motor angle is unknown", joint));
    const std::vector<double> row = periodic.at(name).as_doubles(kPeriodicPerJoint);
    for (int k = 0; k < kPeriodicPerJoint; ++k)
      x[offset + kPeriodicPerJoint * (joint - 1) + k] = deg2rad(row[static_cast<size_t>(k)]);
  }
}

}  // namespace

std::string truth_to_yaml(const TrueRobot& truth, const std::string& robot_name) {
  const ParameterVector& x = truth.robot.params;
  const UnmodelledEffects& fx = truth.effects;
  YAML::Emitter out;
  out.SetDoublePrecision(15);
  out << YAML::Comment(
      "robcal simulation truth: the real robot behind simulated measurements. The calibration "
      "pipeline never reads this file; compare its results with it.");
  out << YAML::BeginMap;
  out << YAML::Key << "robot" << YAML::Value << robot_name;
  out << YAML::Key << "origin" << YAML::Value << truth.origin;
  out << YAML::Key << "base" << YAML::Value << YAML::BeginMap;
  const char* base_keys[6] = {"x_mm", "y_mm", "z_mm", "alpha_deg", "beta_deg", "gamma_deg"};
  for (int k = 0; k < 6; ++k)
    out << YAML::Key << base_keys[k] << YAML::Value << (k < 3 ? x[k] : rad2deg(x[k]));
  out << YAML::EndMap;
  out << YAML::Key << "links" << YAML::Value << YAML::BeginMap;
  for (int link = 2; link <= kJointCount; ++link)
    out << YAML::Key << link << YAML::Value << YAML::Flow
        << std::vector<double>{rad2deg(x[link_param(link, 0)]), x[link_param(link, 1)],
                               rad2deg(x[link_param(link, 2)]), x[link_param(link, 3)],
                               x[compliance_param(link)]};
  out << YAML::EndMap;
  out << YAML::Key << "scales" << YAML::Value << YAML::Flow
      << std::vector<double>(x.data() + kScaleOffset, x.data() + kScaleOffset + kJointCount);
  // Periodic joint and motor errors (opt-in groups, docs/method/03-error-model.md §5, §9).
  emit_periodic(out, "periodic_deg", x, kPeriodicOffset);
  emit_periodic(out, "motor_periodic_deg", x, kMotorPeriodicOffset);
  out << YAML::Key << "masses" << YAML::Value << YAML::BeginMap;
  for (int link = 1; link <= kJointCount; ++link) {
    const PointMass& mass = truth.robot.model.link_masses[static_cast<size_t>(link - 1)];
    if (mass.mass_kg == 0) continue;
    out << YAML::Key << link << YAML::Value;
    emit_mass(out, mass);
  }
  out << YAML::Key << "payload" << YAML::Value;
  emit_mass(out, truth.robot.tool.payload);
  out << YAML::EndMap;
  emit_gravity(out, truth.robot.model);
  if (x[kJoint1Compliance] != 0.0)  // inclined, wall or ceiling mounting (§7)
    out << YAML::Key << "joint1_compliance" << YAML::Value << x[kJoint1Compliance];
  out << YAML::Key << "targets" << YAML::Value << YAML::BeginMap;
  for (const Target& t : truth.robot.tool.targets)
    out << YAML::Key << YAML::DoubleQuoted << t.name << YAML::Value << YAML::Flow
        << as_list(t.position_mm);
  out << YAML::EndMap;
  out << YAML::Key << "effects" << YAML::Value << YAML::BeginMap;
  if (fx.backlash)
    out << YAML::Key << "backlash_deg" << YAML::Value << YAML::Flow
        << std::vector<double>(fx.backlash_deg.begin(), fx.backlash_deg.end());
  if (fx.j6_periodic)
    out << YAML::Key << "j6_periodic" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
        << "amplitude_deg" << YAML::Value << fx.j6_amplitude_deg << YAML::Key << "harmonic"
        << YAML::Value << fx.j6_harmonic << YAML::Key << "phase_deg" << YAML::Value
        << fx.j6_phase_deg << YAML::EndMap;
  if (fx.mass_error > 0) out << YAML::Key << "mass_error" << YAML::Value << fx.mass_error;
  if (fx.thermal)
    out << YAML::Key << "thermal" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
        << "expansion_per_kelvin" << YAML::Value << fx.expansion_per_kelvin << YAML::Key
        << "temperature_rise_k" << YAML::Value << fx.temperature_rise_k << YAML::Key
        << "time_constant_s" << YAML::Value << fx.time_constant_s << YAML::EndMap;
  out << YAML::EndMap;
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

TrueRobot parse_truth(const yaml::Node& root, const std::string& robot, const Tool& tool) {
  // A typo ('efects:', 'scale:') would silently simulate another robot than the one meant.
  yaml::expect_keys(
      root, {"robot", "origin", "base", "links", "scales", "masses", "payload", "gravity_m_s2",
             "targets", "effects", "periodic_deg", "motor_periodic_deg", "gravity_base_m_s2",
             "mounting_deg", "joint1_compliance"});
  const std::string robot_name = root.has("robot") ? root.at("robot").as_string() : robot;
  RobotModel model = load_robot(robot_name);
  TrueRobot truth =
      make_truth(model, tool, root.has("origin") ? root.at("origin").as_string() : "");
  ParameterVector& x = truth.robot.params;
  const yaml::Node base = root.at("base");
  yaml::expect_keys(base, {"x_mm", "y_mm", "z_mm", "alpha_deg", "beta_deg", "gamma_deg"});
  const char* base_keys[6] = {"x_mm", "y_mm", "z_mm", "alpha_deg", "beta_deg", "gamma_deg"};
  for (int k = 0; k < 6; ++k) {
    const double value = base.at(base_keys[k]).as_double();
    x[k] = k < 3 ? value : deg2rad(value);
  }
  const yaml::Node links = root.at("links");
  yaml::expect_keys(links, {"2", "3", "4", "5", "6"});
  for (int link = 2; link <= kJointCount; ++link) {
    const std::vector<double> row = links.at(std::to_string(link)).as_doubles(5);
    x[link_param(link, 0)] = deg2rad(row[0]);
    x[link_param(link, 1)] = row[1];
    x[link_param(link, 2)] = deg2rad(row[2]);
    x[link_param(link, 3)] = row[3];
    x[compliance_param(link)] = row[4];
  }
  if (root.has("scales")) {
    const std::vector<double> scales = root.at("scales").as_doubles(kJointCount);
    for (int i = 0; i < kJointCount; ++i) x[kScaleOffset + i] = scales[static_cast<size_t>(i)];
  }
  parse_periodic(root, "periodic_deg", model, kPeriodicOffset, x);
  parse_periodic(root, "motor_periodic_deg", model, kMotorPeriodicOffset, x);
  // The masses listed are all the arm has: links not listed carry none.
  RobotModel& true_model = truth.robot.model;
  const yaml::Node masses = root.at("masses");
  for (PointMass& mass : true_model.link_masses) mass = PointMass{};
  for (const std::string& key : masses.keys()) {
    if (key == "payload") continue;
    const int link = key.size() == 1 ? key[0] - '0' : 0;
    if (link < 1 || link > kJointCount)
      throw masses.at(key).error("expected a link number 1..6 or 'payload'");
    true_model.link_masses[static_cast<size_t>(link - 1)] = parse_mass(masses.at(key));
  }
  Tool& true_tool = truth.robot.tool;
  if (masses.has("payload"))
    true_tool.payload = parse_mass(masses.at("payload"));
  else if (root.has("payload"))
    true_tool.payload = parse_tool(root).payload;
  parse_gravity(root, true_model);
  if (root.has("joint1_compliance"))
    x[kJoint1Compliance] = root.at("joint1_compliance").as_double();
  if (root.has("targets")) {
    true_tool.targets.clear();
    const yaml::Node targets = root.at("targets");
    for (const std::string& name : targets.keys())
      true_tool.targets.push_back({name, targets.at(name).as_vector3(), true});
  }

  UnmodelledEffects& fx = truth.effects;
  if (root.has("effects")) {
    const yaml::Node effects = root.at("effects");
    yaml::expect_keys(effects, {"backlash_deg", "j6_periodic", "mass_error", "thermal"});
    if (effects.has("backlash_deg")) {
      fx.backlash = true;
      const std::vector<double> b = effects.at("backlash_deg").as_doubles(kJointCount);
      std::copy(b.begin(), b.end(), fx.backlash_deg.begin());
    }
    if (effects.has("j6_periodic")) {
      const yaml::Node p = effects.at("j6_periodic");
      yaml::expect_keys(p, {"amplitude_deg", "harmonic", "phase_deg"});
      fx.j6_periodic = true;
      fx.j6_amplitude_deg = p.at("amplitude_deg").as_double();
      fx.j6_harmonic = p.at("harmonic").as_double();
      fx.j6_phase_deg = p.at("phase_deg").as_double();
    }
    if (effects.has("mass_error")) fx.mass_error = effects.at("mass_error").as_double();
    if (effects.has("thermal")) {
      const yaml::Node t = effects.at("thermal");
      yaml::expect_keys(t, {"expansion_per_kelvin", "temperature_rise_k", "time_constant_s"});
      fx.thermal = true;
      fx.expansion_per_kelvin = t.at("expansion_per_kelvin").as_double();
      fx.temperature_rise_k = t.at("temperature_rise_k").as_double();
      fx.time_constant_s = t.at("time_constant_s").as_double();
      if (fx.time_constant_s <= 0) throw t.at("time_constant_s").error("must be positive");
    }
  }
  return truth;
}

TrueRobot load_truth(const std::string& path, const std::string& robot, const Tool& tool) {
  TrueRobot truth = parse_truth(yaml::load_file(path), robot, tool);
  if (truth.origin.empty()) truth.origin = path;
  return truth;
}

}  // namespace robcal
