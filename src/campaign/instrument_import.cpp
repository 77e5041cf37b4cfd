#include "robcal/campaign/instrument_import.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <tuple>

#include "robcal/campaign/frames_world.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/yaml_checks.hpp"
#include "robcal/io/yaml_support.hpp"
#include "robcal/sim/simulator.hpp"

namespace robcal::campaign {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// A header name without its unit mark, and the unit ("" when none): "X [mm]" → ("x", "mm").
struct ColumnName {
  std::string name;
  std::string unit;
};

ColumnName normalise(const std::string& raw) {
  std::string name = lower(raw);
  std::string unit;
  const auto strip = [&](char open, char close) {
    if (name.size() > 2 && name.back() == close) {
      const size_t at = name.rfind(open);
      if (at != std::string::npos) {
        unit = name.substr(at + 1, name.size() - at - 2);
        name.erase(at);
      }
    }
  };
  strip('[', ']');
  strip('(', ')');
  while (!name.empty() && (name.back() == ' ' || name.back() == '_')) name.pop_back();
  for (const char* suffix : {"_mm", "_m", "_deg", "_rad", "_s"}) {
    const std::string s(suffix);
    if (unit.empty() && name.size() > s.size() && name.ends_with(s)) {
      unit = s.substr(1);
      name.erase(name.size() - s.size());
    }
  }
  return {name, unit};
}

/// Names instrument software gives each role (normalised).
const std::map<std::string, std::vector<std::string>>& role_aliases() {
  static const std::map<std::string, std::vector<std::string>> kAliases = {
      {"x", {"x"}},
      {"y", {"y"}},
      {"z", {"z"}},
      {"qw", {"qw", "q0"}},
      {"qx", {"qx", "q1"}},
      {"qy", {"qy", "q2"}},
      {"qz", {"qz", "q3"}},
      {"rx", {"rx", "rot x"}},
      {"ry", {"ry", "rot y"}},
      {"rz", {"rz", "rot z"}},
      {"target",
       {"target", "point", "point name", "name", "target name", "label", "id", "point id"}},
      {"config", {"config", "configuration", "pose"}},
      {"time", {"time", "timestamp", "time stamp", "date/time", "datetime"}}};
  return kAliases;
}

/// The columns of a table: names (normalised), units, the line of the header (0: none), and
/// the data rows.
struct Columns {
  std::vector<ColumnName> names;
  int header_line = 0;
  std::vector<const TextRow*> data;
  std::map<std::string, int> role;  ///< role → column index
};

Columns resolve_columns(const TextTable& table, const std::vector<std::string>& given,
                        bool has_header, const std::map<std::string, std::string>& roles,
                        const std::vector<std::string>& known_roles) {
  Columns c;
  size_t first_data = 0;
  if (given.empty()) {
    const TextRow& header = table.rows.front();
    for (const std::string& f : header.fields) c.names.push_back(normalise(f));
    c.header_line = header.line;
    first_data = 1;
  } else {
    for (const std::string& f : given) c.names.push_back(normalise(f));
    first_data = has_header ? 1 : 0;
  }
  for (size_t r = first_data; r < table.rows.size(); ++r) c.data.push_back(&table.rows[r]);

  std::map<std::string, int> by_name;
  for (size_t i = 0; i < c.names.size(); ++i) {
    if (c.names[i].name.empty() || c.names[i].name == "-") continue;
    if (!by_name.emplace(c.names[i].name, static_cast<int>(i)).second)
      throw InputError({table.file, c.header_line,
                        c.header_line ? table.rows.front().columns[i] : 0, c.names[i].name},
                       fmt::format("column '{}' appears twice", c.names[i].name));
  }
  for (const std::string& role : known_roles) {
    const auto mapped = roles.find(role);
    if (mapped != roles.end()) {
      const auto column = by_name.find(lower(mapped->second));
      if (column == by_name.end()) {
        std::vector<std::string> names;
        names.reserve(by_name.size());
        for (const auto& [name, index] : by_name) names.push_back(name);
        throw InputError({table.file, c.header_line, 0, role},
                         fmt::format("the {} column is said to be '{}', which the file does not "
                                     "have: its columns are {}",
                                     role, mapped->second, fmt::join(names, ", ")));
      }
      c.role[role] = column->second;
      continue;
    }
    const auto aliases = role_aliases().find(role);
    if (aliases == role_aliases().end()) continue;
    for (const std::string& alias : aliases->second) {
      const auto column = by_name.find(alias);
      if (column != by_name.end()) {
        c.role[role] = column->second;
        break;
      }
    }
  }
  return c;
}

const std::vector<std::string> kExportRoles = {"config", "target", "time", "x",  "y",  "z", "qw",
                                               "qx",     "qy",     "qz",   "rx", "ry", "rz"};

/// One reading of the export.
struct Reading {
  int line = 0;
  std::string config, target;
  double time_s = 0;
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
};

struct LogRow {
  int line = 0;
  std::string config, target;
  double time_s = 0;
  Vector6d joints = Vector6d::Zero();
};

/// Reads a field of a data row by role, with its location for messages.
struct FieldReader {
  const TextTable& table;
  const Columns& columns;

  [[nodiscard]] bool has(const std::string& role) const { return columns.role.count(role) > 0; }

  [[nodiscard]] SourceLocation where(const TextRow& row, const std::string& role) const {
    return field_location(table, row, static_cast<size_t>(columns.role.at(role)), role);
  }
  [[nodiscard]] const std::string& text(const TextRow& row, const std::string& role) const {
    const std::string& value = row.fields[static_cast<size_t>(columns.role.at(role))];
    if (value.empty()) throw InputError(where(row, role), fmt::format("empty {} name", role));
    return value;
  }
  [[nodiscard]] double number(const TextRow& row, const std::string& role,
                              std::string_view expected) const {
    return parse_number(row.fields[static_cast<size_t>(columns.role.at(role))],
                        table.dialect.decimal, where(row, role), expected);
  }
  [[nodiscard]] double time(const TextRow& row) const {
    return parse_time_seconds(row.fields[static_cast<size_t>(columns.role.at("time"))],
                              table.dialect.decimal, where(row, "time"));
  }
  void check_width(const TextRow& row) const {
    if (row.fields.size() != columns.names.size())
      throw InputError({table.file, row.line, 0, ""},
                       fmt::format("expected {} fields ({}), got {}", columns.names.size(),
                                   columns.header_line ? fmt::format("as in the header, line {}",
                                                                     columns.header_line)
                                                       : std::string("as the column list"),
                                   row.fields.size()));
  }
};

/// The length unit's factor to mm: the format's, else the header's marks (all alike), else mm.
double length_factor(const ExportFormat& format, const Columns& c, const std::string& file) {
  std::string unit = format.unit;
  if (unit.empty()) {
    for (const char* axis : {"x", "y", "z"}) {
      const auto it = c.role.find(axis);
      if (it == c.role.end()) continue;
      const std::string& mark = c.names[static_cast<size_t>(it->second)].unit;
      if (mark.empty()) continue;
      if (!unit.empty() && mark != unit)
        throw InputError({file, c.header_line, 0, axis},
                         fmt::format("the header gives x, y, z in different units ('{}' and "
                                     "'{}'): expected one length unit",
                                     unit, mark));
      unit = mark;
    }
  }
  if (unit.empty() || unit == "mm") return 1.0;
  if (unit == "m") return 1000.0;
  throw InputError({file, c.header_line, 0, "unit"},
                   fmt::format("unknown length unit '{}': expected mm or m", unit));
}

Eigen::Matrix3d rotation_from_angles(const Eigen::Vector3d& r, AngleOrder order) {
  const Eigen::AngleAxisd ax(r.x(), Eigen::Vector3d::UnitX()), ay(r.y(), Eigen::Vector3d::UnitY()),
      az(r.z(), Eigen::Vector3d::UnitZ());
  return order == AngleOrder::FixedXyz ? Eigen::Matrix3d(az * ay * ax)
                                       : Eigen::Matrix3d(ax * ay * az);
}

/// Quaternions must be unit up to what exports keep (6 decimals); normalised after.
constexpr double kQuaternionTolerance = 1e-5;

std::vector<Reading> read_export(const NamedText& file, const ExportFormat& format,
                                 MeasurementKind& kind, bool& has_time) {
  const TextTable table = read_text_table(file.text, file.name, format.dialect);
  const Columns columns =
      resolve_columns(table, format.columns, format.columns.empty() || format.has_header,
                      format.roles, kExportRoles);
  const FieldReader reader{table, columns};
  for (const char* axis : {"x", "y", "z"})
    if (!reader.has(axis))
      throw InputError({file.name, columns.header_line, 0, axis},
                       fmt::format("no '{}' column: name the columns (a header, or columns/roles "
                                   "in the mapping file)",
                                   axis));
  const bool quaternion =
      reader.has("qw") || reader.has("qx") || reader.has("qy") || reader.has("qz");
  const bool angles = reader.has("rx") || reader.has("ry") || reader.has("rz");
  if (quaternion && angles)
    throw InputError({file.name, columns.header_line, 0, ""},
                     "both quaternion and angle columns: expected one orientation");
  if (quaternion)
    for (const char* q : {"qw", "qx", "qy", "qz"})
      if (!reader.has(q))
        throw InputError({file.name, columns.header_line, 0, q},
                         fmt::format("quaternion column '{}' missing: expected qw, qx, qy, qz", q));
  if (angles)
    for (const char* a : {"rx", "ry", "rz"})
      if (!reader.has(a))
        throw InputError({file.name, columns.header_line, 0, a},
                         fmt::format("angle column '{}' missing: expected rx, ry, rz", a));
  kind = quaternion || angles ? MeasurementKind::Poses : MeasurementKind::Points;
  has_time = reader.has("time");
  if (columns.data.empty())
    throw InputError({file.name, columns.header_line, 0, ""}, "no readings after the header");

  const double to_mm = length_factor(format, columns, file.name);
  const std::string length_text = to_mm == 1.0 ? "a length in mm" : "a length in m";
  const std::string angle_text =
      format.angles_in_degrees ? "an angle in degrees" : "an angle in radians";
  std::vector<Reading> readings;
  for (const TextRow* row : columns.data) {
    reader.check_width(*row);
    Reading r;
    r.line = row->line;
    if (reader.has("config")) r.config = reader.text(*row, "config");
    if (reader.has("target")) r.target = reader.text(*row, "target");
    if (reader.has("time")) r.time_s = reader.time(*row);
    for (int k = 0; k < 3; ++k)
      r.position_mm[k] =
          to_mm * reader.number(*row, std::string(1, static_cast<char>('x' + k)), length_text);
    if (quaternion) {
      const Eigen::Vector4d q(reader.number(*row, "qw", "a quaternion component"),
                              reader.number(*row, "qx", "a quaternion component"),
                              reader.number(*row, "qy", "a quaternion component"),
                              reader.number(*row, "qz", "a quaternion component"));
      if (std::abs(q.norm() - 1.0) > kQuaternionTolerance)
        throw InputError(reader.where(*row, "qw"),
                         fmt::format("quaternion ({}, {}, {}, {}) has norm {:.9f}: expected a "
                                     "unit quaternion (within {:g})",
                                     q[0], q[1], q[2], q[3], q.norm(), kQuaternionTolerance));
      r.R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    } else if (angles) {
      Eigen::Vector3d a(reader.number(*row, "rx", angle_text),
                        reader.number(*row, "ry", angle_text),
                        reader.number(*row, "rz", angle_text));
      if (format.angles_in_degrees) a *= kDegToRad;
      r.R = rotation_from_angles(a, format.angle_order);
    }
    readings.push_back(std::move(r));
  }
  return readings;
}

std::vector<LogRow> read_joint_log(const NamedText& file, const TextDialect& dialect,
                                   bool& has_time) {
  const TextTable table = read_text_table(file.text, file.name, dialect);
  std::vector<std::string> roles = {"config", "target", "time"};
  for (int j = 1; j <= kJointCount; ++j) roles.push_back(fmt::format("j{}", j));
  const Columns columns = resolve_columns(table, {}, true, {}, roles);
  // Joints are found by their own names (not aliases).
  Columns with_joints = columns;
  for (size_t i = 0; i < columns.names.size(); ++i)
    for (int j = 1; j <= kJointCount; ++j)
      if (columns.names[i].name == fmt::format("j{}", j) ||
          columns.names[i].name == fmt::format("a{}", j))
        with_joints.role[fmt::format("j{}", j)] = static_cast<int>(i);
  const FieldReader reader{table, with_joints};
  for (const std::string& role :
       {std::string("config"), std::string("j1"), std::string("j2"), std::string("j3"),
        std::string("j4"), std::string("j5"), std::string("j6")})
    if (!reader.has(role))
      throw InputError({file.name, columns.header_line, 0, role},
                       fmt::format("the joint log has no '{}' column: expected a header with "
                                   "config, j1..j6 (degrees) and optionally time, target",
                                   role));
  if (columns.data.empty())
    throw InputError({file.name, columns.header_line, 0, ""}, "no rows after the header");
  has_time = reader.has("time");
  for (int j = 1; j <= kJointCount; ++j) {
    const std::string& unit =
        with_joints.names[static_cast<size_t>(with_joints.role.at(fmt::format("j{}", j)))].unit;
    if (!unit.empty() && unit != "deg")
      throw InputError({file.name, columns.header_line, 0, fmt::format("j{}", j)},
                       fmt::format("joint unit '{}': expected degrees (deg)", unit));
  }
  std::vector<LogRow> rows;
  for (const TextRow* row : columns.data) {
    reader.check_width(*row);
    LogRow r;
    r.line = row->line;
    r.config = reader.text(*row, "config");
    if (reader.has("target")) r.target = reader.text(*row, "target");
    if (reader.has("time")) r.time_s = reader.time(*row);
    for (int j = 0; j < kJointCount; ++j)
      r.joints[j] =
          deg2rad(reader.number(*row, fmt::format("j{}", j + 1), "a joint value in degrees"));
    rows.push_back(std::move(r));
  }
  return rows;
}

/// "FILE:L1, FILE:L2, … (and N more)".
template <typename Row>
std::string list_lines(const std::string& file, const std::vector<const Row*>& rows) {
  std::string out;
  const size_t shown = std::min<size_t>(rows.size(), 10);
  for (size_t i = 0; i < shown; ++i)
    out += fmt::format("{}{}:{} ({})", i ? ", " : "", file, rows[i]->line,
                       rows[i]->config.empty() ? "-" : rows[i]->config);
  if (rows.size() > shown) out += fmt::format(" and {} more", rows.size() - shown);
  return out;
}

/// Pairs (reading, log row) by the requested rule.
std::vector<std::pair<size_t, size_t>> join(const ImportRequest& request,
                                            const std::vector<Reading>& readings,
                                            const std::vector<LogRow>& log, bool export_has_config,
                                            bool export_has_time, bool log_has_time,
                                            bool log_has_target, bool export_has_target,
                                            std::vector<std::string>& warnings) {
  const std::string& ef = request.export_file.name;
  const std::string& lf = request.joint_log.name;
  std::vector<std::pair<size_t, size_t>> pairs;
  std::vector<bool> used(log.size(), false);
  switch (request.join) {
    case JoinBy::Order: {
      if (readings.size() != log.size()) {
        std::string detail;
        if (readings.size() > log.size()) {
          std::vector<const Reading*> extra;
          for (size_t i = log.size(); i < readings.size(); ++i) extra.push_back(&readings[i]);
          detail = "readings without a log row: " + list_lines(ef, extra);
        } else {
          std::vector<const LogRow*> extra;
          for (size_t i = readings.size(); i < log.size(); ++i) extra.push_back(&log[i]);
          detail = "log rows without a reading: " + list_lines(lf, extra);
        }
        throw InputError(
            {ef, 0, 0, ""},
            fmt::format("{} readings (lines {}–{}) but the joint log {} has {} rows (lines "
                        "{}–{}): joining by order needs equal counts; {}. Join by name or time, "
                        "or remove the rows that do not belong",
                        readings.size(), readings.front().line, readings.back().line, lf,
                        log.size(), log.front().line, log.back().line, detail));
      }
      for (size_t i = 0; i < readings.size(); ++i) pairs.emplace_back(i, i);
      std::fill(used.begin(), used.end(), true);
      break;
    }
    case JoinBy::Name: {
      if (!export_has_config)
        throw InputError({ef, 0, 0, "config"},
                         "joining by name needs a configuration column in the export (name it "
                         "'config' or map one, e.g. roles: {config: group})");
      const bool with_target = log_has_target && export_has_target;
      std::map<std::string, size_t> by_key;
      for (size_t i = 0; i < log.size(); ++i) {
        const std::string key = with_target ? log[i].config + "\n" + log[i].target : log[i].config;
        const auto [it, inserted] = by_key.emplace(key, i);
        if (!inserted)
          throw InputError(
              {lf, log[i].line, 0, "config"},
              fmt::format("configuration '{}'{} already on line {}: names must be "
                          "unique to join by name",
                          log[i].config,
                          with_target ? fmt::format(" with target '{}'", log[i].target) : "",
                          log[it->second].line));
      }
      for (size_t r = 0; r < readings.size(); ++r) {
        const std::string key =
            with_target ? readings[r].config + "\n" + readings[r].target : readings[r].config;
        const auto it = by_key.find(key);
        if (it == by_key.end())
          throw InputError(
              {ef, readings[r].line, 0, "config"},
              fmt::format("configuration '{}'{} is not in the joint log {}", readings[r].config,
                          with_target ? fmt::format(" with target '{}'", readings[r].target) : "",
                          lf));
        if (used[it->second])
          throw InputError({ef, readings[r].line, 0, "config"},
                           fmt::format("configuration '{}' is read twice: its log row {}:{} "
                                       "already has a reading",
                                       readings[r].config, lf, log[it->second].line));
        used[it->second] = true;
        pairs.emplace_back(r, it->second);
      }
      break;
    }
    case JoinBy::Time: {
      if (!export_has_time || !log_has_time)
        throw InputError({export_has_time ? lf : ef, 0, 0, "time"},
                         "joining by time needs a time column in both the export and the joint "
                         "log");
      // A log row (one configuration) may get one reading per target.
      std::map<std::pair<size_t, std::string>, size_t> owner;
      // Log rows by time, so each reading finds its nearest row by bisection.
      std::vector<size_t> by_time(log.size());
      for (size_t i = 0; i < log.size(); ++i) by_time[i] = i;
      std::stable_sort(by_time.begin(), by_time.end(),
                       [&](size_t a, size_t b) { return log[a].time_s < log[b].time_s; });
      for (size_t r = 0; r < readings.size(); ++r) {
        const auto after = std::lower_bound(by_time.begin(), by_time.end(), readings[r].time_s,
                                            [&](size_t i, double t) { return log[i].time_s < t; });
        size_t best = after == by_time.end() ? by_time.back() : *after;
        if (after != by_time.begin() && std::abs(log[*(after - 1)].time_s - readings[r].time_s) <=
                                            std::abs(log[best].time_s - readings[r].time_s))
          best = *(after - 1);
        const double gap = std::abs(log[best].time_s - readings[r].time_s);
        if (gap > request.time_tolerance_s)
          throw InputError({ef, readings[r].line, 0, "time"},
                           fmt::format("no joint-log row within ±{:g} s of this reading (nearest: "
                                       "{}:{} at {:.3f} s): expected a log row for every reading",
                                       request.time_tolerance_s, lf, log[best].line, gap));
        const auto [it, first] = owner.emplace(std::pair{best, readings[r].target}, r);
        if (!first)
          throw InputError(
              {ef, readings[r].line, 0, "time"},
              fmt::format("this reading and the one on line {} (same target) are "
                          "both nearest to log row {}:{}: the tolerance ±{:g} s is "
                          "too wide or a log row is missing",
                          readings[it->second].line, lf, log[best].line, request.time_tolerance_s));
        used[best] = true;
        pairs.emplace_back(r, best);
      }
      break;
    }
  }
  std::vector<const LogRow*> unmeasured;
  for (size_t i = 0; i < log.size(); ++i)
    if (!used[i]) unmeasured.push_back(&log[i]);
  if (!unmeasured.empty()) {
    const std::string text = fmt::format("{} joint-log rows have no reading: {}", unmeasured.size(),
                                         list_lines(lf, unmeasured));
    if (!request.allow_unmeasured)
      throw InputError({lf, unmeasured.front()->line, 0, ""},
                       text + " (pass --allow-unmeasured to import the others)");
    warnings.push_back(text);
  }
  return pairs;
}

}  // namespace

JoinBy parse_join_by(const std::string& text, const std::string& flag) {
  if (text == "order") return JoinBy::Order;
  if (text == "name") return JoinBy::Name;
  if (text == "time") return JoinBy::Time;
  throw InputError({"", 0, 0, flag},
                   fmt::format("unknown join '{}': expected order, name or time", text));
}

namespace {

/// The choice named `value` (case-insensitive) among `choices`; `error` builds the InputError
/// for anything else (the caller knows the place).
template <typename T>
T choose(const std::string& value, const std::vector<std::pair<std::string, T>>& choices,
         const std::function<InputError(const std::string&)>& error) {
  const std::string wanted = lower(value);
  std::vector<std::string> names;
  for (const auto& [name, choice] : choices) {
    if (name == wanted) return choice;
    names.push_back(name);
  }
  throw error(fmt::format("unknown value '{}': expected {}", value, fmt::join(names, ", ")));
}

const std::vector<std::pair<std::string, char>> kDelimiters = {
    {"comma", ','}, {"semicolon", ';'}, {"tab", '\t'}, {"space", ' '}, {",", ','}, {";", ';'}};
const std::vector<std::pair<std::string, char>> kDecimals = {
    {"point", '.'}, {"comma", ','}, {".", '.'}, {",", ','}};
const std::vector<std::pair<std::string, std::string>> kUnits = {{"mm", "mm"}, {"m", "m"}};

}  // namespace

void set_export_option(ExportFormat& format, const std::string& option, const std::string& value,
                       const std::string& flag) {
  const auto error = [&](const std::string& what) { return InputError({"", 0, 0, flag}, what); };
  if (option == "delimiter") {
    format.dialect.delimiter = choose(value, kDelimiters, error);
  } else if (option == "decimal") {
    format.dialect.decimal = choose(value, kDecimals, error);
  } else if (option == "unit") {
    format.unit = choose(value, kUnits, error);
  } else if (option == "columns") {
    format.columns.clear();
    size_t start = 0;
    while (start <= value.size()) {
      const size_t comma = std::min(value.find(',', start), value.size());
      std::string name = value.substr(start, comma - start);
      name.erase(0, name.find_first_not_of(' '));
      name.erase(name.find_last_not_of(' ') + 1);
      format.columns.push_back(name);
      start = comma + 1;
    }
    format.has_header = false;
  } else if (option == "config-column") {
    format.roles["config"] = lower(value);
  } else {
    throw error(fmt::format("unknown export option '{}'", option));
  }
}

ExportFormat parse_export_format(const std::string& yaml_text, const std::string& file) {
  const yaml::Node root = yaml::parse(yaml_text, file);
  ExportFormat format;
  if (!root.node.IsMap()) throw root.error("expected a map of export settings");
  yaml::expect_keys(root, {"delimiter", "decimal", "header", "columns", "roles", "unit", "angles"});
  for (const std::string& key : root.keys()) {
    const yaml::Node node = root.at(key);
    const auto error = [&node](const std::string& what) { return node.error(what); };
    if (key == "delimiter") {
      format.dialect.delimiter = choose(node.as_string(), kDelimiters, error);
    } else if (key == "decimal") {
      format.dialect.decimal = choose(node.as_string(), kDecimals, error);
    } else if (key == "header") {
      format.has_header =
          choose<bool>(node.as_string(),
                       {{"true", true}, {"false", false}, {"yes", true}, {"no", false}}, error);
    } else if (key == "columns") {
      if (!node.node.IsSequence()) throw node.error("expected a list of column names");
      for (size_t i = 0; i < node.size(); ++i) format.columns.push_back(node.at(i).as_string());
    } else if (key == "roles") {
      for (const std::string& role : node.keys()) {
        if (std::find(kExportRoles.begin(), kExportRoles.end(), role) == kExportRoles.end())
          throw node.at(role).error(fmt::format("unknown role '{}': expected one of {}", role,
                                                fmt::join(kExportRoles, ", ")));
        format.roles[role] = lower(node.at(role).as_string());
      }
    } else if (key == "unit") {
      format.unit = choose(node.as_string(), kUnits, error);
    } else if (key == "angles") {
      yaml::expect_keys(node, {"unit", "order"});
      for (const std::string& sub : node.keys()) {
        const yaml::Node value = node.at(sub);
        const auto sub_error = [&value](const std::string& what) { return value.error(what); };
        if (sub == "unit")
          format.angles_in_degrees =
              choose<bool>(value.as_string(), {{"deg", true}, {"rad", false}}, sub_error);
        else  // order (expect_keys allows no other)
          format.angle_order = choose<AngleOrder>(
              value.as_string(),
              {{"fixed-xyz", AngleOrder::FixedXyz}, {"mobile-xyz", AngleOrder::MobileXyz}},
              sub_error);
      }
    }
  }
  if (!format.has_header && format.columns.empty())
    throw root.error("header: false needs `columns` (the column names in file order)");
  if (format.columns.empty())
    format.has_header = true;
  else if (!root.has("header"))
    format.has_header = false;
  return format;
}

namespace {

/// --target goes into the target column of the CSV written: a plain name, no cell separator,
/// quote or line break.
void check_target_name(const std::string& name) {
  const bool plain = name.find_first_not_of(' ') != std::string::npos && name.front() != ' ' &&
                     name.back() != ' ' &&
                     std::none_of(name.begin(), name.end(), [](unsigned char c) {
                       return c < 0x20 || c == 0x7F || c == ',' || c == ';' || c == '"';
                     });
  if (!plain)
    throw InputError({"", 0, 0, "--target"},
                     fmt::format("target name '{}': expected a name without blanks at its ends, "
                                 "commas, semicolons, quotes or control characters (it is "
                                 "written into the target column of the CSV)",
                                 name));
}

/// The plan's rows by configuration name.
std::map<std::string, ConfigurationRow> plan_rows(const NamedText& plan) {
  std::map<std::string, ConfigurationRow> rows;
  for (ConfigurationRow& row : parse_configuration_rows(plan.text, plan.name)) {
    const std::string name = row.config.name;
    rows.emplace(name, std::move(row));
  }
  return rows;
}

/// The plan's condition of the reading joined with log row `row`: its configuration's approach
/// and payload (an index into `payloads`, the names met so far, extended with a new one).
std::pair<Vector6d, int> planned_condition(const std::map<std::string, ConfigurationRow>& plan,
                                           const std::string& plan_file, const LogRow& row,
                                           const std::string& log_file,
                                           std::vector<NamedPayload>& payloads) {
  const auto it = plan.find(row.config);
  if (it == plan.end())
    throw InputError({log_file, row.line, 0, "config"},
                     fmt::format("configuration '{}' is not in the plan {} (--configs): the "
                                 "joint log is of another measurement program",
                                 row.config, plan_file));
  const ConfigurationRow& planned = it->second;
  int index = -1;  // the tool's own payload
  if (!planned.payload.empty()) {
    const auto named = std::find_if(payloads.begin(), payloads.end(), [&](const NamedPayload& p) {
      return p.name == planned.payload;
    });
    index = static_cast<int>(named - payloads.begin());
    if (named == payloads.end()) payloads.push_back({planned.payload, {}});
  }
  return {planned.config.approach, index};
}

}  // namespace

ImportResult import_measurements(const ImportRequest& request) {
  if (!(request.time_tolerance_s > 0))
    throw InputError(
        {"", 0, 0, "--time-tolerance"},
        fmt::format("expected a time tolerance > 0 s, got {}", request.time_tolerance_s));
  ImportResult result;
  MeasurementKind kind = MeasurementKind::Points;
  bool export_has_time = false, log_has_time = false;
  const std::vector<Reading> readings =
      read_export(request.export_file, request.format, kind, export_has_time);
  const std::vector<LogRow> log =
      read_joint_log(request.joint_log, request.log_dialect, log_has_time);

  const auto any = [](const auto& rows, auto field) {
    return std::any_of(rows.begin(), rows.end(),
                       [&](const auto& r) { return !(r.*field).empty(); });
  };
  const bool export_has_config = any(readings, &Reading::config);
  const bool export_has_target = any(readings, &Reading::target);
  const bool log_has_target = any(log, &LogRow::target);
  // Names are never empty (the readers refuse empty names), so "any name" means "a column".
  if (!request.default_target.empty()) {
    check_target_name(request.default_target);
    if (export_has_target || log_has_target)
      throw InputError(
          {"", 0, 0, "--target"},
          fmt::format("'{}' would not be used: {} names the target of every reading (its target "
                      "column); give --target only when neither file names it",
                      request.default_target,
                      export_has_target ? request.export_file.name : request.joint_log.name));
  }
  const auto pairs = join(request, readings, log, export_has_config, export_has_time, log_has_time,
                          log_has_target, export_has_target, result.warnings);
  const std::map<std::string, ConfigurationRow> plan =
      request.plan ? plan_rows(*request.plan) : std::map<std::string, ConfigurationRow>{};
  const auto condition = [&](const LogRow& row) {
    return request.plan ? planned_condition(plan, request.plan->name, row, request.joint_log.name,
                                            result.targets.payloads)
                        : std::pair<Vector6d, int>{Vector6d::Ones(), -1};
  };

  MeasurementSet& set = result.measurements;
  set.kind = kind;
  set.file = request.export_file.name;
  std::map<std::string, int> seen;  // "config\ntarget" → export line
  for (const auto& [r, l] : pairs) {
    const Reading& reading = readings[r];
    const LogRow& row = log[l];
    if (kind == MeasurementKind::Poses) {
      const auto [it, inserted] = seen.emplace(row.config, reading.line);
      if (!inserted)
        throw InputError({request.export_file.name, reading.line, 0, ""},
                         fmt::format("configuration '{}' (log {}:{}) already has the pose read "
                                     "on line {}",
                                     row.config, request.joint_log.name, row.line, it->second));
      PoseMeasurement m;
      m.config = row.config;
      m.joints = row.joints;
      std::tie(m.approach, m.payload) = condition(row);
      m.world_T_tcp.R = reading.R;
      m.world_T_tcp.p = reading.position_mm;
      m.line = reading.line;
      set.poses.push_back(std::move(m));
      continue;
    }
    std::string target = reading.target;
    if (!row.target.empty()) {
      if (!target.empty() && target != row.target)
        throw InputError({request.export_file.name, reading.line, 0, "target"},
                         fmt::format("target '{}' but the joint log row {}:{} says target '{}'",
                                     target, request.joint_log.name, row.line, row.target));
      target = row.target;
    }
    if (target.empty()) target = request.default_target;
    if (target.empty())
      throw InputError({request.export_file.name, reading.line, 0, "target"},
                       "neither the export nor the joint log names the target: add a target "
                       "column or give the target (--target)");
    const auto [it, inserted] = seen.emplace(row.config + "\n" + target, reading.line);
    if (!inserted)
      throw InputError(
          {request.export_file.name, reading.line, 0, ""},
          fmt::format("configuration '{}' target '{}' (log {}:{}) already read on "
                      "line {}",
                      row.config, target, request.joint_log.name, row.line, it->second));
    int index = result.targets.target_index(target);
    if (index < 0) {
      result.targets.targets.push_back({target, Eigen::Vector3d::Zero(), false});
      index = static_cast<int>(result.targets.targets.size()) - 1;
    }
    PointMeasurement m;
    m.config = row.config;
    m.target = index;
    m.joints = row.joints;
    std::tie(m.approach, m.payload) = condition(row);
    m.position_mm = reading.position_mm;
    m.line = reading.line;
    set.points.push_back(std::move(m));
  }
  std::string comment =
      fmt::format("imported from {} joined by {} with {}", request.export_file.name,
                  request.join == JoinBy::Order  ? "order"
                  : request.join == JoinBy::Name ? "configuration name"
                                                 : "time",
                  request.joint_log.name);
  if (request.plan)
    comment += fmt::format("\nconditions (approach, payload) from the plan {}", request.plan->name);
  if (request.instrument_T_world) {
    set = measurements_in_frame(set, *request.instrument_T_world);
    result.world_frame = request.world_frame_file;
    comment += "\n" + world_frame_comment(request.world_frame_file);
  }
  result.csv = write_measurements_csv(set, result.targets, comment);
  return result;
}

std::vector<Eigen::Vector3d> read_export_points(const NamedText& file, const ExportFormat& format) {
  const size_t complete = file.text.rfind('\n');
  if (complete == std::string::npos) return {};
  const NamedText lines{file.name, file.text.substr(0, complete + 1)};
  // Nothing but comments, or only the header line so far: no reading yet.
  std::string_view body = lines.text;
  if (body.substr(0, 3) == "\xEF\xBB\xBF") body.remove_prefix(3);
  int content_lines = 0;
  for (size_t start = 0; start < body.size();) {
    const size_t end = body.find('\n', start);
    std::string_view line = body.substr(start, end - start);
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    if (!line.empty() && line != "\r" && line.front() != '#' && line.substr(0, 2) != "//")
      ++content_lines;
    start = end + 1;
  }
  if (content_lines <= (format.columns.empty() || format.has_header ? 1 : 0)) return {};
  MeasurementKind kind = MeasurementKind::Points;
  bool has_time = false;
  const std::vector<Reading> readings = read_export(lines, format, kind, has_time);
  if (kind != MeasurementKind::Points)
    throw InputError({file.name, 0, 0, ""},
                     "a session takes point readings; this export has poses");
  std::vector<Eigen::Vector3d> points;
  points.reserve(readings.size());
  for (const Reading& r : readings) points.push_back(r.position_mm);
  return points;
}

}  // namespace robcal::campaign
