#include "robcal/hexapod/session_answers.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace robcal::hexapod {

SessionAnswer parse_session_answer(const std::string& line) {
  const auto first = line.find_first_not_of(" \t\r");
  if (first == std::string::npos) return {};
  const std::string text = line.substr(first, line.find_last_not_of(" \t\r") - first + 1);
  if (text == "out" || text == "x") return {SessionAnswer::Kind::Out};
  if (text == "quit" || text == "q") return {SessionAnswer::Kind::Quit};
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return {SessionAnswer::Kind::Reading, v};
  } catch (const std::exception&) {  // std::stod: not a number, or out of double's range
  }
  return {};
}

std::string session_answer_text(const std::optional<double>& reading) {
  return reading ? fmt::format("{}", *reading) : std::string("out");
}

}  // namespace robcal::hexapod
