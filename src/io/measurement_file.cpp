#include "robcal/io/measurement_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <unordered_map>

#include "csv_fields.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal {
namespace {

constexpr std::array<const char*, kJointCount> kJointColumns = {"j1", "j2", "j3", "j4", "j5", "j6"};

/// Columns of each kind, in the order the writer prints them.
std::vector<std::string> columns_of(MeasurementKind kind) {
  std::vector<std::string> columns = {"config"};
  if (kind != MeasurementKind::Poses) columns.emplace_back("target");
  for (const char* j : kJointColumns) columns.emplace_back(j);
  if (kind == MeasurementKind::Distances) {
    columns.emplace_back("length");
  } else {
    for (const char* c : {"x", "y", "z"}) columns.emplace_back(c);
  }
  if (kind == MeasurementKind::Poses)
    for (const char* c : {"qw", "qx", "qy", "qz"}) columns.emplace_back(c);
  return columns;
}

std::string join(const std::vector<std::string>& items, std::string_view separator) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += separator;
    out += items[i];
  }
  return out;
}

/// One data line of the file: its 1-based number and its trimmed fields.
struct Row {
  int line = 0;
  std::vector<std::string_view> fields;
};

/// Reads the fields of the rows by column name, with errors that name the place.
class RowReader {
 public:
  RowReader(const std::string& file, const std::map<std::string, int>& columns)
      : file_(file), columns_(columns) {}

  [[nodiscard]] SourceLocation where(const Row& row, const std::string& name) const {
    return {file_, row.line, columns_.at(name) + 1, name};
  }

  [[nodiscard]] std::string_view text(const Row& row, const std::string& name) const {
    const std::string_view value = row.fields[static_cast<size_t>(columns_.at(name))];
    if (value.empty())
      throw InputError(where(row, name), fmt::format("empty {}: expected a name", name));
    return value;
  }

  [[nodiscard]] double number(const Row& row, const std::string& name,
                              std::string_view unit) const {
    std::string_view value = row.fields[static_cast<size_t>(columns_.at(name))];
    const std::string expected = fmt::format("expected a finite number{}", unit);
    if (value.empty()) throw InputError(where(row, name), "empty field: " + expected);
    std::string_view digits = value;
    if (digits.front() == '+') digits.remove_prefix(1);
    double parsed = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), parsed);
    if (end != digits.data() + digits.size() ||
        (ec != std::errc() && ec != std::errc::result_out_of_range))
      throw InputError(where(row, name), fmt::format("'{}' is not a number: {}", value, expected));
    if (ec == std::errc::result_out_of_range || !std::isfinite(parsed))
      throw InputError(where(row, name), fmt::format("'{}' is not finite: {}", value, expected));
    return parsed;
  }

  [[nodiscard]] Vector6d joints_rad(const Row& row) const {
    Vector6d q;
    for (int i = 0; i < kJointCount; ++i)
      q[i] = deg2rad(number(row, kJointColumns[i], " (degrees)"));
    return q;
  }

  [[nodiscard]] Eigen::Vector3d xyz(const Row& row) const {
    return {number(row, "x", " (mm)"), number(row, "y", " (mm)"), number(row, "z", " (mm)")};
  }

  [[nodiscard]] int target(const Row& row, const Tool& tool) const {
    const std::string_view name = text(row, "target");
    const int index = tool.target_index(name);
    if (index < 0) {
      std::vector<std::string> known;
      for (const Target& t : tool.targets) known.push_back("'" + t.name + "'");
      throw InputError(where(row, "target"),
                       fmt::format("unknown target '{}': the tool has {}", name,
                                   known.empty() ? std::string("no targets") : join(known, ", ")));
    }
    return index;
  }

 private:
  const std::string& file_;
  const std::map<std::string, int>& columns_;
};

MeasurementKind detect_kind(const std::map<std::string, int>& columns, const std::string& file,
                            int header_line) {
  const auto has = [&](const char* name) { return columns.count(name) > 0; };
  if (has("qw") || has("qx") || has("qy") || has("qz")) return MeasurementKind::Poses;
  if (has("x") || has("y") || has("z")) return MeasurementKind::Points;
  if (has("length")) return MeasurementKind::Distances;
  throw InputError({file, header_line, 0, ""},
                   "cannot tell the kind of measurement file from the header: expected columns "
                   "x,y,z (points), x,y,z,qw,qx,qy,qz (poses) or length (distances)");
}

std::string kinds_text(const std::vector<MeasurementKind>& kinds) {
  std::vector<std::string> names;
  names.reserve(kinds.size());
  for (MeasurementKind k : kinds) names.emplace_back(measurement_kind_name(k));
  return join(names, " or ");
}

/// Degrees for a joint value (rad) that read back to exactly `rad` when a double within two
/// ulps of rad2deg(rad) does (about 91% of values; the rest are 1 ulp off), so a file that is
/// read and written again reads back to the same radians.
double degrees_reading_back(double rad) {
  const double degrees = rad2deg(rad);
  double up = degrees, down = degrees;
  if (deg2rad(degrees) == rad) return degrees;
  for (int step = 0; step < 2; ++step) {
    up = std::nextafter(up, HUGE_VAL);
    down = std::nextafter(down, -HUGE_VAL);
    if (deg2rad(up) == rad) return up;
    if (deg2rad(down) == rad) return down;
  }
  return degrees;
}

/// Quaternions must be unit up to what 6-decimal files keep; they are normalised after.
constexpr double kQuaternionTolerance = 1e-5;

}  // namespace

std::string_view measurement_kind_name(MeasurementKind kind) {
  switch (kind) {
    case MeasurementKind::Points:
      return "points";
    case MeasurementKind::Poses:
      return "poses";
    case MeasurementKind::Distances:
      return "distances";
  }
  return "unknown";
}

MeasurementFile parse_measurements_csv(std::string_view text, const std::string& source_name,
                                       const Tool& tool,
                                       const std::vector<MeasurementKind>& accepted) {
  MeasurementFile result;
  MeasurementSet& set = result.measurements;
  set.file = source_name;

  // Split into lines, dropping comments and blank lines but keeping the line numbers.
  std::vector<Row> rows;
  int header_line = 0;
  std::vector<std::string_view> header;
  int line_number = 0;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t newline = text.find('\n', start);
    const std::string_view line = text.substr(
        start, newline == std::string_view::npos ? std::string_view::npos : newline - start);
    ++line_number;
    start = newline == std::string_view::npos ? text.size() + 1 : newline + 1;
    const std::string_view content = csv::trim(line);
    if (content.empty() || content.front() == '#') continue;
    if (header_line == 0) {
      header_line = line_number;
      header = csv::split_fields(content);
    } else {
      rows.push_back({line_number, csv::split_fields(content)});
    }
  }
  if (header_line == 0)
    throw InputError({source_name, 0, 0, ""},
                     "empty measurement file: expected a header row such as "
                     "'config,target,j1,j2,j3,j4,j5,j6,x,y,z'");

  std::map<std::string, int> columns;
  for (size_t i = 0; i < header.size(); ++i) {
    std::string name(header[i]);
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (name.empty())
      throw InputError({source_name, header_line, static_cast<int>(i) + 1, ""},
                       "empty column name in the header");
    if (!columns.emplace(name, static_cast<int>(i)).second)
      throw InputError({source_name, header_line, static_cast<int>(i) + 1, name},
                       fmt::format("column '{}' appears twice in the header", name));
  }
  set.kind = detect_kind(columns, source_name, header_line);
  const std::string kind_name(measurement_kind_name(set.kind));
  if (!accepted.empty() && std::find(accepted.begin(), accepted.end(), set.kind) == accepted.end())
    throw InputError({source_name, header_line, 0, ""},
                     fmt::format("this is a {} file (by its columns); this command takes {} files",
                                 kind_name, kinds_text(accepted)));

  const std::vector<std::string> required = columns_of(set.kind);
  for (const std::string& name : required)
    if (columns.count(name) == 0)
      throw InputError({source_name, header_line, 0, name},
                       fmt::format("missing column '{}': a {} file needs the columns {}", name,
                                   kind_name, join(required, ",")));
  for (size_t i = 0; i < header.size(); ++i) {
    const auto used = std::find_if(required.begin(), required.end(), [&](const std::string& r) {
      return columns.at(r) == static_cast<int>(i);
    });
    if (used == required.end())
      result.warnings.push_back(
          fmt::format("{}:{}:{}: column '{}' is not used by a {} file; ignored", source_name,
                      header_line, i + 1, header[i], kind_name));
  }
  if (rows.empty())
    throw InputError({source_name, header_line, 0, ""},
                     "no measurement rows after the header: expected at least one row");

  const RowReader reader(source_name, columns);
  std::unordered_map<std::string, int> seen;  // "config\ntarget" -> line
  for (const Row& row : rows) {
    if (row.fields.size() != header.size())
      throw InputError({source_name, row.line, 0, ""},
                       fmt::format("expected {} comma-separated fields as in the header (line {}), "
                                   "got {}",
                                   header.size(), header_line, row.fields.size()));
    const std::string config(reader.text(row, "config"));
    std::string key = config;
    if (set.kind != MeasurementKind::Poses) key += "\n" + std::string(reader.text(row, "target"));
    const auto [previous, inserted] = seen.emplace(key, row.line);
    if (!inserted)
      throw InputError(
          {source_name, row.line, columns.at("config") + 1, "config"},
          set.kind == MeasurementKind::Poses
              ? fmt::format("duplicate row: config '{}' already on line {}", config,
                            previous->second)
              : fmt::format("duplicate row: config '{}' with target '{}' already on line {}",
                            config, reader.text(row, "target"), previous->second));

    switch (set.kind) {
      case MeasurementKind::Points: {
        PointMeasurement m;
        m.config = config;
        m.target = reader.target(row, tool);
        m.joints = reader.joints_rad(row);
        m.position_mm = reader.xyz(row);
        m.line = row.line;
        set.points.push_back(std::move(m));
        break;
      }
      case MeasurementKind::Poses: {
        PoseMeasurement m;
        m.config = config;
        m.joints = reader.joints_rad(row);
        const Eigen::Vector4d q(reader.number(row, "qw", ""), reader.number(row, "qx", ""),
                                reader.number(row, "qy", ""), reader.number(row, "qz", ""));
        if (std::abs(q.norm() - 1.0) > kQuaternionTolerance)
          throw InputError(
              {source_name, row.line, columns.at("qw") + 1, "qw,qx,qy,qz"},
              fmt::format("quaternion ({}, {}, {}, {}) has norm {:.9f}: expected a unit "
                          "quaternion (within {:g})",
                          q[0], q[1], q[2], q[3], q.norm(), kQuaternionTolerance));
        m.world_T_tcp.R =
            Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
        m.world_T_tcp.p = reader.xyz(row);
        m.line = row.line;
        set.poses.push_back(std::move(m));
        break;
      }
      case MeasurementKind::Distances: {
        DistanceMeasurement m;
        m.config = config;
        m.target = reader.target(row, tool);
        m.joints = reader.joints_rad(row);
        m.length_mm = reader.number(row, "length", " (mm)");
        if (m.length_mm < 0)
          throw InputError(
              reader.where(row, "length"),
              fmt::format("length {} is negative: expected a distance ≥ 0 (mm)", m.length_mm));
        m.line = row.line;
        set.distances.push_back(std::move(m));
        break;
      }
    }
  }
  return result;
}

MeasurementFile read_measurements_csv(const std::string& path, const Tool& tool,
                                      const std::vector<MeasurementKind>& accepted) {
  return parse_measurements_csv(read_text_file(path), path, tool, accepted);
}

std::string write_measurements_csv(const MeasurementSet& set, const Tool& tool,
                                   std::string_view comment) {
  std::string out;
  size_t start = 0;
  while (start < comment.size()) {
    const size_t newline = std::min(comment.find('\n', start), comment.size());
    out += fmt::format("# {}\n", comment.substr(start, newline - start));
    start = newline + 1;
  }
  out += join(columns_of(set.kind), ",") + "\n";

  const auto config = [](const std::string& name) -> const std::string& {
    if (name.empty() || name.find_first_of(",\n\r#") != std::string::npos)
      throw InputError({"", 0, 0, "config"},
                       fmt::format("configuration label '{}' cannot be written to CSV: expected a "
                                   "non-empty label without commas, '#' or line breaks",
                                   name));
    return name;
  };
  const auto target = [&](int index) -> const std::string& {
    if (index < 0 || index >= static_cast<int>(tool.targets.size()))
      throw InputError({"", 0, 0, "target"},
                       fmt::format("target index {} is not a target of the tool ({} targets)",
                                   index, tool.targets.size()));
    return tool.targets[static_cast<size_t>(index)].name;
  };
  const auto joints = [](const Vector6d& q) {
    return fmt::format("{},{},{},{},{},{}", degrees_reading_back(q[0]), degrees_reading_back(q[1]),
                       degrees_reading_back(q[2]), degrees_reading_back(q[3]),
                       degrees_reading_back(q[4]), degrees_reading_back(q[5]));
  };
  switch (set.kind) {
    case MeasurementKind::Points:
      for (const PointMeasurement& m : set.points)
        out +=
            fmt::format("{},{},{},{},{},{}\n", config(m.config), target(m.target), joints(m.joints),
                        m.position_mm.x(), m.position_mm.y(), m.position_mm.z());
      break;
    case MeasurementKind::Poses:
      for (const PoseMeasurement& m : set.poses) {
        Eigen::Quaterniond q(m.world_T_tcp.R);
        if (q.w() < 0) q.coeffs() = -q.coeffs();
        out += fmt::format("{},{},{},{},{},{},{},{},{}\n", config(m.config), joints(m.joints),
                           m.world_T_tcp.p.x(), m.world_T_tcp.p.y(), m.world_T_tcp.p.z(), q.w(),
                           q.x(), q.y(), q.z());
      }
      break;
    case MeasurementKind::Distances:
      for (const DistanceMeasurement& m : set.distances)
        out += fmt::format("{},{},{},{}\n", config(m.config), target(m.target), joints(m.joints),
                           m.length_mm);
      break;
  }
  return out;
}

}  // namespace robcal
