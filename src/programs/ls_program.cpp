// Fanuc TP source (.ls): measurement programs and their joint positions read back.
//
// Grammar constraints relied on (what the controller's LS loader checks):
// - sections in this order: `/PROG name`, `/ATTR` (OWNER, COMMENT of at most 16 characters,
//   LINE_COUNT equal to the number of /MN lines, PROTECT, TCD, DEFAULT_GROUP, CONTROL_CODE),
//   `/MN`, `/POS`, `/END`; program names at most 36 characters, upper case (robcal writes 8);
// - /MN lines are `number:instruction ;`, numbered 1..n without gaps; a comment `! text ;`
//   holds at most 32 characters and MESSAGE[] at most 24;
// - every P[i] used in /MN is defined once in /POS, `P[i]{ GP1: UF : u, UT : t, J1= v deg,
//   ... };` in joint representation (Cartesian ones have CONFIG and X..R instead);
// - numbers are plain decimals; the controller prints 3 decimals and stores 32-bit floats,
//   robcal writes 6 so that the plan reads back exactly.

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <map>

#include "measurement_writers.hpp"
#include "robcal/core/error.hpp"

namespace robcal::detail {

std::string write_ls_measurement(const MeasurementPart& part) {
  const MeasurementProgramRequest& r = part.request;
  std::vector<std::string> mn;  // /MN instructions, numbered when written
  std::string pos;
  int next_point = 1;
  const auto point = [&](const Vector6d& q) {
    pos += fmt::format(
        "P[{}]{{\n   GP1:\n\tUF : 0, UT : {},\n"
        "\tJ1= {:.6f} deg,\tJ2= {:.6f} deg,\tJ3= {:.6f} deg,\n"
        "\tJ4= {:.6f} deg,\tJ5= {:.6f} deg,\tJ6= {:.6f} deg\n}};\n",
        next_point, r.tool_number, q[0], q[1], q[2], q[3], q[4], q[5]);
    mn.push_back(fmt::format("J P[{}] {:g}% FINE", next_point++, r.joint_speed_percent));
  };
  mn.push_back("UFRAME_NUM=0");
  mn.push_back(fmt::format("UTOOL_NUM={}", r.tool_number));
  for (const Visit& v : part.visits) {
    mn.push_back(fmt::format("! {}", v.name));
    point(v.approach_deg);
    point(v.target_deg);
    mn.push_back(fmt::format("WAIT {:.2f}(sec)", r.settle_s));
    switch (r.hook) {
      case MeasurementHook::WaitInput:
        mn.push_back(fmt::format("WAIT DI[{}]=ON", r.signal));
        break;
      case MeasurementHook::PulseOutput:
        mn.push_back(fmt::format("DO[{}]=PULSE,0.5sec", r.signal));
        break;
      case MeasurementHook::LogLine:
        mn.push_back(fmt::format("MESSAGE[robcal {}]", v.name));
        break;
    }
  }
  std::string out = fmt::format(
      "/PROG  {}\n/ATTR\nOWNER\t\t= MNEDITOR;\nCOMMENT\t\t= \"robcal measure\";\n"
      "LINE_COUNT\t= {};\nPROTECT\t\t= READ_WRITE;\n"
      "TCD:  STACK_SIZE\t= 0,\n      TASK_PRIORITY\t= 50,\n      TIME_SLICE\t= 0,\n"
      "      BUSY_LAMP_OFF\t= 0,\n      ABORT_REQUEST\t= 0,\n      PAUSE_REQUEST\t= 0;\n"
      "DEFAULT_GROUP\t= 1,*,*,*,*;\nCONTROL_CODE\t= 00000000 00000000;\n/MN\n",
      part.program, mn.size());
  // The part's description would not fit a 32-character comment: COMMENT names the purpose.
  for (size_t i = 0; i < mn.size(); ++i)
    out += fmt::format("{:>4}:{}{} ;\n", i + 1, mn[i].starts_with("J ") ? "" : "  ", mn[i]);
  return out + "/POS\n" + pos + "/END\n";
}

namespace {

/// A line-by-line reader of an LS file with the position of each line.
struct LsLine {
  std::string_view text;
  int number = 0;
  size_t start = 0;  ///< offset of the line in the file
};

std::vector<LsLine> split_lines(std::string_view text) {
  std::vector<LsLine> lines;
  size_t at = 0;
  int number = 1;
  while (at < text.size()) {
    size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(at, end - at);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back({line, number++, at});
    at = end + 1;
  }
  return lines;
}

}  // namespace

std::vector<JointMove> read_ls_joint_moves(const std::string& text, const std::string& file) {
  const std::vector<LsLine> lines = split_lines(text);
  enum class Section { Header, Mn, Pos, End } section = Section::Header;
  std::vector<std::pair<int, int>> order;  // (point index, /MN line)
  std::map<int, Vector6d> joints;
  int current = -1;  // P index whose block is open
  int found = 0;     // J values read in the open block's GP1
  bool in_gp1 = false;
  for (const LsLine& l : lines) {
    const auto fail = [&](size_t column, const std::string& what) {
      throw InputError(SourceLocation{file, l.number, static_cast<int>(column) + 1, ""}, what);
    };
    const std::string_view t = l.text;
    if (t.starts_with("/MN")) section = Section::Mn;
    if (t.starts_with("/POS")) section = Section::Pos;
    if (t.starts_with("/END")) section = Section::End;
    if (t.starts_with("/")) continue;
    if (section == Section::Mn) {
      // `  12:J P[3] 10% FINE ;` — a joint move to a P register of this program.
      const size_t colon = t.find(':');
      if (colon == std::string_view::npos) continue;
      const size_t at = t.find_first_not_of(" \t", colon + 1);
      if (at == std::string_view::npos || t.substr(at, 4) != "J P[") continue;
      size_t offset = l.start + at + 4;
      const double index = read_number(text, offset, file, l.number, l.start);
      if (index != std::floor(index) || index < 1 || offset - l.start >= t.size() ||
          t[offset - l.start] != ']')
        fail(at + 4, "expected P[index] with a positive integer index");
      order.emplace_back(static_cast<int>(index), l.number);
    } else if (section == Section::Pos) {
      if (t.starts_with("P[")) {
        size_t at = l.start + 2;
        const double index = read_number(text, at, file, l.number, l.start);
        if (index != std::floor(index) || index < 1) fail(2, "expected a positive P index");
        current = static_cast<int>(index);
        found = 0;
        in_gp1 = false;
        if (joints.count(current)) fail(0, fmt::format("P[{}] defined twice", current));
        continue;
      }
      if (t.find("GP1:") != std::string_view::npos) in_gp1 = true;
      if (t.find("GP2:") != std::string_view::npos) in_gp1 = false;
      if (t.starts_with("};")) {
        if (found == kJointCount) continue;
        if (found != 0) fail(0, fmt::format("P[{}] has {} of the joints J1..J6", current, found));
        joints.erase(current);  // Cartesian representation: not a joint position
        continue;
      }
      if (!in_gp1 || current < 0) continue;
      // `J1=   25.000 deg,  J2= ...`: one to three joints per line.
      for (size_t at = t.find('J'); at != std::string_view::npos; at = t.find('J', at)) {
        if (at + 2 >= t.size() || t[at + 1] < '1' || t[at + 1] > '6' ||
            (at > 0 && std::isalnum(static_cast<unsigned char>(t[at - 1])))) {
          ++at;
          continue;
        }
        const int j = t[at + 1] - '1';
        size_t value = t.find_first_not_of(" \t", at + 2);
        if (value == std::string_view::npos || t[value] != '=') fail(at + 2, "expected '='");
        value = t.find_first_not_of(" \t", value + 1);
        if (value == std::string_view::npos) fail(t.size(), "expected a joint value");
        size_t offset = l.start + value;
        joints[current][j] = read_number(text, offset, file, l.number, l.start);
        at = offset - l.start;
        const size_t unit = t.find_first_not_of(" \t", at);
        if (unit == std::string_view::npos || t.substr(unit, 3) != "deg")
          fail(at, fmt::format("J{} of P[{}]: expected 'deg'", j + 1, current));
        ++found;
      }
    }
  }
  if (section != Section::End)
    throw InputError(SourceLocation{file, lines.empty() ? 0 : lines.back().number, 0, ""},
                     "the program has no /END line");
  std::vector<JointMove> moves;
  for (const auto& [index, line] : order) {
    const auto it = joints.find(index);
    if (it != joints.end()) moves.push_back({it->second, line});
  }
  return moves;
}

}  // namespace robcal::detail
