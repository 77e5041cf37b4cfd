#include "cli_common.hpp"

#include <unistd.h>

#include <fmt/format.h>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <sstream>
#include <streambuf>

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

namespace {
/// std::cout's buffer once standard output is reserved for the data: writes straight to the
/// saved descriptor (write_file_atomically("-") writes through std::cout).
class DescriptorBuffer final : public std::streambuf {
 public:
  explicit DescriptorBuffer(int fd) : fd_(fd) {}

 protected:
  std::streamsize xsputn(const char* data, std::streamsize size) override {
    std::streamsize done = 0;
    while (done < size) {
      const ssize_t n = ::write(fd_, data + done, static_cast<size_t>(size - done));
      if (n <= 0) break;
      done += n;
    }
    return done;
  }
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
  }

 private:
  int fd_;
};
}  // namespace

void reserve_stdout_for_data() {
  std::fflush(stdout);
  std::cout.flush();
  const int data = ::dup(STDOUT_FILENO);
  if (data < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0)
    throw std::runtime_error("cannot separate the data on standard output from the report");
  static DescriptorBuffer buffer(data);
  std::cout.rdbuf(&buffer);
}

void print_json(const nlohmann::json& value) {
  // Through C stdio, as every other printout: with --out - it then goes to standard error. A
  // path that is not UTF-8 (any bytes are a Linux file name) is printed with U+FFFD in place of
  // its stray bytes, not refused by the JSON writer.
  fmt::print("{}\n", value.dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
}

bool stdout_is_terminal() {
  return ::isatty(STDOUT_FILENO) != 0;
}

double tidy(double value, int decimals) {
  return rounded(value, decimals);
}

}  // namespace robcal::cli
