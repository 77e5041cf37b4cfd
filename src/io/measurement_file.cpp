#include "robcal/io/measurement_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <unordered_map>

#include "csv_fields.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal {
namespace {

constexpr std::array<const char*, kJointCount> kJointColumns = {"j1", "j2", "j3", "j4", "j5", "j6"};

/// Columns of each kind, in the order the writer prints them (poses with `orientation`).
std::vector<std::string> columns_of(MeasurementKind kind,
                                    const std::vector<std::string>& orientation = {"qw", "qx", "qy",
                                                                                   "qz"}) {
  std::vector<std::string> columns = {"config"};
  if (kind != MeasurementKind::Poses) columns.emplace_back("target");
  for (const char* j : kJointColumns) columns.emplace_back(j);
  if (kind == MeasurementKind::Distances) {
    columns.emplace_back("length");
  } else {
    for (const char* c : {"x", "y", "z"}) columns.emplace_back(c);
  }
  if (kind == MeasurementKind::Poses)
    columns.insert(columns.end(), orientation.begin(), orientation.end());
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

/// Plausible ranges of the fields, in mm and degrees (see the header): a robot cell is metres
/// across, a joint turns at most ±455° on a six-axis arm.
constexpr double kMaxCoordinateMm = 100000;
constexpr double kMaxAngleDeg = 720;

/// A finite number in `value`; `unit` (with a leading blank) is said in the messages.
double parse_finite_number(std::string_view value, const SourceLocation& where,
                           std::string_view unit) {
  const std::string expected = fmt::format("expected a finite number{}", unit);
  if (value.empty()) throw InputError(where, "empty field: " + expected);
  std::string_view digits = value;
  if (digits.front() == '+') digits.remove_prefix(1);
  double parsed = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), parsed);
  if (end != digits.data() + digits.size() ||
      (ec != std::errc() && ec != std::errc::result_out_of_range))
    throw InputError(where, fmt::format("'{}' is not a number: {}", value, expected));
  if (ec == std::errc::result_out_of_range || !std::isfinite(parsed))
    throw InputError(where, fmt::format("'{}' is not finite: {}", value, expected));
  return parsed;
}

/// One data line of the file: its 1-based number and its trimmed fields.
struct Row {
  int line = 0;
  std::vector<std::string_view> fields;
};

/// Reads the fields of the rows by column name, with errors that name the place.
class RowReader {
 public:
  RowReader(const std::string& file, const std::map<std::string, int>& columns, bool metres,
            bool radians)
      : file_(file),
        columns_(columns),
        mm_per_unit_(metres ? 1000.0 : 1.0),
        rad_per_unit_(radians ? 1.0 : deg2rad(1.0)),
        length_unit_(metres ? "m" : "mm"),
        angle_unit_(radians ? "rad" : "degrees") {}

  [[nodiscard]] SourceLocation where(const Row& row, const std::string& name) const {
    return {file_, row.line, columns_.at(name) + 1, name};
  }

  [[nodiscard]] std::string_view text(const Row& row, const std::string& name) const {
    const std::string_view value = row.fields[static_cast<size_t>(columns_.at(name))];
    if (value.empty())
      throw InputError(where(row, name), fmt::format("empty {}: expected a name", name));
    return value;
  }

  /// A number of the column `name`; `unit` (with a leading blank) is said in the messages.
  [[nodiscard]] double number(const Row& row, const std::string& name,
                              std::string_view unit) const {
    return parse_finite_number(row.fields[static_cast<size_t>(columns_.at(name))], where(row, name),
                               unit);
  }

  /// A number within [lowest, highest] (in the file's unit `unit`), else refused with the range.
  [[nodiscard]] double number_within(const Row& row, const std::string& name, const char* unit,
                                     double lowest, double highest) const {
    const double value = number(row, name, fmt::format(" ({})", unit));
    if (value < lowest || value > highest)
      throw InputError(
          where(row, name),
          fmt::format("{} is outside the plausible range [{:g}, {:g}] {}: a typo or "
                      "a unit slip? (declare the units with '# units: m, rad' or "
                      "--units if they are not mm and degrees)",
                      row.fields[static_cast<size_t>(columns_.at(name))], lowest, highest, unit));
    return value;
  }

  [[nodiscard]] Vector6d joints_rad(const Row& row) const {
    Vector6d q;
    for (int i = 0; i < kJointCount; ++i) q[i] = angle_rad(row, kJointColumns[i]);
    return q;
  }

  [[nodiscard]] double angle_rad(const Row& row, const std::string& name) const {
    const double limit = deg2rad(kMaxAngleDeg) / rad_per_unit_;
    return rad_per_unit_ * number_within(row, name, angle_unit_, -limit, limit);
  }

  [[nodiscard]] double length_mm(const Row& row, const std::string& name) const {
    const double limit = kMaxCoordinateMm / mm_per_unit_;
    return mm_per_unit_ * number_within(row, name, length_unit_, -limit, limit);
  }

  /// A ballbar or wire length: above 0 and at most the cell's size.
  [[nodiscard]] double distance_mm(const Row& row, const std::string& name) const {
    const double limit = kMaxCoordinateMm / mm_per_unit_;
    const double length = number(row, name, fmt::format(" ({})", length_unit_));
    if (length <= 0 || length > limit)
      throw InputError(
          where(row, name),
          fmt::format("length {} is outside the plausible range (0, {:g}] {}: "
                      "expected a distance above 0",
                      row.fields[static_cast<size_t>(columns_.at(name))], limit, length_unit_));
    return mm_per_unit_ * length;
  }

  [[nodiscard]] Eigen::Vector3d xyz(const Row& row) const {
    return {length_mm(row, "x"), length_mm(row, "y"), length_mm(row, "z")};
  }

  [[nodiscard]] Vector6d approach(const Row& row) const {
    return parse_approach(row.fields[static_cast<size_t>(columns_.at("approach"))],
                          where(row, "approach"));
  }

  /// The optional `temperature` column (°C, the thermal group, docs/method/03-error-model.md
  /// §8): empty for a row without a reading.
  [[nodiscard]] std::optional<double> temperature_c(const Row& row) const {
    return parse_temperature_c(row.fields[static_cast<size_t>(columns_.at("temperature"))],
                               where(row, "temperature"));
  }

  /// The optional `time_s` column (s since the arm started working, the warm-up group,
  /// docs/method/03-error-model.md §10): empty for a row without a time.
  [[nodiscard]] std::optional<double> time_s(const Row& row) const {
    return parse_time_s(row.fields[static_cast<size_t>(columns_.at("time_s"))],
                        where(row, "time_s"));
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

  /// The optional `payload` column (several payloads, docs/method/03-error-model.md §7): a name
  /// of the tool's `payloads`, or empty for its own `payload`.
  [[nodiscard]] int payload(const Row& row, const Tool& tool) const {
    const std::string_view name = row.fields[static_cast<size_t>(columns_.at("payload"))];
    if (name.empty()) return -1;
    return payload_index_of(name, tool, where(row, "payload"), "its 'payload'");
  }

 private:
  const std::string& file_;
  const std::map<std::string, int>& columns_;
  double mm_per_unit_, rad_per_unit_;
  const char* length_unit_;
  const char* angle_unit_;
};

/// The orientation columns of a poses file and how to turn them into a rotation.
struct OrientationColumns {
  std::vector<std::string> names;  ///< qw,qx,qy,qz or the three angle columns (x, y, z order)
  bool quaternion = true;
  EulerOrder order;
};

/// Column names that look like an orientation: a file with them but no accepted set is refused
/// rather than read as a points file with the orientation silently ignored.
bool looks_like_orientation(const std::string& name) {
  static const std::array<const char*, 26> kNames = {
      "qw",   "qx", "qy", "qz", "a",    "b",     "c",    "w",    "p",
      "r",    "rx", "ry", "rz", "roll", "pitch", "yaw",  "rotx", "roty",
      "rotz", "q1", "q2", "q3", "q4",   "alpha", "beta", "gamma"};
  return std::find(kNames.begin(), kNames.end(), name) != kNames.end();
}

/// Finds the orientation columns of a file without `target` (nullopt: none at all).
std::optional<OrientationColumns> find_orientation(const std::map<std::string, int>& columns,
                                                   const std::optional<EulerOrder>& declared,
                                                   const std::string& file, int header_line) {
  const auto has = [&](const char* name) { return columns.count(name) > 0; };
  std::vector<std::string> found;
  for (const auto& [name, index] : columns)
    if (looks_like_orientation(name)) found.push_back(name);
  if (found.empty()) return std::nullopt;
  // Any quaternion column: a quaternion file (a missing one is named by the column check).
  if (has("qw") || has("qx") || has("qy") || has("qz"))
    return OrientationColumns{{"qw", "qx", "qy", "qz"}, true, {}};
  const auto complete = [&](std::initializer_list<const char*> set) {
    return std::all_of(set.begin(), set.end(), has);
  };
  std::vector<OrientationColumns> sets;
  if (complete({"a", "b", "c"})) sets.push_back({{"c", "b", "a"}, false, {{2, 1, 0}, true}});
  if (complete({"w", "p", "r"})) sets.push_back({{"w", "p", "r"}, false, {{0, 1, 2}, false}});
  if (complete({"rx", "ry", "rz"})) {
    if (!declared)
      throw InputError(
          {file, header_line, columns.at("rx") + 1, "rx"},
          "columns rx,ry,rz need their rotation order declared: add a header comment such as "
          "'# euler: intrinsic ZYX' (or extrinsic; any order of X, Y, Z) or give --euler");
    sets.push_back({{"rx", "ry", "rz"}, false, *declared});
  }
  std::string all;
  for (const std::string& name : found) all += (all.empty() ? "" : ",") + name;
  if (sets.size() != 1)
    throw InputError(
        {file, header_line, columns.at(found.front()) + 1, found.front()},
        fmt::format("{} orientation columns: found {}; accepted: qw,qx,qy,qz (unit "
                    "quaternion), a,b,c (ABB/KUKA, Rz(a)·Ry(b)·Rx(c)), w,p,r (Fanuc, "
                    "Rz(r)·Ry(p)·Rx(w)) or rx,ry,rz with a declared order ('# euler: intrinsic "
                    "ZYX'), exactly one set",
                    sets.empty() ? "unsupported" : "more than one set of", all));
  return sets.front();
}

/// Parses the header comments that declare units and the Euler order, before the header row;
/// a declaration that contradicts the caller's is an error.
void read_declaration(std::string_view comment, const SourceLocation& where,
                      MeasurementFormat& format, const MeasurementFormat& declared) {
  std::string text(csv::trim(comment.substr(1)));
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  MeasurementFormat found;
  if (text.starts_with("units:")) {
    parse_units(std::string_view(text).substr(6), where, found);
  } else if (text.starts_with("euler:")) {
    found.euler = parse_euler_order(std::string_view(text).substr(6), where);
  } else {
    return;
  }
  const auto merge = [&](auto& into, const auto& value, const auto& given, const char* what) {
    if (!value) return;
    if (given && !(*given == *value))
      throw InputError(where, fmt::format("the file declares {} other than the command line's "
                                          "option: remove one of them",
                                          what));
    into = value;
  };
  merge(format.length, found.length, declared.length, "a length unit");
  merge(format.angle, found.angle, declared.angle, "an angle unit");
  if (found.euler && declared.euler &&
      (found.euler->axes != declared.euler->axes ||
       found.euler->intrinsic != declared.euler->intrinsic))
    throw InputError(where,
                     "the file declares a rotation order other than --euler: remove one of them");
  if (found.euler) format.euler = found.euler;
}

MeasurementKind detect_kind(const std::map<std::string, int>& columns,
                            const std::optional<OrientationColumns>& orientation,
                            const std::string& file, int header_line) {
  const auto has = [&](const char* name) { return columns.count(name) > 0; };
  if (has("qw") || has("qx") || has("qy") || has("qz") || orientation)
    return MeasurementKind::Poses;
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

const Vector6d& approach_of(const MeasurementSet& set, size_t row) {
  return set.kind == MeasurementKind::Points  ? set.points[row].approach
         : set.kind == MeasurementKind::Poses ? set.poses[row].approach
                                              : set.distances[row].approach;
}

const Vector6d& joints_of(const MeasurementSet& set, size_t row) {
  return set.kind == MeasurementKind::Points  ? set.points[row].joints
         : set.kind == MeasurementKind::Poses ? set.poses[row].joints
                                              : set.distances[row].joints;
}

/// Refuses undeclared units that look like the other unit (see the file comment): a metre-scale
/// file read as mm would "calibrate" to hundreds of mm of residual, radians read as degrees to
/// a robot that barely moved.
void check_units(const MeasurementSet& set, const MeasurementFormat& format, int header_line,
                 const std::map<std::string, int>& columns) {
  constexpr size_t kRows = 5;
  if (set.size() < kRows) return;
  const std::string declare =
      "declare the units with a header comment such as '# units: m, deg' (or the --units "
      "option); '# units: mm, deg' if they really are";
  if (!format.length) {
    double span = 0;
    const char* column = set.kind == MeasurementKind::Distances ? "length" : "x";
    if (set.kind == MeasurementKind::Distances) {
      for (const DistanceMeasurement& m : set.distances) span = std::max(span, m.length_mm);
    } else {
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
      for (size_t row = 0; row < set.size(); ++row) {
        const Eigen::Vector3d& p = set.kind == MeasurementKind::Points
                                       ? set.points[row].position_mm
                                       : set.poses[row].world_T_tcp.p;
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      span = (hi - lo).maxCoeff();
    }
    if (span < 10)
      throw InputError(
          {set.file, header_line, columns.at(column) + 1, column},
          fmt::format("the {} only {:.4g} mm over {} rows: they look like metres, not "
                      "millimetres; {}",
                      set.kind == MeasurementKind::Distances ? "lengths reach" : "positions span",
                      span, set.size(), declare));
  }
  if (!format.angle) {
    double largest = 0;
    for (size_t row = 0; row < set.size(); ++row)
      largest = std::max(largest, joints_of(set, row).cwiseAbs().maxCoeff());
    if (largest > deg2rad(0.01) && largest <= deg2rad(2 * std::numbers::pi + 1e-6))
      throw InputError(
          {set.file, header_line, columns.at("j1") + 1, "j1"},
          fmt::format("every joint value is within ±{:.3f} over {} rows: they look like radians, "
                      "not degrees; declare the units with a header comment such as "
                      "'# units: mm, rad' (or the --units option); '# units: mm, deg' if they "
                      "really are degrees",
                      rad2deg(largest), set.size()));
  }
}

}  // namespace

Eigen::Matrix3d rotation_from_axis_angles(const Eigen::Vector3d& angles, const EulerOrder& order) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  for (int k = 0; k < 3; ++k) {
    const int axis = order.axes[static_cast<size_t>(order.intrinsic ? k : 2 - k)];
    R = R * Eigen::AngleAxisd(angles[axis], Eigen::Vector3d::Unit(axis)).toRotationMatrix();
  }
  return R;
}

bool plausible_temperature_c(double celsius) {
  return celsius >= -50 && celsius <= 150;  // workshop to foundry; outside: a unit slip (°F, K)
}

std::optional<double> parse_temperature_c(std::string_view text, const SourceLocation& where) {
  if (text.empty()) return std::nullopt;
  const double t = parse_finite_number(text, where, " (°C)");
  if (!plausible_temperature_c(t))
    throw InputError(where,
                     fmt::format("temperature {} °C is implausible: expected °C in [-50, 150]", t));
  return t;
}

std::optional<double> parse_time_s(std::string_view text, const SourceLocation& where) {
  if (text.empty()) return std::nullopt;
  const double t = parse_finite_number(text, where, " (s)");
  if (t < 0 || t > 1e7)  // beyond 16 weeks: a unit slip (ms) or a clock's epoch
    throw InputError(where, fmt::format("time {} s is implausible: expected seconds in [0, 1e7] "
                                        "since the arm started working",
                                        t));
  return t;
}

int payload_index_of(std::string_view name, const Tool& tool, const SourceLocation& where,
                     std::string_view when_empty) {
  const int index = tool.payload_index(name);
  if (index >= 0) return index;
  std::vector<std::string> known;
  for (const NamedPayload& p : tool.payloads) known.push_back("'" + p.name + "'");
  throw InputError(
      where, fmt::format("unknown payload '{}': expected a name under 'payloads:' in the tool "
                         "file ({}), or empty for {}",
                         name, known.empty() ? std::string("it lists none") : join(known, ", "),
                         when_empty));
}

std::string approach_text(const Vector6d& approach) {
  std::string text;
  for (int j = 0; j < kJointCount; ++j) text += approach[j] > 0 ? '+' : approach[j] < 0 ? '-' : '0';
  return text;
}

Vector6d parse_approach(std::string_view text, const SourceLocation& where) {
  Vector6d s;
  bool valid = text.size() == kJointCount;
  for (int j = 0; valid && j < kJointCount; ++j) {
    const char c = text[static_cast<size_t>(j)];
    valid = c == '+' || c == '-' || c == '0';
    s[j] = c == '+' ? 1.0 : c == '-' ? -1.0 : 0.0;
  }
  if (!valid)
    throw InputError(where, fmt::format("'{}' is not an approach: expected six characters, one "
                                        "per joint, '+' (approached from below), '-' (from "
                                        "above) or '0' (unknown), e.g. '++-+++'",
                                        text));
  return s;
}

void parse_units(std::string_view text, const SourceLocation& where, MeasurementFormat& format) {
  std::string list(text);
  std::replace(list.begin(), list.end(), ',', ' ');
  std::transform(list.begin(), list.end(), list.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  size_t start = 0;
  bool any = false;
  while ((start = list.find_first_not_of(' ', start)) != std::string::npos) {
    const size_t end = std::min(list.find(' ', start), list.size());
    const std::string unit = list.substr(start, end - start);
    start = end;
    any = true;
    if (unit == "mm" || unit == "m") {
      format.length = unit == "m" ? LengthUnit::Metre : LengthUnit::Millimetre;
    } else if (unit == "deg" || unit == "rad") {
      format.angle = unit == "rad" ? AngleUnit::Radian : AngleUnit::Degree;
    } else {
      throw InputError(where, fmt::format("unknown unit '{}': expected a length unit (mm or m) "
                                          "and/or an angle unit (deg or rad), e.g. 'm, rad'",
                                          unit));
    }
  }
  if (!any)
    throw InputError(where,
                     "no unit given: expected a length unit (mm or m) and/or an angle "
                     "unit (deg or rad), e.g. 'm, rad'");
}

EulerOrder parse_euler_order(std::string_view text, const SourceLocation& where) {
  std::string words(text);
  std::transform(words.begin(), words.end(), words.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  const std::string_view t = csv::trim(words);
  const size_t space = t.find(' ');
  const std::string_view kind = t.substr(0, space);
  const std::string_view axes = space == std::string_view::npos ? "" : csv::trim(t.substr(space));
  EulerOrder order;
  bool valid = (kind == "INTRINSIC" || kind == "EXTRINSIC") && axes.size() == 3;
  for (size_t k = 0; valid && k < 3; ++k) {
    const char a = axes[k];
    valid = a >= 'X' && a <= 'Z' && axes.find(a) == k;
    order.axes[k] = a - 'X';
  }
  if (!valid)
    throw InputError(where, fmt::format("'{}' is not a rotation order: expected 'intrinsic' or "
                                        "'extrinsic' and the three axes X, Y, Z in the order of "
                                        "the rotations, e.g. 'intrinsic ZYX'",
                                        csv::trim(text)));
  order.intrinsic = kind == "INTRINSIC";
  return order;
}

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
                                       const std::vector<MeasurementKind>& accepted,
                                       const MeasurementFormat& declared) {
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte-order mark
  MeasurementFormat format = declared;
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
    if (!content.empty() && content.front() == '#' && header_line == 0)
      read_declaration(content, {source_name, line_number, 0, ""}, format, declared);
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
  const std::optional<OrientationColumns> orientation =
      columns.count("target") ? std::nullopt
                              : find_orientation(columns, format.euler, source_name, header_line);
  set.kind = detect_kind(columns, orientation, source_name, header_line);
  const std::string kind_name(measurement_kind_name(set.kind));
  if (!accepted.empty() && std::find(accepted.begin(), accepted.end(), set.kind) == accepted.end())
    throw InputError({source_name, header_line, 0, ""},
                     fmt::format("this is a {} file (by its columns); this command takes {} files",
                                 kind_name, kinds_text(accepted)));

  const std::vector<std::string> required =
      orientation ? columns_of(set.kind, orientation->names) : columns_of(set.kind);
  for (const std::string& name : required)
    if (columns.count(name) == 0)
      throw InputError({source_name, header_line, 0, name},
                       fmt::format("missing column '{}': a {} file needs the columns {}", name,
                                   kind_name, join(required, ",")));
  const bool has_approach = columns.count("approach") > 0;
  for (size_t i = 0; i < header.size(); ++i) {
    const auto used = std::find_if(required.begin(), required.end(), [&](const std::string& r) {
      return columns.at(r) == static_cast<int>(i);
    });
    const auto optional = [&](const char* name) {
      return columns.count(name) > 0 && columns.at(name) == static_cast<int>(i);
    };
    if (used == required.end() && !optional("approach") && !optional("payload") &&
        !optional("temperature") && !optional("time_s"))
      result.warnings.push_back(
          fmt::format("{}:{}:{}: column '{}' is not used by a {} file; ignored", source_name,
                      header_line, i + 1, header[i], kind_name));
  }
  if (rows.empty())
    throw InputError({source_name, header_line, 0, ""},
                     "no measurement rows after the header: expected at least one row");

  const RowReader reader(source_name, columns, format.length == LengthUnit::Metre,
                         format.angle == AngleUnit::Radian);
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
        if (has_approach) m.approach = reader.approach(row);
        m.position_mm = reader.xyz(row);
        m.line = row.line;
        set.points.push_back(std::move(m));
        break;
      }
      case MeasurementKind::Poses: {
        PoseMeasurement m;
        m.config = config;
        m.joints = reader.joints_rad(row);
        if (has_approach) m.approach = reader.approach(row);
        if (orientation && !orientation->quaternion) {
          const std::vector<std::string>& n = orientation->names;
          m.world_T_tcp.R =
              rotation_from_axis_angles({reader.angle_rad(row, n[0]), reader.angle_rad(row, n[1]),
                                         reader.angle_rad(row, n[2])},
                                        orientation->order);
          m.world_T_tcp.p = reader.xyz(row);
          m.line = row.line;
          set.poses.push_back(std::move(m));
          break;
        }
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
        if (has_approach) m.approach = reader.approach(row);
        m.length_mm = reader.distance_mm(row, "length");
        m.line = row.line;
        set.distances.push_back(std::move(m));
        break;
      }
    }
    if (columns.count("payload")) set.set_payload(set.size() - 1, reader.payload(row, tool));
    if (columns.count("temperature"))
      set.set_temperature_c(set.size() - 1, reader.temperature_c(row));
    if (columns.count("time_s")) set.set_time_s(set.size() - 1, reader.time_s(row));
  }
  check_units(set, format, header_line, columns);
  return result;
}

MeasurementFile read_measurements_csv(const std::string& path, const Tool& tool,
                                      const std::vector<MeasurementKind>& accepted,
                                      const MeasurementFormat& format) {
  return parse_measurements_csv(read_text_file(path), path, tool, accepted, format);
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
  // The approach column only when some row was not approached from below on every joint: files
  // of the measurement programs' practice stay as they were.
  bool approach = false;
  for (size_t row = 0; row < set.size(); ++row)
    approach = approach || approach_of(set, row) != Vector6d::Ones();
  const auto sides = [&](const Vector6d& s) {
    return approach ? "," + approach_text(s) : std::string();
  };
  bool temperatures = false;  // written when a row recorded one; empty for a row without
  for (size_t row = 0; row < set.size(); ++row)
    temperatures = temperatures || set.temperature_c(row).has_value();
  const auto temperature = [&](const std::optional<double>& t) {
    return !temperatures ? std::string() : t ? fmt::format(",{}", *t) : std::string(",");
  };
  bool times = false;  // likewise the time
  for (size_t row = 0; row < set.size(); ++row) times = times || set.time_s(row).has_value();
  const auto time = [&](const std::optional<double>& t) {
    return !times ? std::string() : t ? fmt::format(",{}", *t) : std::string(",");
  };
  bool payloads = false;  // an optional last column, written when a row names one
  for (size_t row = 0; row < set.size(); ++row) payloads = payloads || set.payload(row) >= 0;
  out += join(columns_of(set.kind), ",") + (approach ? ",approach" : "") +
         (temperatures ? ",temperature" : "") + (times ? ",time_s" : "") +
         (payloads ? ",payload\n" : "\n");
  const auto payload = [&](int index) -> std::string {
    if (!payloads) return "\n";
    if (index >= static_cast<int>(tool.payloads.size()))
      throw InputError({"", 0, 0, "payload"},
                       fmt::format("payload index {} is not a payload of the tool ({} payloads)",
                                   index, tool.payloads.size()));
    return "," + (index < 0 ? std::string() : tool.payloads[static_cast<size_t>(index)].name) +
           "\n";
  };

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
        out += fmt::format("{},{},{},{},{},{}{}", config(m.config), target(m.target),
                           joints(m.joints), m.position_mm.x(), m.position_mm.y(),
                           m.position_mm.z(), sides(m.approach)) +
               temperature(m.temperature_c) + time(m.time_s) + payload(m.payload);
      break;
    case MeasurementKind::Poses:
      for (const PoseMeasurement& m : set.poses) {
        Eigen::Quaterniond q(m.world_T_tcp.R);
        if (q.w() < 0) q.coeffs() = -q.coeffs();
        out += fmt::format("{},{},{},{},{},{},{},{},{}{}", config(m.config), joints(m.joints),
                           m.world_T_tcp.p.x(), m.world_T_tcp.p.y(), m.world_T_tcp.p.z(), q.w(),
                           q.x(), q.y(), q.z(), sides(m.approach)) +
               temperature(m.temperature_c) + time(m.time_s) + payload(m.payload);
      }
      break;
    case MeasurementKind::Distances:
      for (const DistanceMeasurement& m : set.distances)
        out += fmt::format("{},{},{},{}{}", config(m.config), target(m.target), joints(m.joints),
                           m.length_mm, sides(m.approach)) +
               temperature(m.temperature_c) + time(m.time_s) + payload(m.payload);
      break;
  }
  return out;
}

}  // namespace robcal
