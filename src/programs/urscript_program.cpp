// Universal Robots URScript (.script): measurement programs and their joint moves read back.
//
// Grammar constraints relied on: a program is one `def name():` ... `end` block (names are
// identifiers; indentation is not significant); joint positions are lists of six floats in
// radians, `movej([q1, ..., q6], a=rad/s², v=rad/s)`, which stops at the target (r = 0:
// no blend, a fine point); `#` comments run to the end of the line; textmsg(s1, s2) writes
// to the controller's log. Floats are doubles: 10 decimals of a radian keep 1e-6° exactly.

#include <fmt/format.h>

#include <cctype>
#include <numbers>

#include "measurement_writers.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal::detail {

std::string write_urscript_measurement(const MeasurementPart& part) {
  const MeasurementProgramRequest& r = part.request;
  // The slowest joints of the UR arms reach π rad/s: the percentage is of that.
  const double v = r.joint_speed_percent / 100.0 * std::numbers::pi;
  const auto movej = [&](const Vector6d& q_deg) {
    const Vector6d q = q_deg * kDegToRad;
    return fmt::format(
        "  movej([{:.10f}, {:.10f}, {:.10f}, {:.10f}, {:.10f}, {:.10f}], a=1.0, v={:.4f})\n", q[0],
        q[1], q[2], q[3], q[4], q[5], v);
  };
  std::string out = fmt::format("def {}():\n", part.program) +
                    header_comment(part, "  #", "reached without blending");
  for (const Visit& visit : part.visits) {
    const Vector6d& q = visit.target_deg;
    out += fmt::format("  # {}\n", visit.name) + movej(visit.approach_deg) + movej(q) +
           fmt::format("  sleep({:.2f})\n", r.settle_s);
    switch (r.hook) {
      case MeasurementHook::WaitInput:
        out +=
            fmt::format("  while not get_standard_digital_in({}):\n    sync()\n  end\n", r.signal);
        break;
      case MeasurementHook::PulseOutput:
        out += fmt::format(
            "  set_standard_digital_out({0}, True)\n  sleep(0.5)\n"
            "  set_standard_digital_out({0}, False)\n",
            r.signal);
        break;
      case MeasurementHook::LogLine:
        out += fmt::format(
            "  textmsg(\"robcal config {} joints \", \"{:.6f} {:.6f} {:.6f} {:.6f} {:.6f} "
            "{:.6f}\")\n",
            visit.name, q[0], q[1], q[2], q[3], q[4], q[5]);
        break;
    }
  }
  return out + "end\n";
}

std::vector<JointMove> read_urscript_joint_moves(const std::string& text, const std::string& file) {
  std::vector<JointMove> moves;
  int line = 1;
  size_t line_start = 0;
  for (size_t at = 0; at < text.size(); ++at) {
    const char c = text[at];
    if (c == '\n') {
      ++line;
      line_start = at + 1;
    } else if (c == '#') {
      while (at + 1 < text.size() && text[at + 1] != '\n') ++at;
    } else if (c == '"') {
      // A string (where "movej(" is text): skip to its closing quote, or stop at the line end.
      const size_t close = text.find_first_of("\"\n", at + 1);
      if (close == std::string::npos) break;
      at = text[close] == '"' ? close : close - 1;
    } else if (text.compare(at, 6, "movej(") == 0 &&
               (at == 0 ||
                !(std::isalnum(static_cast<unsigned char>(text[at - 1])) || text[at - 1] == '_'))) {
      const auto fail = [&](size_t pos, const std::string& what) {
        throw InputError(SourceLocation{file, line, static_cast<int>(pos - line_start) + 1, ""},
                         what);
      };
      const auto skip_blanks = [&](size_t pos) {
        while (pos < text.size() && (text[pos] == ' ' || text[pos] == '\t')) ++pos;
        return pos;
      };
      size_t pos = skip_blanks(at + 6);
      // movej(p[...]) is a pose (inverse kinematics on the controller), not a joint move.
      if (text.compare(pos, 2, "p[") == 0) {
        at = pos;
        continue;
      }
      if (pos >= text.size() || text[pos] != '[')
        fail(pos, "movej: expected a joint list [q1, ..., q6] in radians");
      JointMove move;
      move.line = line;
      ++pos;
      for (int j = 0; j < kJointCount; ++j) {
        pos = skip_blanks(pos);
        move.joints_deg[j] = rad2deg(read_number(text, pos, file, line, line_start));
        pos = skip_blanks(pos);
        const char want = j + 1 < kJointCount ? ',' : ']';
        if (pos >= text.size() || text[pos] != want)
          fail(pos, fmt::format("movej: expected '{}' after joint {}", want, j + 1));
        ++pos;
      }
      moves.push_back(move);
      at = pos - 1;
    }
  }
  return moves;
}

}  // namespace robcal::detail
