// KUKA KRL: E6POS/POS and E6AXIS/AXIS points in .dat declarations, assignments and motions.

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>

#include "measurement_writers.hpp"
#include "program_scan.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::detail {
namespace {

enum class PointKind { Position, Axis };

/// One `KEY value` entry of a KRL aggregate `{X 1.0, Y 2.0, ...}`.
struct Entry {
  std::string key;  ///< upper case
  Token at;
  NumberField number;  ///< present when the value is a (signed) number or a bit literal
};

class KrlScanner {
 public:
  KrlScanner(std::string_view text, const std::string& file, const ProgramFilterOptions& options)
      : lexer_(text, ProgramLanguage::Krl, file), options_(options) {}

  ProgramScan run() {
    for (;;) {
      const Token t = lexer_.next();
      if (t.kind == TokenKind::End) break;
      if (t.kind != TokenKind::Identifier) continue;
      const std::string word = upper(t.text);
      if (const auto kind = point_type(word); kind && lexer_.peek().kind == TokenKind::Identifier)
        declaration(*kind);
      else if (word == "PTP" || word == "LIN" || word == "CIRC" || word == "SPTP" ||
               word == "SLIN" || word == "SCIRC")
        motion();
      else if (word == "FDAT" && lexer_.peek().kind == TokenKind::Identifier)
        frame_data();
      else if (word == "BAS")
        bas_call();
      else if (word == "$TOOL" || word == "$BASE")
        frame_assignment(word);
      else if (auto found = declared_.find(word); found != declared_.end())
        assignment(t, found->second);
    }
    assign_frame_data();
    return {std::move(sites_), {}, {}};
  }

 private:
  // `BAS(#TOOL, n)` / `BAS(#BASE, n)`: tool or base n is active for the motions that follow.
  // Another value (a variable) makes it unknown until the next call or assignment; a malformed
  // call (`BAS(#TOOL,,1)`, `BAS(#TOOL 1)`) is refused, not skipped: skipping it would leave the
  // previous tool active for the points after it.
  void bas_call() {
    if (!lexer_.peek().is('(') || lexer_.peek(1).kind != TokenKind::Identifier) return;
    const std::string what = upper(lexer_.peek(1).text);
    if (what != "#TOOL" && what != "#BASE") return;
    const Token comma = lexer_.peek(2);
    if (!comma.is(','))
      refuse(lexer_.file(), comma,
             fmt::format("expected BAS({}, number), found '{}'", what,
                         comma.kind == TokenKind::End ? "end of file" : std::string(comma.text)));
    const Token value = lexer_.peek(3);
    std::string& active = what == "#TOOL" ? tool_ : base_;
    if (value.kind == TokenKind::End || value.is(',') || value.is(')'))
      refuse(lexer_.file(), value,
             fmt::format("expected the {} number after BAS({},", what == "#TOOL" ? "tool" : "base",
                         what));
    if (value.kind == TokenKind::Number && lexer_.peek(4).is(')'))
      active = indexed(what == "#TOOL" ? "TOOL_DATA" : "BASE_DATA", value);
    else
      active = fmt::format("BAS({}, ...) at line {}", what, value.line);
  }

  // `$TOOL = TOOL_DATA[n]`, `$BASE = BASE_DATA[n]`; any other value (a literal frame, an
  // expression) makes the active tool or base unknown until the next assignment.
  void frame_assignment(const std::string& word) {
    if (!lexer_.peek().is('=')) return;
    const bool tool = word == "$TOOL";
    const char* table = tool ? "TOOL_DATA" : "BASE_DATA";
    std::string& active = tool ? tool_ : base_;
    if (iequals(lexer_.peek(1).text, table) && lexer_.peek(2).is('[') &&
        lexer_.peek(3).kind == TokenKind::Number && lexer_.peek(4).is(']'))
      active = indexed(table, lexer_.peek(3));
    else
      active = fmt::format("{} (set at line {})", word, lexer_.peek().line);
  }

  std::string indexed(const char* table, const Token& number) const {
    const double n = number_value(lexer_.file(), number);
    if (n != std::floor(n) || n < 0 || n > 128)
      refuse(lexer_.file(), number, fmt::format("{} index must be an integer 0..128", table));
    return fmt::format("{}[{}]", table, static_cast<int>(n));
  }

  // `DECL FDAT FP1={TOOL_NO 1,BASE_NO 0,...}`: the tool and base of the inline-form point XP1.
  void frame_data() {
    const Token name = lexer_.next();
    if (!lexer_.peek().is('=') || !lexer_.peek(1).is('{')) return;
    lexer_.next();
    const Token open = lexer_.next();
    std::pair<std::string, std::string> frames;
    for (const Entry& e : aggregate(open)) {
      if (!e.number.present || (e.key != "TOOL_NO" && e.key != "BASE_NO")) continue;
      const bool tool = e.key == "TOOL_NO";
      const double n = e.number.value;
      if (n != std::floor(n) || n < 0 || n > 128)
        refuse(lexer_.file(), e.at, fmt::format("{} must be an integer 0..128", e.key));
      (tool ? frames.first : frames.second) =
          fmt::format("{}[{}]", tool ? "TOOL_DATA" : "BASE_DATA", static_cast<int>(n));
    }
    frame_data_[upper(name.text)] = frames;
  }

  // Points declared as XP<n> take the tool and base of FDAT FP<n> (the inline forms' pairing).
  void assign_frame_data() {
    for (PointSite& site : sites_) {
      const std::string name = upper(site.point.name);
      if (name.size() < 2 || name[0] != 'X') continue;
      const auto found = frame_data_.find("F" + name.substr(1));
      if (found == frame_data_.end()) continue;
      site.point.tool = found->second.first;
      site.point.frame = found->second.second;
    }
  }

  static std::optional<PointKind> point_type(const std::string& word) {
    if (word == "E6POS" || word == "POS") return PointKind::Position;
    if (word == "E6AXIS" || word == "AXIS") return PointKind::Axis;
    return std::nullopt;
  }

  // `[DECL] [GLOBAL] E6POS name[[n]] [= {...}] [, name2 ...]`
  void declaration(PointKind kind) {
    for (;;) {
      const Token name = lexer_.next();
      declared_[upper(name.text)] = kind;
      const std::string index = array_index();
      if (lexer_.peek().is('=') && lexer_.peek(1).is('{')) {
        lexer_.next();
        point(kind, std::string(name.text) + index, /*inline_motion=*/false);
      }
      if (!(lexer_.peek().is(',') && lexer_.peek(1).kind == TokenKind::Identifier)) return;
      lexer_.next();
    }
  }

  // `name[i] = {...}` or `name = {...}` for a name declared as a point.
  void assignment(const Token& name, PointKind kind) {
    const std::string index = array_index();
    if (lexer_.peek().is('=') && lexer_.peek(1).is('{')) {
      lexer_.next();
      point(kind, std::string(name.text) + index, false);
    }
  }

  // Motions with literal points: `PTP {...}`, `CIRC {aux}, {target}`; the kind follows the keys.
  void motion() {
    while (lexer_.peek().is('{')) {
      const size_t before = sites_.size();
      point(std::nullopt, "", true);
      for (size_t i = before; i < sites_.size(); ++i) {
        sites_[i].point.tool = tool_;
        sites_[i].point.frame = base_;
      }
      if (!(lexer_.peek().is(',') && lexer_.peek(1).is('{'))) return;
      lexer_.next();
    }
  }

  // Text of an array index `[...]` when one follows, consumed.
  std::string array_index() {
    if (!lexer_.peek().is('[')) return "";
    std::string out;
    for (Token t = lexer_.next();; t = lexer_.next()) {
      if (t.kind == TokenKind::End) refuse(lexer_.file(), t, "array index never closed");
      out += t.text;
      if (t.is(']')) return out;
    }
  }

  void point(std::optional<PointKind> kind, const std::string& name, bool inline_motion) {
    const Token open = lexer_.next();
    const std::vector<Entry> entries = aggregate(open);
    const auto find = [&](const char* key) -> const Entry* {
      for (const Entry& e : entries)
        if (e.key == key) return &e;
      return nullptr;
    };
    if (!kind) {
      if (find("A1"))
        kind = PointKind::Axis;
      else if (find("X") || find("Y") || find("Z") || find("A") || find("B") || find("C"))
        kind = PointKind::Position;
      else
        return;  // not a point (e.g. an empty aggregate)
    }
    static const char* const kPositionKeys[] = {"X", "Y", "Z", "A", "B", "C"};
    static const char* const kAxisKeys[] = {"A1", "A2", "A3", "A4", "A5", "A6"};
    const bool axis = *kind == PointKind::Axis;
    if (axis && !options_.joints) return;
    PointSite site;
    site.point.is_joint_target = axis;
    site.point.name = name;
    site.point.line = open.line;
    site.point.column = open.column;
    for (const char* key : axis ? kAxisKeys : kPositionKeys) {
      const Entry* e = find(key);
      if (!e)
        refuse(lexer_.file(), open,
               fmt::format("point {}has no {}: incomplete points take the missing values from the "
                           "robot at run time and cannot be corrected{}",
                           name.empty() ? "" : "'" + name + "' ", key,
                           inline_motion ? " (use a _REL motion for relative moves)" : ""));
      if (!e->number.present || e->number.binary_digits > 0)
        refuse(lexer_.file(), e->at, fmt::format("{} is not a number literal", key));
      site.fields.push_back(e->number);
    }
    if (axis) {
      for (int k = 0; k < 6; ++k) site.point.joints_deg[k] = site.fields[k].value;
    } else {
      const Eigen::Vector3d abc(site.fields[3].value, site.fields[4].value, site.fields[5].value);
      site.point.base_T_tcp.p << site.fields[0].value, site.fields[1].value, site.fields[2].value;
      site.point.base_T_tcp.R = rotation_from_euler_deg(abc, EulerConvention::ZyxABC);
      const Entry* s = find("S");
      const Entry* t = find("T");
      if ((s == nullptr) != (t == nullptr))
        refuse(lexer_.file(), open, "a point with only one of S and T");
      if (s) {
        for (const Entry* e : {s, t}) {
          if (!e->number.present || e->number.value != std::round(e->number.value))
            refuse(lexer_.file(), e->at, fmt::format("{} must be an integer", e->key));
          site.fields.push_back(e->number);
          site.point.config.push_back(static_cast<int>(e->number.value));
        }
      }
    }
    sites_.push_back(std::move(site));
  }

  // Reads `{[TYPE:] KEY value, ...}` after its `{`.
  std::vector<Entry> aggregate(const Token& open) {
    std::vector<Entry> out;
    if (lexer_.peek().kind == TokenKind::Identifier && lexer_.peek(1).is(':')) {
      lexer_.next();
      lexer_.next();
    }
    if (lexer_.peek().is('}')) {
      lexer_.next();
      return out;
    }
    for (;;) {
      const Token key = lexer_.next();
      if (key.kind != TokenKind::Identifier)
        refuse(lexer_.file(), key.kind == TokenKind::End ? open : key,
               key.kind == TokenKind::End
                   ? "aggregate '{' never closed"
                   : fmt::format("expected a component name, found '{}'", key.text));
      Entry entry;
      entry.key = upper(key.text);
      for (const Entry& e : out)
        if (e.key == entry.key)
          refuse(lexer_.file(), key, fmt::format("component {} given twice", entry.key));
      entry.at = lexer_.peek();
      value(entry);
      out.push_back(std::move(entry));
      const Token t = lexer_.next();
      if (t.is('}')) return out;
      if (!t.is(','))
        refuse(lexer_.file(), t.kind == TokenKind::End ? open : t,
               t.kind == TokenKind::End ? "aggregate '{' never closed"
                                        : fmt::format("expected ',' or '}}', found '{}'", t.text));
    }
  }

  void value(Entry& entry) {
    const Token first = lexer_.peek();
    size_t k = (first.is('-') || first.is('+')) ? 1 : 0;
    const Token& literal = lexer_.peek(k);
    const Token& after = lexer_.peek(k + 1);
    if ((literal.kind == TokenKind::Number || (k == 0 && literal.kind == TokenKind::BitString)) &&
        (after.is(',') || after.is('}'))) {
      entry.number.present = true;
      entry.number.begin = first.offset;
      entry.number.end = literal.offset + literal.text.size();
      if (literal.kind == TokenKind::Number) {
        const double v = number_value(lexer_.file(), literal);
        entry.number.value = first.is('-') ? -v : v;
      } else {
        // 'B0101' (binary) or 'H1F' (hex), quotes included in the token.
        const std::string_view body = literal.text.substr(2, literal.text.size() - 3);
        const char base =
            static_cast<char>(std::toupper(static_cast<unsigned char>(literal.text[1])));
        int v = 0;
        const auto [ptr, ec] =
            std::from_chars(body.data(), body.data() + body.size(), v, base == 'B' ? 2 : 16);
        if ((base != 'B' && base != 'H') || ec != std::errc() || ptr != body.data() + body.size())
          refuse(lexer_.file(), literal, fmt::format("bad bit literal {}", literal.text));
        entry.number.value = v;
        entry.number.binary_digits = base == 'B' ? static_cast<int>(body.size()) : 0;
        if (base == 'H') entry.number.present = false;  // hex S/T: not rewritten, refused later
      }
      for (size_t i = 0; i <= k; ++i) lexer_.next();
      return;
    }
    int depth = 0;
    for (;;) {
      const Token& t = lexer_.peek();
      if (t.kind == TokenKind::End) refuse(lexer_.file(), first, "aggregate never closed");
      if (depth == 0 && (t.is(',') || t.is('}'))) return;
      if (t.is('(') || t.is('[') || t.is('{')) ++depth;
      if (t.is(')') || t.is(']') || t.is('}')) --depth;
      lexer_.next();
    }
  }

  ProgramLexer lexer_;
  const ProgramFilterOptions& options_;
  std::unordered_map<std::string, PointKind> declared_;
  std::vector<PointSite> sites_;
  std::string tool_, base_;  ///< active for inline motion points ("" = not set in this file)
  std::map<std::string, std::pair<std::string, std::string>> frame_data_;  ///< FDAT: tool, base
};

}  // namespace

ProgramScan scan_krl(std::string_view text, const std::string& file,
                     const ProgramFilterOptions& options) {
  return KrlScanner(text, file, options).run();
}

}  // namespace robcal::detail

// Measurement programs in KRL. Grammar constraints relied on: the DEF name is the file name,
// at most 24 characters; comments run from ';' to the end of the line; the first motion is
// an absolute PTP (BCO run), and a PTP without C_PTP stops exactly (fine point); joint
// values are REAL (32-bit on the controller: 6 decimals are more than it keeps, written so
// that the plan reads back exactly).
namespace robcal::detail {

std::string write_krl_measurement(const MeasurementPart& part) {
  const MeasurementProgramRequest& r = part.request;
  const auto axis = [](const Vector6d& q) {
    return fmt::format("{{A1 {:.6f},A2 {:.6f},A3 {:.6f},A4 {:.6f},A5 {:.6f},A6 {:.6f}}}", q[0],
                       q[1], q[2], q[3], q[4], q[5]);
  };
  std::string out = fmt::format("DEF {}( )\n", part.program) +
                    header_comment(part, ";", "reached with an exact stop");
  for (int j = 1; j <= kJointCount; ++j)
    out +=
        fmt::format("  $VEL_AXIS[{0}]={1:g}\n  $ACC_AXIS[{0}]={1:g}\n", j, r.joint_speed_percent);
  for (const Visit& v : part.visits) {
    out += fmt::format("  ; {}\n  PTP {}\n  PTP {}\n  WAIT SEC {:.2f}\n", v.name,
                       axis(v.approach_deg), axis(v.target_deg), r.settle_s);
    if (r.hook == MeasurementHook::WaitInput)
      out += fmt::format("  WAIT FOR $IN[{}]\n", r.signal);
    else
      out += fmt::format("  PULSE($OUT[{}], TRUE, 0.5)\n", r.signal);
  }
  return out + "END\n";
}

}  // namespace robcal::detail
