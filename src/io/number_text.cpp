#include "robcal/io/number_text.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

namespace robcal {
namespace {

/// `text` without one leading '+' (from_chars takes only '-'); empty when the rest is signed
/// again ("+-1", "++1").
std::string_view unplus(std::string_view text) {
  if (!text.empty() && text[0] == '+') {
    text.remove_prefix(1);
    if (!text.empty() && (text[0] == '+' || text[0] == '-')) return {};
  }
  return text;
}

/// True when `text` is made of characters a decimal number may have: from_chars would
/// also read "inf", "nan" and "infinity", which no file of ours means.
bool decimal_characters(std::string_view text) {
  for (const char c : text)
    if (!((c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '-' || c == '+'))
      return false;
  return true;
}

}  // namespace

std::optional<double> parse_number(std::string_view text) {
  text = unplus(text);
  if (text.empty() || !decimal_characters(text)) return std::nullopt;
  double value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
    return std::nullopt;
  return value;
}

std::optional<int64_t> parse_integer(std::string_view text) {
  text = unplus(text);
  if (text.empty()) return std::nullopt;
  int64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

std::string describe_bad_number(std::string_view text) {
  const std::string_view bare = unplus(text);
  double value = 0;
  if (!bare.empty() && decimal_characters(bare)) {
    const auto [end, ec] = std::from_chars(bare.data(), bare.data() + bare.size(), value);
    if (ec == std::errc::result_out_of_range && end == bare.data() + bare.size())
      return fmt::format("'{}' is outside the range of double-precision numbers", text);
  }
  return fmt::format("expected a number, found '{}'", text);
}

}  // namespace robcal
