#pragma once
// JSON text of the hexapod files (plan, journal lines) parsed with located refusals.

#include <nlohmann/json.hpp>

#include <string>

namespace robcal::hexapod {

/// Parses JSON text (a whole file, or one journal line numbered `line`); InputError at the line
/// and column of a syntax error, and at the number for one beyond the double range (the parser
/// reports those without a place). `expected` says what the text should have been.
nlohmann::json parse_json(const std::string& text, const std::string& file, int line,
                          const char* expected);

}  // namespace robcal::hexapod
