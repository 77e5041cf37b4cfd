#pragma once
/// \file
/// The hexapod session's answer lines, the one format both sides use: what the operator types
/// (or a file piped to `robcal hexapod session` holds, e.g. `simulate-readings`' output), one
/// answer a line: a reading in mm, "out" (or "x": the ballbar does not fit), or "quit" ("q").

#include <optional>
#include <string>

namespace robcal::hexapod {

struct SessionAnswer {
  enum class Kind { Reading, Out, Quit, Invalid };
  Kind kind = Kind::Invalid;
  double reading_mm = 0;  ///< for Kind::Reading, finite
};

/// Reads one answer line (surrounding blanks ignored); Invalid for anything else, a number with
/// trailing text or a non-finite number included.
SessionAnswer parse_session_answer(const std::string& line);

/// The line that answers with `reading` ("out" for nullopt), without its newline; read back
/// exactly by parse_session_answer.
std::string session_answer_text(const std::optional<double>& reading);

}  // namespace robcal::hexapod
