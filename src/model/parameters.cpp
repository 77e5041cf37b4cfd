#include "robcal/model/parameters.hpp"

#include <fmt/format.h>

#include "robcal/core/units.hpp"

namespace robcal {

double ParameterInfo::to_external() const {
  switch (kind) {
    case ParamKind::Angle:
      return kRadToDeg;
    case ParamKind::Expansion:
      return 1e6;  // 1/K → ppm/K: steel 11.7, aluminium 23
    default:
      return 1.0;
  }
}

const std::array<ParameterInfo, kParameterCount>& parameter_table() {
  static const std::array<ParameterInfo, kParameterCount> kTable = [] {
    std::array<ParameterInfo, kParameterCount> t;
    const char* base_names[] = {"x", "y", "z", "alpha", "beta", "gamma"};
    for (int k = 0; k < 6; ++k) {
      const bool angle = k >= 3;
      t[k] = {fmt::format("base.{}", base_names[k]), angle ? ParamKind::Angle : ParamKind::Length,
              angle ? "deg" : "mm"};
    }
    const char* link_names[] = {"alpha", "a", "theta", "d"};
    for (int link = 2; link <= 6; ++link) {
      for (int k = 0; k < 4; ++k) {
        const bool angle = (k == 0 || k == 2);
        t[link_param(link, k)] = {fmt::format("link{}.{}", link, link_names[k]),
                                  angle ? ParamKind::Angle : ParamKind::Length,
                                  angle ? "deg" : "mm"};
      }
      t[compliance_param(link)] = {fmt::format("joint{}.compliance", link), ParamKind::Compliance,
                                   "rad/N·mm"};
    }
    for (int joint = 1; joint <= 6; ++joint)
      t[scale_param(joint)] = {fmt::format("joint{}.scale", joint), ParamKind::Scale, "1"};
    for (int joint = 1; joint <= kJointCount; ++joint)
      for (int h = 1; h <= kPeriodicHarmonics; ++h)
        for (const bool sine : {false, true})
          t[periodic_param(joint, h, sine)] = {
              fmt::format("joint{}.periodic{}.{}", joint, h, sine ? "sin" : "cos"),
              ParamKind::Angle, "deg"};
    for (int joint = 1; joint <= kJointCount; ++joint)
      t[backlash_param(joint)] = {fmt::format("joint{}.backlash", joint), ParamKind::Angle, "deg"};
    t[kJoint1Compliance] = {"joint1.compliance", ParamKind::Compliance, "rad/N·mm"};
    for (int link = 2; link <= kJointCount; ++link)
      t[expansion_param(link)] = {fmt::format("link{}.expansion", link), ParamKind::Expansion,
                                  "ppm/K"};
    for (int joint = 1; joint <= kJointCount; ++joint)
      for (int h = 1; h <= kPeriodicHarmonics; ++h)
        for (const bool sine : {false, true})
          t[motor_periodic_param(joint, h, sine)] = {
              fmt::format("joint{}.motor_periodic{}.{}", joint, h, sine ? "sin" : "cos"),
              ParamKind::Angle, "deg"};
    for (int link = 2; link <= kJointCount; ++link)
      t[warmup_param(link)] = {fmt::format("link{}.warmup_growth", link), ParamKind::Length, "mm"};
    t[kGravityTiltA] = {"gravity.tilt_a", ParamKind::Angle, "deg"};
    t[kGravityTiltB] = {"gravity.tilt_b", ParamKind::Angle, "deg"};
    return t;
  }();
  return kTable;
}

const std::vector<ParameterGroup>& opt_in_groups() {
  static const std::vector<ParameterGroup> kGroups = [] {
    std::vector<ParameterGroup> g;
    for (int joint = 1; joint <= kJointCount; ++joint) {
      ParameterGroup group{fmt::format("joint{}.periodic", joint), {}};
      for (int k = 0; k < kPeriodicPerJoint; ++k)
        group.params.push_back(periodic_param(joint, 1, false) + k);
      g.push_back(group);
    }
    for (int joint = 1; joint <= kJointCount; ++joint)
      g.push_back({fmt::format("joint{}.backlash", joint), {backlash_param(joint)}});
    g.push_back({"joint1.compliance", {kJoint1Compliance}});
    ParameterGroup thermal{"thermal", {}};
    for (int link = 2; link <= kJointCount; ++link) thermal.params.push_back(expansion_param(link));
    g.push_back(thermal);
    for (int joint = 1; joint <= kJointCount; ++joint) {
      ParameterGroup group{fmt::format("joint{}.motor_periodic", joint), {}};
      for (int k = 0; k < kPeriodicPerJoint; ++k)
        group.params.push_back(motor_periodic_param(joint, 1, false) + k);
      g.push_back(group);
    }
    ParameterGroup warmup{"warmup", {}};
    for (int link = 2; link <= kJointCount; ++link) warmup.params.push_back(warmup_param(link));
    g.push_back(warmup);
    g.push_back({"gravity", {kGravityTiltA, kGravityTiltB}});
    return g;
  }();
  return kGroups;
}

std::vector<int> opt_in_group_parameters(std::string_view name) {
  std::vector<int> out;
  const bool family =  // one group per joint
      name == "periodic" || name == "backlash" || name == "motor_periodic";
  for (const ParameterGroup& group : opt_in_groups()) {
    if (name == "groups" || name == group.name ||
        (family && group.name.ends_with(fmt::format(".{}", name))) ||
        (name == "mounting" && group.name == "joint1.compliance"))
      out.insert(out.end(), group.params.begin(), group.params.end());
  }
  return out;
}

bool selects_by_family(std::string_view name) {
  return name == "groups" || name == "motor_periodic";
}

bool is_opt_in(int index) {
  return index >= kPeriodicOffset && index < kParameterCount;
}

int parameter_index(std::string_view name) {
  const auto& table = parameter_table();
  for (int i = 0; i < kParameterCount; ++i)
    if (table[i].name == name) return i;
  return -1;
}

bool glob_match(std::string_view pattern, std::string_view text) {
  // Iterative wildcard match with single backtrack point (linear for one '*').
  size_t p = 0, t = 0, star = std::string_view::npos, mark = 0;
  while (t < text.size()) {
    if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == text[t])) {
      ++p;
      ++t;
    } else if (p < pattern.size() && pattern[p] == '*') {
      star = p++;
      mark = t;
    } else if (star != std::string_view::npos) {
      p = star + 1;
      t = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

std::vector<int> match_parameters(std::string_view pattern) {
  std::vector<int> out;
  const auto& table = parameter_table();
  for (int i = 0; i < kParameterCount; ++i)
    if (glob_match(pattern, table[i].name)) out.push_back(i);
  return out;
}

}  // namespace robcal
