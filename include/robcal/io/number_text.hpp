#pragma once
/// \file
/// The one reader of numbers written as text, shared by the CSV and YAML readers and the CLI:
/// the whole text must be one finite decimal number ("364.35.4", "1e999", "nan", "0x10" and
/// "12mm" are refused, never read as a prefix, zero or infinity).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace robcal {

/// The finite number spelled by all of `text` (an optional sign, digits, point, exponent),
/// else nullopt.
std::optional<double> parse_number(std::string_view text);

/// The integer spelled by all of `text` (optional sign, digits only), else nullopt (also when
/// it does not fit in 64 bits).
std::optional<int64_t> parse_integer(std::string_view text);

/// What a reader says about a refused number: "expected a number, found '…'", or that it is
/// outside the double range.
std::string describe_bad_number(std::string_view text);

}  // namespace robcal
