#include "robcal/identify/unknowns.hpp"

#include <fmt/format.h>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal {

CalibrationLevel parse_calibration_level(const std::string& text) {
  if (text == "base") return CalibrationLevel::Base;
  if (text == "joints") return CalibrationLevel::Joints;
  if (text == "kinematic") return CalibrationLevel::Kinematic;
  if (text == "full") return CalibrationLevel::Full;
  throw InputError(
      {"", 0, 0, "--level"},
      fmt::format("unknown level '{}': expected base, joints, kinematic or full", text));
}

CalibrationLevel parse_reidentification_level(const std::string& text) {
  if (text == "tool") return CalibrationLevel::Tool;
  if (text == "base" || text == "joints" || text == "kinematic" || text == "full")
    return parse_calibration_level(text);
  throw InputError(
      {"", 0, 0, "--level"},
      fmt::format("unknown level '{}' for a calibrated model (--model): expected tool, base, "
                  "joints, kinematic or full",
                  text));
}

const char* level_name(CalibrationLevel level) {
  switch (level) {
    case CalibrationLevel::Base:
      return "base";
    case CalibrationLevel::Joints:
      return "joints";
    case CalibrationLevel::Kinematic:
      return "kinematic";
    case CalibrationLevel::Full:
      return "full";
    case CalibrationLevel::Tool:
      return "tool";
    case CalibrationLevel::Patterns:
      return "patterns";
  }
  return "";
}

std::vector<int> level_parameters(CalibrationLevel level) {
  std::vector<int> out;
  if (level == CalibrationLevel::Tool || level == CalibrationLevel::Patterns) return out;
  out.reserve(kParameterCount);
  for (int i = 0; i < kBaseParamCount; ++i) out.push_back(i);
  for (int link = 2; link <= kJointCount; ++link) {
    for (int k = 0; k < 4; ++k) {
      const bool offset = k == 2;
      if (level == CalibrationLevel::Kinematic || level == CalibrationLevel::Full ||
          (level == CalibrationLevel::Joints && offset))
        out.push_back(link_param(link, k));
    }
  }
  if (level == CalibrationLevel::Full)
    for (int joint = 2; joint <= kJointCount; ++joint) out.push_back(compliance_param(joint));
  return out;
}

namespace {
bool is_rotation(const UnknownLayout& layout, int index) {
  return layout.tcp_rotation >= 0 && index >= layout.tcp_rotation &&
         index < layout.tcp_rotation + 3;
}
}  // namespace

double UnknownLayout::to_external(int index) const {
  if (is_rotation(*this, index)) return rad2deg(1.0);
  return is_model(index) ? parameter_table()[index].to_external() : 1.0;
}

std::string UnknownLayout::unit(int index) const {
  if (is_rotation(*this, index)) return "deg";
  return is_model(index) ? parameter_table()[index].unit : "mm";
}

double UnknownLayout::plausible_error(int index) const {
  if (is_rotation(*this, index)) return 1e-3;
  if (!is_model(index)) return 1.0;
  switch (parameter_table()[static_cast<size_t>(index)].kind) {
    case ParamKind::Length:
      return 1.0;
    case ParamKind::Angle:
      // The direction of gravity acts through the compliances alone (a 1° tilt moves the
      // gravity deflections by 2 %): known to a degree, not to a milliradian (§11).
      return index == kGravityTiltA || index == kGravityTiltB ? deg2rad(1.0) : 1e-3;
    case ParamKind::Compliance:
      return 1e-7;
    case ParamKind::Scale:
      return 1e-4;
    case ParamKind::Expansion:
      return 1e-5;  // 1/K: metals expand 10–25 ppm/K
  }
  return 1.0;
}

int UnknownLayout::index(const std::string& name) const {
  for (int i = 0; i < size(); ++i)
    if (names[i] == name) return i;
  return -1;
}

UnknownLayout make_unknown_layout(const Tool& tool, MeasurementKind kind) {
  UnknownLayout layout;
  for (const ParameterInfo& info : parameter_table()) layout.names.push_back(info.name);
  for (const Target& target : tool.targets) {
    if (target.known) {
      layout.target_slot.push_back(-1);
      continue;
    }
    layout.target_slot.push_back(layout.size());
    for (const char* axis : {"x", "y", "z"})
      layout.names.push_back(fmt::format("target.{}.{}", target.name, axis));
  }
  if (kind == MeasurementKind::Poses && !tool.tcp_position_known) {
    layout.tcp_position = layout.size();
    for (const char* axis : {"x", "y", "z"}) layout.names.push_back(fmt::format("tcp.{}", axis));
  }
  if (kind == MeasurementKind::Poses && !tool.tcp_orientation_known) {
    layout.tcp_rotation = layout.size();
    for (const char* axis : {"rx", "ry", "rz"}) layout.names.push_back(fmt::format("tcp.{}", axis));
  }
  if (kind == MeasurementKind::Distances) {
    layout.centre = layout.size();
    for (const char* axis : {"x", "y", "z"})
      layout.names.push_back(fmt::format("ballbar.centre.{}", axis));
    layout.length_offset = layout.size();
    layout.names.push_back("ballbar.length_offset");
  }
  return layout;
}

std::vector<bool> select_unknowns(const UnknownLayout& layout, CalibrationLevel level,
                                  const std::vector<std::string>& identify,
                                  const std::vector<std::string>& fix) {
  std::vector<bool> free(layout.size(), false);
  for (int i : level_parameters(level)) free[i] = true;
  for (int i = kParameterCount; i < layout.size(); ++i) free[i] = i != layout.length_offset;
  const auto apply = [&](const std::vector<std::string>& patterns, bool value, const char* flag) {
    for (const std::string& pattern : patterns) {
      const std::vector<int> group = opt_in_group_parameters(pattern);
      for (int i : group) free[i] = value;
      bool matched = !group.empty();
      for (int i = 0; i < layout.size(); ++i) {
        if (!glob_match(pattern, layout.names[i])) continue;
        matched = true;
        if (!value && !layout.is_model(i) && i != layout.length_offset &&
            (layout.centre < 0 || i < layout.centre))
          throw InputError({"", 0, 0, flag},
                           fmt::format("'{}' would fix {}, a target given without coordinates: "
                                       "give its coordinates in the tool file instead",
                                       pattern, layout.names[i]));
        free[i] = value;
      }
      if (!matched)
        throw InputError(
            {"", 0, 0, flag},
            fmt::format(
                "pattern '{}' matches no parameter (names look like "
                "base.x, link3.a, joint2.compliance, joint1.scale{}; opt-in groups: periodic, "
                "backlash, mounting, thermal, warmup, motor_periodic, gravity or groups for all)",
                pattern,
                layout.size() > kParameterCount ? ", " + layout.names[kParameterCount] : ""));
    }
  };
  apply(identify, true, "--identify");
  apply(fix, false, "--fix");
  return free;
}

void refuse_gearless_motor_terms(const RobotModel& model, const std::vector<std::string>& identify,
                                 std::vector<bool>& requested) {
  for (int joint = 1; joint <= kJointCount; ++joint) {
    if (model.gear_ratio[static_cast<size_t>(joint - 1)] != 0.0) continue;
    for (int k = 0; k < kPeriodicPerJoint; ++k) {
      const int i = motor_periodic_param(joint, 1, false) + k;
      if (!requested[static_cast<size_t>(i)]) continue;
      for (const std::string& pattern : identify) {
        if (selects_by_family(pattern) || pattern.find("motor") == std::string::npos) continue;
        const std::vector<int> group = opt_in_group_parameters(pattern);
        if (glob_match(pattern, parameter_table()[static_cast<size_t>(i)].name) ||
            std::find(group.begin(), group.end(), i) != group.end())
          throw InputError(
              {"", 0, 0, "--identify"},
              fmt::format("'{}' asks for the motor-angle periodic error of joint {}, whose gear "
                          "ratio the robot file does not give: add 'gear_ratio' (motor turns per "
                          "joint turn, ~ for the joints without one) or leave joint {} out",
                          pattern, joint, joint));
      }
      requested[static_cast<size_t>(i)] = false;
    }
  }
}

void check_identify_patterns(CalibrationLevel level, const std::vector<std::string>& identify) {
  select_unknowns(make_unknown_layout(Tool{}, MeasurementKind::Poses), level, identify, {});
}

std::vector<int> identified_model_parameters(const RobotModel& model, const Tool& tool,
                                             MeasurementKind kind, CalibrationLevel level,
                                             const std::vector<std::string>& identify) {
  std::vector<bool> requested =
      select_unknowns(make_unknown_layout(tool, kind), level, identify, {});
  requested.resize(kParameterCount);
  refuse_gearless_motor_terms(model, identify, requested);
  std::vector<int> out;
  for (int i = 0; i < kParameterCount; ++i)
    if (requested[static_cast<size_t>(i)]) out.push_back(i);
  return out;
}

}  // namespace robcal
