#include "robcal/io/ur_calibration_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>

#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/number_text.hpp"

namespace robcal {
namespace {

constexpr const char* kDeltaKeys[4] = {"delta_theta", "delta_a", "delta_d", "delta_alpha"};
/// Metres in the file, mm inside; radians both.
constexpr double kMetre = 1000.0;
constexpr double kMmPerUrUnit[4] = {1.0, kMetre, kMetre, 1.0};

std::string_view trim(std::string_view s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

/// `[ v1, …, v6 ]`: the text after the `=` at `where` (its column is the text's first).
std::array<double, kJointCount> six_numbers(std::string_view value, const SourceLocation& where) {
  auto fail = [&](int column, const std::string& what) {
    SourceLocation at = where;
    at.column = column;
    throw InputError(at, what);
  };
  const std::string_view body = trim(value);
  if (body.size() < 2 || body.front() != '[' || body.back() != ']')
    fail(where.column, fmt::format("expected [ six numbers ], found '{}'", body));
  std::array<double, kJointCount> out{};
  int count = 0;
  size_t start = value.find('[') + 1;
  const size_t end = value.rfind(']');
  while (start <= end) {
    size_t comma = value.find(',', start);
    if (comma == std::string_view::npos || comma > end) comma = end;
    const std::string_view item = trim(value.substr(start, comma - start));
    const size_t first = value.find_first_not_of(" \t", start);
    const int column = where.column + static_cast<int>(std::min(first, comma));
    if (count == kJointCount) fail(column, "more than six numbers (one per joint)");
    const std::optional<double> x = parse_number(item);
    if (!x) fail(column, describe_bad_number(item));
    out[static_cast<size_t>(count++)] = *x;
    start = comma + 1;
  }
  if (count != kJointCount)
    fail(where.column, fmt::format("expected six numbers (one per joint), found {}", count));
  return out;
}

/// DH table of UR's standard convention (see the header): theta, a, d, alpha (rad, mm).
struct DhTable {
  std::array<std::array<double, kJointCount>, 4> rows{};
};

/// The four delta rows in kDeltaKeys order.
template <typename Calibration>
auto rows_of(Calibration& c) {
  return std::array{&c.delta_theta, &c.delta_a, &c.delta_d, &c.delta_alpha};
}

void require_identity_map(const RobotModel& model) {
  if (!model.joint_map.is_identity())
    throw InputError(SourceLocation{"", 0, 0, "--robot"},
                     fmt::format("{}: calibration.conf angles are the controller's joint values "
                                 "plus delta_theta, so the robot's joint map must be the identity "
                                 "(a Universal Robots robot file)",
                                 model.name));
}

/// The standard-DH table of `params` (link 1 from the base's z and gamma, a6 = α6 = 0).
DhTable dh_of(const RobotModel& model, const ParameterVector& p) {
  DhTable t;
  auto& [theta, a, d, alpha] = t.rows;
  theta[0] = model.mdh[0].theta_offset + p[5];
  d[0] = model.mdh[0].d + p[2];
  for (int link = 2; link <= kJointCount; ++link) {
    alpha[link - 2] = p[link_param(link, 0)];
    a[link - 2] = p[link_param(link, 1)];
    theta[link - 1] = p[link_param(link, 2)];
    d[link - 1] = p[link_param(link, 3)];
  }
  return t;
}

}  // namespace

UrCalibration parse_ur_calibration(const std::string& text, const std::string& path) {
  UrCalibration out;
  out.file = path;
  std::array<bool, 4> seen{};
  bool in_mounting = false, any_mounting = false;
  std::istringstream in(text);
  std::string raw;
  for (int number = 1; std::getline(in, raw); ++number) {
    const std::string_view line = std::string_view(raw).substr(0, raw.find('#'));
    const std::string_view t = trim(line);
    if (t.empty()) continue;
    if (t.front() == '[') {
      if (t.back() != ']')
        throw InputError(SourceLocation{path, number, 1, ""},
                         fmt::format("expected a section header [name], found '{}'", t));
      in_mounting = trim(t.substr(1, t.size() - 2)) == "mounting";
      any_mounting = any_mounting || in_mounting;
      continue;
    }
    const size_t eq = line.find('=');
    if (eq == std::string_view::npos)
      throw InputError(SourceLocation{path, number, 1, ""},
                       fmt::format("expected 'key = value', found '{}'", t));
    if (!in_mounting) continue;
    const std::string key(trim(line.substr(0, eq)));
    const SourceLocation where{path, number, static_cast<int>(eq) + 2, key};
    if (key == "calibration_status") {
      const auto v = parse_integer(trim(line.substr(eq + 1)));
      if (!v || *v < 0 || *v > 2)
        throw InputError(where,
                         fmt::format("expected 0, 1 or 2, found '{}'", trim(line.substr(eq + 1))));
      out.calibration_status = static_cast<int>(*v);
      continue;
    }
    for (int k = 0; k < 4; ++k) {
      if (key != kDeltaKeys[k]) continue;
      if (seen[static_cast<size_t>(k)])
        throw InputError(where, fmt::format("{} given twice in [mounting]", key));
      seen[static_cast<size_t>(k)] = true;
      std::array<double, kJointCount> v = six_numbers(line.substr(eq + 1), where);
      for (double& x : v) x *= kMmPerUrUnit[k];
      *rows_of(out)[static_cast<size_t>(k)] = v;
    }
  }
  if (!any_mounting)
    throw InputError(SourceLocation{path, 0, 0, "[mounting]"},
                     "no [mounting] section: not a Universal Robots calibration.conf");
  for (int k = 0; k < 4; ++k)
    if (!seen[static_cast<size_t>(k)])
      throw InputError(
          SourceLocation{path, 0, 0, kDeltaKeys[k]},
          fmt::format("[mounting] has no {} (six numbers, one per joint)", kDeltaKeys[k]));
  return out;
}

UrCalibration load_ur_calibration(const std::string& path) {
  return parse_ur_calibration(read_text_file(path), path);
}

std::string ur_calibration_text(const UrCalibration& c) {
  std::string out =
      "# Universal Robots calibration.conf deltas written by robcal: nominal standard DH + delta,\n"
      "# metres and radians. joint_checksum, calibration_status and the other hardware lines are\n"
      "# not written: they identify the robot's joint modules (copy them from its own file).\n"
      "[mounting]\n";
  const auto rows = rows_of(c);
  for (int k = 0; k < 4; ++k) {
    std::vector<std::string> v;
    for (double x : *rows[static_cast<size_t>(k)])
      v.push_back(fmt::format("{:.17g}", x / kMmPerUrUnit[k]));
    out += fmt::format("{} = [ {}]\n", kDeltaKeys[k], fmt::join(v, ", "));
  }
  return out;
}

ParameterVector params_from_ur_calibration(const RobotModel& model, const UrCalibration& c) {
  require_identity_map(model);
  for (const auto& [value, key] :
       {std::pair{c.delta_a[5], "delta_a"}, std::pair{c.delta_alpha[5], "delta_alpha"}})
    if (value != 0)
      throw InputError(SourceLocation{c.file, 0, 0, key},
                       fmt::format("the sixth {} is {:g}, not 0: robcal's flange is DH frame 6 "
                                   "(UR's own files have 0 there)",
                                   key, value));
  DhTable t = dh_of(model, model.nominal());
  const auto deltas = rows_of(c);
  for (size_t k = 0; k < 4; ++k)
    for (size_t i = 0; i < kJointCount; ++i) t.rows[k][i] += (*deltas[k])[i];
  ParameterVector p = model.nominal();
  const auto& [theta, a, d, alpha] = t.rows;
  p[2] = d[0] - model.mdh[0].d;
  p[5] = theta[0] - model.mdh[0].theta_offset;
  for (int link = 2; link <= kJointCount; ++link) {
    const auto i = static_cast<size_t>(link - 2), j = static_cast<size_t>(link - 1);
    p[link_param(link, 0)] = alpha[i];
    p[link_param(link, 1)] = a[i];
    p[link_param(link, 2)] = theta[j];
    p[link_param(link, 3)] = d[j];
  }
  return p;
}

UrCalibration ur_calibration_from_params(const RobotModel& model, const ParameterVector& params) {
  require_identity_map(model);
  const DhTable n = dh_of(model, model.nominal()), v = dh_of(model, params);
  UrCalibration c;
  const auto deltas = rows_of(c);
  for (size_t k = 0; k < 4; ++k)
    for (size_t i = 0; i < kJointCount; ++i) (*deltas[k])[i] = v.rows[k][i] - n.rows[k][i];
  return c;
}

}  // namespace robcal
