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

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <unordered_map>
#include <unordered_set>

#include "measurement_writers.hpp"
#include "program_scan.hpp"
#include "robcal/core/error.hpp"
#include "robcal/kinematics/orientation.hpp"

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
    mn.push_back(fmt::format("! {}", v.label()));
    if (v.approach) point(v.approach_deg);
    point(v.target_deg);
    if (!v.measure) continue;
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

/// One position of the /POS section (group 1): where each value sits in the text.
struct LsPosition {
  int index = 0;  ///< n of P[n]
  int line = 0, column = 0;
  int uf = -1, ut = -1;                                    ///< -1: not given
  std::map<std::string, NumberField, std::less<>> values;  ///< X..R or J1..J6
  std::string config;                                      ///< CONFIG text between quotes
  size_t config_column = 0;
};

/// The /POS section's positions and the /MN joint moves `J P[n]` (index, line), with every
/// number read whole. Grammar: see the top of this file.
struct LsProgram {
  std::vector<LsPosition> positions;
  std::vector<std::pair<int, int>> joint_moves;
};

LsProgram parse_ls(std::string_view text, const std::string& file) {
  enum class Section { Header, Mn, Pos, End } section = Section::Header;
  LsProgram out;
  LsPosition* current = nullptr;
  std::unordered_set<int> defined;  // P indices of /POS
  bool in_gp1 = false;
  int number = 0;
  for (size_t at = 0; at < text.size();) {
    ++number;
    const size_t start = at;
    size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    std::string_view t = text.substr(start, end - start);
    if (!t.empty() && t.back() == '\r') t.remove_suffix(1);
    at = end + 1;
    const auto fail = [&](size_t column, const std::string& what) {
      throw InputError(SourceLocation{file, number, static_cast<int>(column) + 1, ""}, what);
    };
    const auto integer = [&](size_t& offset, const char* what) {
      const double v = read_number(text, offset, file, number, start);
      if (v != std::floor(v) || v < 0 || v > 1e6)
        fail(offset - start - 1, fmt::format("{}: expected a whole number", what));
      return static_cast<int>(v);
    };
    if (t.starts_with("/MN")) section = Section::Mn;
    if (t.starts_with("/POS")) section = Section::Pos;
    if (t.starts_with("/END")) section = Section::End;
    if (t.starts_with("/")) continue;
    if (section == Section::Mn) {
      // `  12:J P[3] 10% FINE ;` — a joint move to a position of this program.
      const size_t colon = t.find(':');
      if (colon == std::string_view::npos) continue;
      const size_t col = t.find_first_not_of(" \t", colon + 1);
      if (col == std::string_view::npos || t.substr(col, 4) != "J P[") continue;
      size_t offset = start + col + 4;
      const int index = integer(offset, "P index");  // P[4] or P[4:comment]
      if (offset - start >= t.size() || (t[offset - start] != ']' && t[offset - start] != ':'))
        fail(offset - start, "expected ']' or ':comment]'");
      out.joint_moves.emplace_back(index, number);
    } else if (section == Section::Pos) {
      if (t.starts_with("P[")) {
        size_t offset = start + 2;
        LsPosition p;
        p.index = integer(offset, "P index");
        p.line = number;
        p.column = 1;
        if (!defined.insert(p.index).second) fail(0, fmt::format("P[{}] defined twice", p.index));
        out.positions.push_back(std::move(p));
        current = &out.positions.back();
        in_gp1 = false;
        continue;
      }
      if (t.find("GP1:") != std::string_view::npos) in_gp1 = true;
      if (t.find("GP2:") != std::string_view::npos) in_gp1 = false;
      if (t.starts_with("};")) current = nullptr;
      if (!current || !in_gp1) continue;
      // `KEY : value` or `KEY = value unit`, separated by commas (CONFIG's quotes hold commas).
      for (size_t col = 0; col < t.size();) {
        if (!std::isalpha(static_cast<unsigned char>(t[col]))) {
          ++col;
          continue;
        }
        const size_t key_start = col;
        while (col < t.size() && std::isalnum(static_cast<unsigned char>(t[col]))) ++col;
        const std::string key(t.substr(key_start, col - key_start));
        col = t.find_first_not_of(" \t", col);
        if (key == "GP1") break;
        if (col == std::string_view::npos || (t[col] != ':' && t[col] != '='))
          fail(key_start, fmt::format("P[{}]: expected ':' or '=' after {}", current->index, key));
        col = t.find_first_not_of(" \t", col + 1);
        if (col == std::string_view::npos) fail(t.size(), fmt::format("{}: expected a value", key));
        if (key == "CONFIG") {
          const size_t close = t[col] == '\'' ? t.find('\'', col + 1) : std::string_view::npos;
          if (close == std::string_view::npos) fail(col, "CONFIG: expected a quoted string");
          current->config = std::string(t.substr(col + 1, close - col - 1));
          current->config_column = col + 1;
          col = close + 1;
          continue;
        }
        size_t offset = start + col;
        if (key == "UF" || key == "UT") {
          int& slot = key == "UF" ? current->uf : current->ut;
          if (slot >= 0)
            fail(key_start, fmt::format("{} given twice in P[{}]", key, current->index));
          slot = integer(offset, key.c_str());
        } else {
          const bool joint = key.size() == 2 && key[0] == 'J' && key[1] >= '1' && key[1] <= '6';
          if (!joint && (key.size() != 1 ||
                         std::string_view("XYZWPR").find(key[0]) == std::string_view::npos))
            fail(key_start, fmt::format("P[{}]: unknown component {}", current->index, key));
          NumberField f;
          f.present = true;
          f.begin = offset;
          f.value = read_number(text, offset, file, number, start);
          f.end = offset;
          const size_t unit = t.find_first_not_of(" \t", offset - start);
          const std::string_view want =
              joint || std::string_view("WPR").find(key[0]) != std::string_view::npos ? "deg"
                                                                                      : "mm";
          if (unit == std::string_view::npos || t.substr(unit, want.size()) != want)
            fail(offset - start,
                 fmt::format("{} of P[{}]: expected '{}'", key, current->index, want));
          if (!current->values.emplace(key, f).second)
            fail(key_start, fmt::format("{} given twice in P[{}]", key, current->index));
          offset = start + unit + want.size();
        }
        col = offset - start;
        // Items are separated by commas: `UF : 1 UT : 2` would read as written by no controller.
        const size_t next = t.find_first_not_of(" \t", col);
        if (next != std::string_view::npos && t[next] != ',')
          fail(next, fmt::format("P[{}]: expected ',' after {}", current->index, key));
      }
    }
  }
  if (section != Section::End)
    throw InputError(SourceLocation{file, number, 0, ""}, "the program has no /END line");
  return out;
}

constexpr std::array<const char*, 6> kCartesian{"X", "Y", "Z", "W", "P", "R"};
constexpr std::array<const char*, 6> kJoints{"J1", "J2", "J3", "J4", "J5", "J6"};

/// Which of `keys` a position has: all (true), none (false), or some (InputError).
bool has_all(const LsPosition& p, const std::array<const char*, 6>& keys, const std::string& file) {
  int found = 0;
  for (const char* k : keys) found += p.values.count(k) ? 1 : 0;
  if (found != 0 && found != 6)
    throw InputError(SourceLocation{file, p.line, p.column, fmt::format("P[{}]", p.index)},
                     fmt::format("has {} of the components {}..{}", found, keys[0], keys[5]));
  return found == 6;
}

/// CONFIG 'F U T, t4, t5, t6' as (flip, down, back, t4, t5, t6).
std::vector<int> ls_config(const LsPosition& p, const std::string& file) {
  std::vector<int> out;
  const SourceLocation where{file, p.line, static_cast<int>(p.config_column) + 1,
                             fmt::format("P[{}]", p.index)};
  size_t at = 0;
  const auto skip = [&] {
    while (at < p.config.size() && (p.config[at] == ' ' || p.config[at] == '\t')) ++at;
  };
  for (const char* letters : {"NF", "UD", "TB"}) {
    skip();
    const size_t k = at < p.config.size() ? std::string_view(letters).find(p.config[at])
                                          : std::string_view::npos;
    if (k == std::string_view::npos)
      throw InputError(where, fmt::format("CONFIG '{}': expected the letters N|F U|D T|B and "
                                          "three turn numbers",
                                          p.config));
    out.push_back(static_cast<int>(k));
    ++at;
  }
  for (int turn = 0; turn < 3; ++turn) {
    skip();
    if (at >= p.config.size() || p.config[at] != ',')
      throw InputError(where, fmt::format("CONFIG '{}': expected three turn numbers", p.config));
    ++at;
    skip();
    const size_t begin = at;
    if (at < p.config.size() && p.config[at] == '-') ++at;
    while (at < p.config.size() && std::isdigit(static_cast<unsigned char>(p.config[at]))) ++at;
    int v = 0;
    const auto [ptr, ec] = std::from_chars(p.config.data() + begin, p.config.data() + at, v);
    if (ec != std::errc() || begin == at)
      throw InputError(where, fmt::format("CONFIG '{}': expected a turn number", p.config));
    out.push_back(v);
  }
  return out;
}

}  // namespace

ProgramScan scan_ls(std::string_view text, const std::string& file,
                    const ProgramFilterOptions& options) {
  ProgramScan out;
  for (const LsPosition& p : parse_ls(text, file).positions) {
    PointSite site;
    site.point.name = fmt::format("P[{}]", p.index);
    site.point.line = p.line;
    site.point.column = p.column;
    if (p.uf < 0 || p.ut < 0)
      throw InputError(SourceLocation{file, p.line, p.column, site.point.name},
                       fmt::format("GP1 has no {}: each position names its user frame and tool "
                                   "(UF : n, UT : n)",
                                   p.uf < 0 ? "UF" : "UT"));
    site.point.tool = fmt::format("UT[{}]", p.ut);
    site.point.frame = fmt::format("UF[{}]", p.uf);
    if (has_all(p, kCartesian, file)) {
      for (const char* k : kCartesian) site.fields.push_back(p.values.at(k));
      const auto& f = site.fields;
      site.point.base_T_tcp.p << f[0].value, f[1].value, f[2].value;
      // (W, P, R) = rotations about x, y, z: R = Rz(R)·Ry(P)·Rx(W), the ZYX angles reversed.
      site.point.base_T_tcp.R = rotation_from_euler_deg(
          Eigen::Vector3d(f[5].value, f[4].value, f[3].value), EulerConvention::ZyxABC);
      site.point.config = ls_config(p, file);
    } else if (has_all(p, kJoints, file)) {
      if (!options.joints) continue;
      site.point.is_joint_target = true;
      for (int j = 0; j < kJointCount; ++j) {
        site.fields.push_back(p.values.at(kJoints[static_cast<size_t>(j)]));
        site.point.joints_deg[j] = site.fields.back().value;
      }
    } else {
      throw InputError(SourceLocation{file, p.line, p.column, site.point.name},
                       "neither X..R (Cartesian) nor J1..J6 (joint) components");
    }
    out.sites.push_back(std::move(site));
  }
  return out;
}

std::vector<JointMove> read_ls_joint_moves(const std::string& text, const std::string& file) {
  const LsProgram program = parse_ls(text, file);
  std::unordered_map<int, const LsPosition*> by_index;
  for (const LsPosition& p : program.positions) by_index[p.index] = &p;
  std::vector<JointMove> moves;
  for (const auto& [index, line] : program.joint_moves) {
    const auto it = by_index.find(index);
    if (it == by_index.end() || !has_all(*it->second, kJoints, file)) continue;
    JointMove m;
    m.line = line;
    for (int j = 0; j < kJointCount; ++j)
      m.joints_deg[j] = it->second->values.at(kJoints[static_cast<size_t>(j)]).value;
    moves.push_back(m);
  }
  return moves;
}

}  // namespace robcal::detail
