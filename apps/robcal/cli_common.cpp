#include "cli_common.hpp"

#include <unistd.h>

#include <fmt/format.h>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include "robcal/core/error.hpp"
#include "robcal/core/rounding.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/number_text.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::cli {

std::vector<double> parse_numbers(const std::string& text, int count, const std::string& what) {
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  int column = 0;
  while (std::getline(ss, item, ',')) {
    ++column;
    const auto first = item.find_first_not_of(" \t");
    const auto last = item.find_last_not_of(" \t");
    const std::string trimmed =
        first == std::string::npos ? "" : item.substr(first, last - first + 1);
    const std::optional<double> v = parse_number(trimmed);
    if (!v)
      throw InputError({"", 0, 0, what},
                       fmt::format("value {} is '{}', expected a finite number", column, trimmed));
    values.push_back(*v);
  }
  if (count >= 0 && static_cast<int>(values.size()) != count)
    throw InputError({"", 0, 0, what}, fmt::format("expected {} comma-separated values, got {}",
                                                   count, values.size()));
  return values;
}

Vector6d parse_joints_deg(const std::string& text, const std::string& what) {
  const auto values = parse_numbers(text, kJointCount, what);
  Vector6d q;
  for (int i = 0; i < kJointCount; ++i) q[i] = deg2rad(values[i]);
  return q;
}

Eigen::Matrix3d parse_orientation(const std::string& text, const std::string& what) {
  const std::vector<double> q = parse_numbers(text, 4, what);
  try {
    return pose_from_position_quaternion(Eigen::Vector3d::Zero(),
                                         Eigen::Vector4d(q[0], q[1], q[2], q[3]))
        .R;
  } catch (const InputError& e) {
    throw InputError({"", 0, 0, what}, e.what());
  }
}

ArmConfig parse_config(const std::string& text, const std::string& what) {
  const std::optional<ArmConfig> config = parse_arm_config(text);
  if (!config)
    throw InputError(
        {"", 0, 0, what},
        fmt::format("expected a configuration such as front-up-noflip, found '{}'", text));
  return *config;
}

void print_json(const nlohmann::json& value) {
  std::cout << value.dump(2) << std::endl;
}

bool stdout_is_terminal() {
  return ::isatty(STDOUT_FILENO) != 0;
}

double tidy(double value, int decimals) {
  return rounded(value, decimals);
}

}  // namespace robcal::cli
