#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/identify/calibrated_robot_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/yaml_checks.hpp"
#include "robcal/io/yaml_support.hpp"

namespace robcal {
const char* status_name(ParameterStatus status) {
  switch (status) {
    case ParameterStatus::Identified:
      return "identified";
    case ParameterStatus::Fixed:
      return "fixed";
    case ParameterStatus::Dropped:
      return "dropped";
  }
  return "";
}

namespace {

ParameterStatus parse_status(const yaml::Node& node) {
  const std::string text = node.as_string();
  if (text == "identified") return ParameterStatus::Identified;
  if (text == "fixed") return ParameterStatus::Fixed;
  if (text == "dropped") return ParameterStatus::Dropped;
  throw node.error(fmt::format("unknown status '{}': expected identified, fixed or dropped", text));
}

/// The calibrated model a file's YAML root describes.
CalibratedRobot calibrated_robot_from(const yaml::Node& root) {
  const auto& table = parameter_table();
  if (!root.has("parameters") || !root.has("robot"))
    throw root.error(
        "not a calibrated model: expected the keys 'robot' and 'parameters' "
        "(a file written by `robcal calibrate`)");
  // A misspelt key ('covarience:') would silently drop what it holds.
  yaml::expect_keys(root, {"format", "level", "base_fitted", "robot", "tool", "parameters",
                           "covariance", "groups", "statistics", "reidentified"});
  CalibratedRobot robot;
  robot.model = parse_robot(root.at("robot"));
  robot.tool = root.has("tool") ? parse_tool(root.at("tool")) : Tool{};
  if (root.has("format") && root.at("format").as_string() != "robcal-calibrated-model")
    throw root.at("format").error(fmt::format(
        "unknown format '{}': expected robcal-calibrated-model", root.at("format").as_string()));
  robot.level = root.has("level") ? root.at("level").as_string() : "nominal";
  // What the writers put there (calibrate's levels, a nominal model, a simulator's truth, a
  // model imported from UR's calibration.conf).
  constexpr std::array<std::string_view, 9> kLevels{"nominal", "truth",     "base",
                                                    "joints",  "kinematic", "full",
                                                    "tool",    "patterns",  "ur-calibration"};
  if (std::find(kLevels.begin(), kLevels.end(), robot.level) == kLevels.end())
    throw root.at("level").error(fmt::format(
        "unknown level '{}': expected nominal, base, joints, kinematic, full, tool or patterns "
        "(calibrate's levels), truth (a simulator's) or ur-calibration (imported)",
        robot.level));
  robot.base_fitted = root.has("base_fitted") && root.at("base_fitted").node.as<bool>(false);
  robot.params = robot.model.nominal();
  robot.status.fill(ParameterStatus::Fixed);
  std::array<bool, kParameterCount> seen{};
  const yaml::Node parameters = root.at("parameters");
  if (!parameters.node.IsSequence()) throw parameters.error("expected a list of parameters");
  for (size_t k = 0; k < parameters.size(); ++k) {
    const yaml::Node entry = parameters.at(k);
    yaml::expect_keys(entry, {"name", "unit", "nominal", "value", "std", "status", "reason"});
    const yaml::Node name = entry.at("name");
    const int i = parameter_index(name.as_string());
    if (i < 0) throw name.error(fmt::format("unknown parameter '{}'", name.as_string()));
    const auto s = static_cast<size_t>(i);
    if (seen[s]) throw name.error(fmt::format("parameter '{}' given twice", table[i].name));
    seen[s] = true;
    if (entry.has("unit") && entry.at("unit").as_string() != table[i].unit)
      throw entry.at("unit").error(fmt::format("{} is in {}, not {}", table[i].name, table[i].unit,
                                               entry.at("unit").as_string()));
    robot.params[i] = entry.at("value").as_double() / table[i].to_external();
    if (entry.has("status")) robot.status[s] = parse_status(entry.at("status"));
    if (entry.has("reason")) robot.reason[s] = entry.at("reason").as_string();
  }
  if (root.has("statistics")) robot.statistics = YAML::Dump(root.at("statistics").node);
  if (root.has("reidentified")) {
    const yaml::Node records = root.at("reidentified");
    if (!records.node.IsSequence()) throw records.error("expected a list of re-identifications");
    for (size_t k = 0; k < records.size(); ++k)
      robot.reidentified.push_back(YAML::Dump(records.at(k).node));
  }
  if (root.has("covariance")) {
    const yaml::Node cov = root.at("covariance");
    yaml::expect_keys(cov, {"units", "parameters", "matrix"});
    const yaml::Node names = cov.at("parameters");
    std::vector<int> index;
    for (size_t k = 0; k < names.size(); ++k) {
      const int i = parameter_index(names.at(k).as_string());
      if (i < 0)
        throw names.at(k).error(fmt::format("unknown parameter '{}'", names.at(k).as_string()));
      index.push_back(i);
    }
    const yaml::Node matrix = cov.at("matrix");
    if (!matrix.node.IsSequence() || matrix.size() != index.size())
      throw matrix.error(fmt::format("expected {} rows, one per parameter", index.size()));
    robot.covariance = Eigen::MatrixXd::Zero(kParameterCount, kParameterCount);
    for (size_t a = 0; a < index.size(); ++a) {
      const auto row = matrix.at(a).as_doubles(static_cast<int>(index.size()));
      for (size_t b = 0; b < index.size(); ++b)
        robot.covariance(index[a], index[b]) =
            row[b] / (table[index[a]].to_external() * table[index[b]].to_external());
    }
  }
  return robot;
}

}  // namespace

std::string calibrated_robot_to_yaml(const CalibratedRobot& robot) {
  return calibrated_robot_to_yaml(robot, YamlWriter{});
}

std::string calibrated_robot_to_yaml(const CalibratedRobot& robot, const YamlWriter& statistics,
                                     const YamlWriter& new_record) {
  const auto& table = parameter_table();
  const ParameterVector nominal = robot.model.nominal();
  const bool has_covariance = robot.covariance.rows() == kParameterCount;
  YAML::Emitter out;
  out.SetDoublePrecision(kExactDigits);
  out << YAML::Comment(
      "robcal calibrated model: the robot, its tool and every parameter (mm, deg, rad/N·mm)");
  out << YAML::BeginMap;
  out << YAML::Key << "format" << YAML::Value << "robcal-calibrated-model";
  out << YAML::Key << "level" << YAML::Value << robot.level;
  out << YAML::Key << "base_fitted" << YAML::Value << robot.base_fitted;
  out << YAML::Key << "robot" << YAML::Value << YAML::BeginMap;
  emit_robot_fields(out, robot.model);
  out << YAML::EndMap;
  out << YAML::Key << "tool" << YAML::Value;
  emit_tool(out, robot.tool);
  out.SetDoublePrecision(kExactDigits);
  // Opt-in groups (docs/method/03-error-model.md §5) appear only when enabled: a file without
  // them reads back as the same robot (absent parameters are nominal and fixed).
  const std::vector<GroupSignificance> groups = group_significance(robot);
  std::array<bool, kParameterCount> shown;
  shown.fill(true);
  for (size_t g = 0; g < groups.size(); ++g)
    for (int i : opt_in_groups()[g].params) shown[static_cast<size_t>(i)] = groups[g].enabled;
  out << YAML::Key << "parameters" << YAML::Value << YAML::BeginSeq;
  std::vector<int> identified;
  for (int i = 0; i < kParameterCount; ++i) {
    if (!shown[static_cast<size_t>(i)]) continue;
    const double f = table[i].to_external();
    const auto s = static_cast<size_t>(i);
    const double variance = has_covariance ? robot.covariance(i, i) : 0.0;
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value << table[i].name
        << YAML::Key << "unit" << YAML::Value << table[i].unit << YAML::Key << "nominal"
        << YAML::Value << nominal[i] * f << YAML::Key << "value" << YAML::Value
        << robot.params[i] * f;
    // An identified parameter of a fit without a covariance has no known σ: no `std` rather than
    // a 0 that reads as exact. Held parameters have none to report.
    if (has_covariance || robot.status[s] != ParameterStatus::Identified)
      out << YAML::Key << "std" << YAML::Value << std::sqrt(std::max(0.0, variance)) * f;
    out << YAML::Key << "status" << YAML::Value << status_name(robot.status[s]);
    if (!robot.reason[s].empty()) out << YAML::Key << "reason" << YAML::Value << robot.reason[s];
    out << YAML::EndMap;
    if (robot.status[s] == ParameterStatus::Identified) identified.push_back(i);
  }
  out << YAML::EndSeq;
  if (has_covariance && !identified.empty()) {
    out << YAML::Key << "covariance" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "units" << YAML::Value << "products of the parameters' units";
    out << YAML::Key << "parameters" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (int i : identified) out << table[i].name;
    out << YAML::EndSeq << YAML::Key << "matrix" << YAML::Value << YAML::BeginSeq;
    for (int i : identified) {
      std::vector<double> row;
      row.reserve(identified.size());
      for (int j : identified)
        row.push_back(robot.covariance(i, j) * table[i].to_external() * table[j].to_external());
      out << YAML::Flow << row;
    }
    out << YAML::EndSeq << YAML::EndMap;
  }
  bool any_group = false;
  for (const GroupSignificance& g : groups) any_group = any_group || g.enabled;
  if (any_group) {
    out << YAML::Key << "groups" << YAML::Value << YAML::BeginSeq;
    for (const GroupSignificance& g : groups) {
      if (!g.enabled) continue;
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value << g.group
          << YAML::Key << "identified" << YAML::Value << g.identified << YAML::Key << "wald"
          << YAML::Value << g.wald << YAML::Key << "p_value" << YAML::Value << g.p_value
          << YAML::Key << "significant" << YAML::Value << g.significant << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  // The robot's statistics and records as read from its file are kept as they were written.
  if (statistics) {
    out << YAML::Key << "statistics" << YAML::Value;
    statistics(out);
  } else if (!robot.statistics.empty()) {
    out << YAML::Key << "statistics" << YAML::Value << YAML::Load(robot.statistics);
  }
  if (!robot.reidentified.empty() || new_record) {
    out << YAML::Key << "reidentified" << YAML::Value << YAML::BeginSeq;
    for (const std::string& record : robot.reidentified) out << YAML::Load(record);
    if (new_record) new_record(out);
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

void check_tool_against_model(const CalibratedRobot& robot, const Tool& tool,
                              const std::string& tool_path) {
  const std::string advice =
      "the model was calibrated with another tool: validate with the tool it was calibrated "
      "with (the model's 'tool:' section), or calibrate this tool first (calibrate --model)";
  for (const Target& t : tool.targets) {
    const int i = robot.tool.target_index(t.name);
    if (i < 0)
      throw InputError(
          {tool_path, 0, 0, "targets." + t.name},
          fmt::format("target '{}' is not a target of the model's tool; {}", t.name, advice));
    const Eigen::Vector3d& m = robot.tool.targets[static_cast<size_t>(i)].position_mm;
    // Calibration refines nominal coordinates by tenths of mm; 5 mm apart is another tool.
    if (t.known && (m - t.position_mm).norm() > 5.0)
      throw InputError({tool_path, 0, 0, "targets." + t.name},
                       fmt::format("target '{}' is at ({:g}, {:g}, {:g}) mm here, at ({:.4f}, "
                                   "{:.4f}, {:.4f}) mm in the model; {}",
                                   t.name, t.position_mm.x(), t.position_mm.y(), t.position_mm.z(),
                                   m.x(), m.y(), m.z(), advice));
  }
  if (std::abs(tool.payload.mass_kg - robot.tool.payload.mass_kg) > 1e-9 ||
      (tool.payload.cog_mm - robot.tool.payload.cog_mm).norm() > 1e-6)
    throw InputError({tool_path, 0, 0, "payload"},
                     fmt::format("payload {:g} kg differs from the model's {:g} kg; {}",
                                 tool.payload.mass_kg, robot.tool.payload.mass_kg, advice));
}

CalibratedRobot load_calibrated_robot(const std::string& path) {
  return calibrated_robot_from(yaml::load_file(path));
}

CalibratedRobot parse_calibrated_robot(const std::string& text, const std::string& source) {
  return calibrated_robot_from(yaml::parse(text, source));
}

}  // namespace robcal
