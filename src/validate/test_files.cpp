// Reading the measurements of the ISO 9283 test (format in validate/iso9283.hpp) and of the
// axis test (validate/axis_test.hpp): one reader per format, sharing the cell parsers.

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "../io/csv_fields.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/pose_list_file.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/validate/axis_test.hpp"
#include "robcal/validate/iso9283.hpp"

namespace robcal {
namespace {

double number_cell(std::string_view cell, const SourceLocation& where) {
  double v = 0;
  const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (ec != std::errc() || ptr != cell.data() + cell.size() || !std::isfinite(v))
    throw InputError(where, fmt::format("expected a number, found '{}'", cell));
  return v;
}

int integer_cell(std::string_view cell, const SourceLocation& where, int lowest) {
  int v = 0;
  const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (ec != std::errc() || ptr != cell.data() + cell.size() || v < lowest)
    throw InputError(where, fmt::format("expected a whole number ≥ {}, found '{}'", lowest, cell));
  return v;
}

}  // namespace

std::vector<Iso9283Sample> read_iso9283_samples(const std::string& path) {
  return parse_iso9283_samples(read_text_file(path), path);
}

std::vector<Iso9283Sample> parse_iso9283_samples(const std::string& text, const std::string& file) {
  static const std::vector<std::string> kPosition = {"pose", "cycle", "x", "y", "z"};
  static const std::vector<std::string> kOrientation = {"qw", "qx", "qy", "qz"};
  std::vector<std::string> columns;
  std::vector<Iso9283Sample> out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (csv::trim(line).empty() || csv::trim(line)[0] == '#') continue;
    std::vector<int> at;
    const std::vector<std::string_view> cells = csv::split_fields(line, &at);
    if (columns.empty()) {
      columns.assign(cells.begin(), cells.end());
      std::vector<std::string> expected = kPosition;
      if (columns.size() >= 9)
        expected.insert(expected.end(), kOrientation.begin(), kOrientation.end());
      if (columns.size() == expected.size() + 1) expected.emplace_back("direction");
      if (columns != expected)
        throw InputError({file, number, 1, ""},
                         "expected the header pose,cycle,x,y,z or pose,cycle,x,y,z,qw,qx,qy,qz, "
                         "either optionally followed by direction");
      continue;
    }
    if (cells.size() != columns.size())
      throw InputError({file, number, 0, ""},
                       fmt::format("expected {} cells, found {}", columns.size(), cells.size()));
    const auto where = [&](size_t k) { return SourceLocation{file, number, at[k], columns[k]}; };
    Iso9283Sample s;
    s.line = number;
    std::string_view pose = cells[0];
    if (!pose.empty() && (pose[0] == 'P' || pose[0] == 'p')) pose.remove_prefix(1);
    s.pose = integer_cell(pose, where(0), 1);
    if (s.pose > 5)
      throw InputError(where(0), fmt::format("expected P1..P5, found '{}'", cells[0]));
    s.cycle = integer_cell(cells[1], where(1), 1);
    for (int k = 0; k < 3; ++k) s.position_mm[k] = number_cell(cells[2 + k], where(2 + k));
    size_t next = 5;
    if (columns.size() >= 9) {
      Eigen::Vector4d q;
      for (int k = 0; k < 4; ++k) q[k] = number_cell(cells[5 + k], where(5 + k));
      try {
        s.world_R_tcp = pose_from_position_quaternion(s.position_mm, q).R;
      } catch (const InputError& e) {
        throw InputError(where(5), e.what());
      }
      next = 9;
    }
    if (columns.size() > next) {
      s.direction = integer_cell(cells[next], where(next), 0);
      if (s.direction > 3)
        throw InputError(where(next), fmt::format("expected 0..3, found '{}'", cells[next]));
    }
    out.push_back(s);
  }
  if (columns.empty()) throw InputError({file, 0, 0, ""}, "empty file: no header");
  if (out.empty()) throw InputError({file, 0, 0, ""}, "no measured cycles");
  return out;
}

Iso9283AnalysisRequest read_iso9283_request(const std::string& poses_path,
                                            const std::string& measurements_path, int min_cycles) {
  Iso9283AnalysisRequest request;
  request.file = measurements_path;
  const std::vector<ListedPose> listed = read_pose_list(poses_path);
  for (int k = 1; k <= 5; ++k) {
    const std::string name = fmt::format("P{}", k);
    const auto it = std::find_if(listed.begin(), listed.end(),
                                 [&](const ListedPose& p) { return p.name == name; });
    if (it == listed.end())
      throw InputError({poses_path, 0, 0, "name"}, fmt::format("no pose named {}", name));
    request.commanded.push_back(it->world_T_tcp);
  }
  request.samples = read_iso9283_samples(measurements_path);
  request.min_cycles = min_cycles;
  return request;
}

std::vector<AxisTestSample> read_axis_test_samples(const std::string& path) {
  return parse_axis_test_samples(read_text_file(path), path);
}

std::vector<AxisTestSample> parse_axis_test_samples(const std::string& text,
                                                    const std::string& file) {
  static const std::vector<std::string> kColumns = {"joint_deg", "side", "x", "y", "z"};
  std::istringstream in(text);
  std::string line;
  int number = 0;
  bool header = false;
  std::vector<AxisTestSample> out;
  while (std::getline(in, line)) {
    ++number;
    if (csv::trim(line).empty() || csv::trim(line)[0] == '#') continue;
    std::vector<int> at;
    const std::vector<std::string_view> cells = csv::split_fields(line, &at);
    if (!header) {
      if (std::vector<std::string>(cells.begin(), cells.end()) != kColumns)
        throw InputError({file, number, 1, ""}, "expected the header joint_deg,side,x,y,z");
      header = true;
      continue;
    }
    if (cells.size() != kColumns.size())
      throw InputError({file, number, 0, ""},
                       fmt::format("expected 5 cells, found {}", cells.size()));
    const auto where = [&](size_t k) { return SourceLocation{file, number, at[k], kColumns[k]}; };
    if (cells[1] != "below" && cells[1] != "above")
      throw InputError(where(1), fmt::format("expected below or above, found '{}'", cells[1]));
    AxisTestSample s;
    s.joint_rad = deg2rad(number_cell(cells[0], where(0)));
    s.from_above = cells[1] == "above";
    for (int k = 0; k < 3; ++k) s.position_mm[k] = number_cell(cells[2 + k], where(2 + k));
    out.push_back(s);
  }
  if (!header) throw InputError({file, 0, 0, ""}, "empty file: no header");
  return out;
}

}  // namespace robcal
