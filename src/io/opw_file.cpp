#include "robcal/io/opw_file.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "robcal/core/units.hpp"

namespace robcal {
namespace {

/// A joint offset: a number (radians) or `deg(x)` / `rad(x)`, the rosparam forms.
double parse_angle(const yaml::Node& node) {
  if (node.node.IsScalar()) {
    const std::string text = node.node.Scalar();
    for (const auto& [prefix, factor] :
         {std::pair<const char*, double>{"deg(", std::numbers::pi / 180}, {"rad(", 1.0}}) {
      const std::string p = prefix;
      if (text.rfind(p, 0) != 0) continue;
      if (text.back() != ')') break;
      const std::string inner = text.substr(p.size(), text.size() - p.size() - 1);
      char* end = nullptr;
      const double value = std::strtod(inner.c_str(), &end);
      if (end == inner.c_str() || *end != '\0' || !std::isfinite(value)) break;
      return value * factor;
    }
  }
  if (node.node.IsScalar() && node.node.Scalar().find('(') != std::string::npos)
    throw node.error(
        fmt::format("expected a number (rad), deg(x) or rad(x), got '{}'", node.node.Scalar()));
  return node.as_double();
}

/// The map holding the OPW keys: the root, or the one planning group under it that has them.
yaml::Node opw_section(const yaml::Node& root, std::string& prefix) {
  for (const char* p : {"opw_kinematics_", "kinematics_solver_"}) {
    prefix = p;
    if (root.has(prefix + "geometric_parameters")) return root;
    if (!root.node.IsMap()) break;
    for (const std::string& key : root.keys()) {
      yaml::Node child = root.at(key);
      if (child.node.IsMap() && child.has(prefix + "geometric_parameters")) return child;
    }
  }
  throw root.error(
      "missing key 'opw_kinematics_geometric_parameters' (not a ROS-Industrial OPW file)");
}

}  // namespace

OpwParameters parse_opw_parameters(const yaml::Node& root) {
  std::string prefix;
  const yaml::Node section = opw_section(root, prefix);
  const yaml::Node g = section.at(prefix + "geometric_parameters");
  OpwParameters p;
  auto metres = [&](const char* key) { return 1000.0 * g.at(key).as_double(); };
  p.a1 = metres("a1");
  p.a2 = metres("a2");
  p.b = metres("b");
  p.c1 = metres("c1");
  p.c2 = metres("c2");
  p.c3 = metres("c3");
  p.c4 = metres("c4");
  if (section.has(prefix + "joint_offsets")) {
    const yaml::Node offsets = section.at(prefix + "joint_offsets");
    if (!offsets.node.IsSequence() || offsets.size() != kJointCount)
      throw offsets.error("expected a list of 6 joint offsets");
    for (int i = 0; i < kJointCount; ++i) p.offsets[i] = parse_angle(offsets.at(i));
  }
  if (section.has(prefix + "joint_sign_corrections")) {
    const yaml::Node signs = section.at(prefix + "joint_sign_corrections");
    if (!signs.node.IsSequence() || signs.size() != kJointCount)
      throw signs.error("expected a list of 6 sign corrections (1 or -1)");
    for (int i = 0; i < kJointCount; ++i) {
      p.signs[i] = signs.at(i).as_int();
      if (p.signs[i] != 1 && p.signs[i] != -1)
        throw signs.at(i).error(fmt::format("expected 1 or -1, got {}", p.signs[i]));
    }
  }
  if (p.b != 0.0) throw g.at("b").error("a lateral offset b ≠ 0 is not supported (expected 0)");
  if (p.c2 == 0.0) throw g.at("c2").error("the upper arm c2 must not be 0");
  return p;
}

RobotModel robot_from_opw(const OpwParameters& p, const OpwImportOptions& options) {
  if (p.b != 0.0) throw InputError("OPW parameters: a lateral offset b ≠ 0 is not supported");
  if (p.c2 == 0.0) throw InputError("OPW parameters: the upper arm c2 must not be 0");
  for (int s : p.signs)
    if (s != 1 && s != -1) throw InputError("OPW parameters: sign corrections must be 1 or -1");
  RobotModel m;
  m.name = options.name;
  m.manufacturer = options.manufacturer;
  m.source = "ROS-Industrial OPW parameters, converted to MDH";
  const double r90 = deg2rad(90);
  m.mdh[0] = {0, 0, 0, p.c1};
  m.mdh[1] = {-r90, p.a1, -r90, 0};
  m.mdh[2] = {0, p.c2, 0, 0};
  m.mdh[3] = {-r90, -p.a2, 0, p.c3};
  m.mdh[4] = {r90, 0, 0, 0};
  m.mdh[5] = {-r90, 0, deg2rad(180), p.c4};
  for (int i = 0; i < kJointCount; ++i) {
    m.joint_map.matrix(i, i) = p.signs[i];
    m.joint_map.offset[i] = -p.offsets[i];
    m.limits[i] = {-std::numbers::pi, std::numbers::pi};
  }
  m.joint_map.offset[2] -= r90;
  // ROS joint 3 = J3 + J2: model q3 = s3·(J3 + J2) + offset.
  if (options.fanuc_j2_j3_coupling) m.joint_map.matrix(2, 1) = p.signs[2];
  return m;
}

RobotModel load_opw_robot(const std::string& path, const OpwImportOptions& options) {
  return robot_from_opw(parse_opw_parameters(yaml::load_file(path)), options);
}

}  // namespace robcal
