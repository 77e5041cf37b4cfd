#include "flag_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "robcal/io/number_text.hpp"

namespace robcal::cli {
namespace {

// Flags whose negative values mean nothing: a negative σ or scale is a slip. (--floor-mm may be
// negative: a robot on a pedestal.)
constexpr std::array<std::string_view, 10> kNonNegativeFlags{
    "--error-angle-deg",    "--noise-mm",        "--huber-scale", "--error-length-mm", "--sigma-um",
    "--orientation-weight", "--payload-mass-kg", "--angle-deg",   "--distance-mm",     "--sigma"};
// Counts (of configurations, runs, samples, …): whole numbers from 0 to a bound that keeps what
// they size in memory. --candidates has its own, larger, bound in the library.
constexpr std::array<std::string_view, 11> kCountFlags{
    "--random", "--runs",   "--samples", "--count",      "--task-count", "--seeds",
    "--kfold",  "--points", "--poses",   "--validation", "--threads"};
constexpr long kMaxCount = 1'000'000;

/// "" when `text` is a seed (a 64-bit unsigned number), else what is wrong (CLI11 prints it with
/// the flag).
std::string check_seed(const std::string& text) {
  const bool digits = !text.empty() && text.size() <= 20 &&
                      text.find_first_not_of("0123456789") == std::string::npos;
  if (digits && (text.size() < 20 || text <= "18446744073709551615")) return {};
  return fmt::format("seed '{}': expected a whole number 0 .. 18446744073709551615", text);
}

/// "" when `text` is a count 0 .. kMaxCount, else what is wrong (CLI11 prints it with the flag).
std::string check_count(const std::string& text) {
  const std::optional<int64_t> v = parse_integer(text);
  if (!v || *v < 0 || *v > kMaxCount)
    return fmt::format("'{}': expected a whole number 0 .. {}", text, kMaxCount);
  return {};
}

/// "" when `text` is a whole number that fits an int (at least `min`), else what is wrong:
/// CLI11's own "Could not convert: --best = abc" names neither the value nor what was expected.
std::string check_whole_number(const std::string& text, int64_t min) {
  const std::optional<int64_t> v = parse_integer(text);
  if (v && *v >= min && *v <= std::numeric_limits<int>::max()) return {};
  if (min == 0) return fmt::format("'{}': expected a whole number >= 0", text);
  return fmt::format("'{}': expected a whole number", text);
}

/// "" when `text` is a number >= 0, else what is wrong (CLI11 prints it with the flag).
std::string check_non_negative(const std::string& text) {
  const std::optional<double> v = parse_number(text);
  if (!v) return describe_bad_number(text);
  if (*v < 0) return fmt::format("'{}' is negative: expected a value >= 0", text);
  return {};
}

/// "" when `text` is a finite number, else what is wrong: CLI11 reads "nan" and "inf" as numbers.
std::string check_finite(const std::string& text) {
  return parse_number(text) ? std::string() : describe_bad_number(text);
}

void check_flags_of(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    const std::string name = option->get_name(false, true);
    const auto is = [&](const auto& list) {
      return std::find(list.begin(), list.end(), name) != list.end();
    };
    if (name == "--seed")
      option->check(CLI::Validator(check_seed, "SEED"));
    else if (is(kCountFlags) && option->get_type_name().rfind("INT", 0) == 0)
      option->check(CLI::Validator(check_count, "COUNT"));
    else if (name == "--candidates")
      option->check(CLI::Validator([](const std::string& t) { return check_whole_number(t, 0); },
                                   "NON-NEGATIVE"));
    else if (is(kNonNegativeFlags) && option->get_expected_max() == 1)
      option->check(CLI::Validator(check_non_negative, "NON-NEGATIVE"));
    else if (option->get_type_name().rfind("INT", 0) == 0)
      option->check(CLI::Validator(
          [](const std::string& t) {
            return check_whole_number(t, std::numeric_limits<int>::min());
          },
          ""));
    else if (option->get_type_name().rfind("FLOAT", 0) == 0)
      option->check(CLI::Validator(check_finite, ""));
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) check_flags_of(*sub);
}

}  // namespace

void add_flag_checks(CLI::App& app) {
  check_flags_of(app);
}

}  // namespace robcal::cli
