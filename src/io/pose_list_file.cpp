#include "robcal/io/pose_list_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string_view>

#include "csv_fields.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/number_text.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal {
namespace {

constexpr double kMaxPoseCoordinateMm = 20000;

std::optional<ArmConfig> parse_config_cell(const std::string& cell) {
  if (cell.size() == 1 && cell[0] >= '0' && cell[0] <= '7') {
    const int index = cell[0] - '0';
    return ArmConfig{(index & 4) != 0, (index & 2) != 0, (index & 1) != 0};
  }
  return parse_arm_config(cell);
}

}  // namespace

std::vector<ListedPose> read_pose_list(const std::string& path) {
  return parse_pose_list(read_text_file(path), path);
}

std::vector<ListedPose> parse_pose_list(const std::string& text, const std::string& file) {
  static const char* const kColumns[] = {"name", "x", "y", "z", "qw", "qx", "qy", "qz"};
  static const char* const kOptional[] = {"config", "approach", "temperature", "time_s", "payload"};
  std::vector<ListedPose> out;
  std::istringstream in{std::string(csv::without_bom(text))};
  std::string line;
  int number = 0;
  bool header = false;
  std::vector<std::string> optional;      // the header's optional columns, in its order
  std::map<std::string, int> first_line;  // pose name → its line
  while (std::getline(in, line)) {
    ++number;
    if (csv::trim(line).empty() || csv::trim(line)[0] == '#') continue;
    std::vector<int> columns;  // 1-based character column of each cell
    const std::vector<std::string_view> fields = csv::split_fields(line, &columns);
    std::vector<std::pair<std::string, int>> cells;
    for (size_t k = 0; k < fields.size(); ++k) cells.emplace_back(fields[k], columns[k]);
    if (!header) {
      for (int k = 0; k < 8; ++k)
        if (static_cast<int>(cells.size()) <= k || cells[k].first != kColumns[k])
          throw InputError(
              SourceLocation{file, number, k < static_cast<int>(cells.size()) ? cells[k].second : 0,
                             ""},
              fmt::format("expected the header name,x,y,z,qw,qx,qy,qz[,config]; column "
                          "{} should be '{}'",
                          k + 1, kColumns[k]));
      for (size_t k = 8; k < cells.size(); ++k) {
        const std::string& name = cells[k].first;
        // time_s after the list: its words are older than the column (catalogued messages).
        if (std::find(std::begin(kOptional), std::end(kOptional), name) == std::end(kOptional))
          throw InputError(SourceLocation{file, number, cells[k].second, ""},
                           fmt::format("unexpected column after the header's pose columns: "
                                       "expected config, approach, temperature or payload, "
                                       "found '{}' (or time_s, the warm-up time)",
                                       name));
        if (std::find(optional.begin(), optional.end(), name) != optional.end())
          throw InputError(SourceLocation{file, number, cells[k].second, name},
                           fmt::format("column '{}' appears twice in the header", name));
        optional.push_back(name);
      }
      header = true;
      continue;
    }
    // Trailing optional cells may be left out: the run's defaults.
    const size_t expected = 8 + optional.size();
    if (cells.size() < 8 || cells.size() > expected)
      throw InputError(SourceLocation{file, number, 0, ""},
                       fmt::format("expected {} cells, found {}", expected, cells.size()));
    ListedPose t;
    t.line = number;
    t.name = cells[0].first;
    if (t.name.empty()) throw InputError(SourceLocation{file, number, 1, "name"}, "empty name");
    const auto [previous, fresh] = first_line.emplace(t.name, number);
    if (!fresh)
      throw InputError(
          SourceLocation{file, number, 1, "name"},
          fmt::format("pose '{}' is listed twice (first on line {})", t.name, previous->second));
    double v[7];
    for (int k = 0; k < 7; ++k) {
      const std::string& cell = cells[k + 1].first;
      const SourceLocation where{file, number, cells[k + 1].second, kColumns[k + 1]};
      const std::optional<double> value = parse_number(cell);
      if (!value) throw InputError(where, describe_bad_number(cell));
      // Positions: a robot cell is metres across, not kilometres (a unit slip or a typo).
      if (k < 3 && std::abs(*value) > kMaxPoseCoordinateMm)
        throw InputError(where, fmt::format("{} mm is outside the plausible range [-{}, {}] mm",
                                            cell, kMaxPoseCoordinateMm, kMaxPoseCoordinateMm));
      v[k] = *value;
    }
    try {
      t.world_T_tcp = pose_from_position_quaternion(Eigen::Vector3d(v[0], v[1], v[2]),
                                                    Eigen::Vector4d(v[3], v[4], v[5], v[6]));
    } catch (const InputError& e) {
      throw InputError(SourceLocation{file, number, cells[4].second, "qw..qz"}, e.what());
    }
    for (size_t k = 8; k < cells.size(); ++k) {
      const auto& [cell, column] = cells[k];
      const std::string& key = optional[k - 8];
      const SourceLocation where{file, number, column, key};
      if (cell.empty()) continue;
      if (key == "config") {
        t.config = parse_config_cell(cell);
        if (!t.config)
          throw InputError(where, fmt::format("expected a configuration such as "
                                              "front-up-noflip or its index 0..7, found '{}'",
                                              cell));
      } else if (key == "approach") {
        t.approach = parse_approach(cell, where);
      } else if (key == "temperature") {
        t.temperature_c = parse_temperature_c(cell, where);
      } else if (key == "time_s") {
        t.time_s = cell == kWarmCell ? kFullyWarmS : parse_time_s(cell, where);
      } else {
        t.payload = cell;
        t.payload_column = column;
      }
    }
    out.push_back(std::move(t));
  }
  if (!header)
    throw InputError(SourceLocation{file, 0, 0, ""}, "no header row name,x,y,z,qw,qx,qy,qz");
  if (out.empty()) throw InputError(SourceLocation{file, 0, 0, ""}, "no poses");
  return out;
}

}  // namespace robcal
