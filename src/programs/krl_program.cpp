// KUKA KRL: E6POS/POS and E6AXIS/AXIS points in .dat declarations, assignments and motions.

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>

#include "measurement_writers.hpp"
#include "program_scan.hpp"
#include "robcal/core/error.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::detail {
namespace {

enum class PointKind { Position, Axis, Frame };

/// One `KEY value` entry of a KRL aggregate `{X 1.0, Y 2.0, ...}`.
struct Entry {
  std::string key;  ///< upper case
  Token at;
  NumberField number;  ///< present when the value is a (signed) number or a bit literal
};

/// A motion instruction's use of a named point, with the tool and base active there.
struct Usage {
  std::string tool, base;
  const std::string* file = nullptr;  ///< the scanner's file name
  int line = 0, column = 0;
};

class KrlScanner {
 public:
  /// `dat`: the module's .dat, scanned first (a .src sees its declarations, FDATs and frames).
  KrlScanner(std::string_view text, const std::string& file, const ProgramFilterOptions& options,
             const KrlScanner* dat = nullptr)
      : lexer_(text, ProgramLanguage::Krl, file), options_(options), module_(dat != nullptr) {
    // The frame tables of $config.dat, known to every module.
    declared_["TOOL_DATA"] = declared_["BASE_DATA"] = PointKind::Frame;
    dat_ = dat;
    if (dat == nullptr) return;
    frame_data_ = dat->frame_data_;
    out_.tools = dat->out_.tools;
    out_.frames = dat->out_.frames;
    out_.unknown_frames = dat->out_.unknown_frames;
    varying_ = dat->varying_;
    defined_at_ = dat->defined_at_;
  }

  void scan() {
    int previous_line = 0;
    for (;;) {
      const Token t = lexer_.next();
      if (t.kind == TokenKind::End) break;
      // KRL writes one statement per line: the first token of a line starts one.
      statement_start_ = t.line != previous_line;
      previous_line = t.line;
      if (t.kind != TokenKind::Identifier) continue;
      const std::string upper_word = upper(t.text);
      // Compared as a view: lengths first, no strlen per keyword (every identifier passes here).
      const std::string_view word = upper_word;
      if (word == "DECL" || word == "GLOBAL") continue;  // (not a name: no table look-up)
      if (const auto kind = point_type(word); kind && lexer_.peek().kind == TokenKind::Identifier)
        declaration(*kind);
      else if (word == "PTP" || word == "LIN" || word == "CIRC" || word == "SPTP" ||
               word == "SLIN" || word == "SCIRC" || word == "SPL")
        motion();
      else if (word == "FDAT" && lexer_.peek().kind == TokenKind::Identifier)
        frame_data();
      else if (word == "FDAT_ACT" && lexer_.peek().is('=') &&
               lexer_.peek(1).kind == TokenKind::Identifier)
        fdat_act_ = {upper(lexer_.peek(1).text), lexer_.peek(1).line};
      else if (word == "BAS")
        bas_call();
      else if (word == "$TOOL" || word == "$BASE")
        frame_assignment(upper_word);
      else if (const auto kind = declared(upper_word))
        assignment(t, *kind);
    }
    assign_frame_data();
  }

  /// The points of this file with the tool and base of the motions (of this file and of
  /// `users`, the module's other file) that use them.
  ProgramScan finish(const KrlScanner* users = nullptr) {
    assign_usages(users);
    out_.sites = std::move(sites_);
    return std::move(out_);
  }

 private:
  // `BAS(#TOOL, n)` / `BAS(#BASE, n)`: tool or base n is active for the motions that follow.
  // Another value (a variable) makes it unknown until the next call or assignment; a malformed
  // call (`BAS(#TOOL,,1)`, `BAS(#TOOL 1)`) is refused, not skipped: skipping it would leave the
  // previous tool active for the points after it.
  void bas_call() {
    if (!lexer_.peek().is('(') || lexer_.peek(1).kind != TokenKind::Identifier) return;
    const std::string what = upper(lexer_.peek(1).text);
    if (what == "#PTP_PARAMS" || what == "#CP_PARAMS" || what == "#FRAMES") return inline_form();
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
      active = unknown_frame(fmt::format("BAS({}, ...) at line {}", what, value.line),
                             fmt::format("BAS({}, ...) at {}:{} takes the number from an "
                                         "expression, known only at run time",
                                         what, lexer_.file(), value.line));
  }

  // A tool or base whose value the scan cannot know: `key` names it at the points after it,
  // `why` is the reason a point under it gives when refused.
  std::string unknown_frame(const std::string& key, std::string why) {
    out_.unknown_frames.insert_or_assign(key, std::move(why));
    return key;
  }

  // `.X = value` after a FRAME-valued name at the start of a statement (`$TOOL.X = 5`,
  // `XTOOL.Z = XTOOL.Z + 10`): one component changes at run time (`==` is a comparison).
  bool component_assignment() {
    return statement_start_ && lexer_.peek().is('.') &&
           lexer_.peek(1).kind == TokenKind::Identifier && lexer_.peek(2).is('=') &&
           !lexer_.peek(3).is('=');
  }

  // An inline form's `FDAT_ACT = Fname` then `BAS(#PTP_PARAMS|#CP_PARAMS|#FRAMES, ...)`: BAS.SRC
  // sets $TOOL = TOOL_DATA[FDAT_ACT.TOOL_NO] and $BASE = BASE_DATA[FDAT_ACT.BASE_NO].
  void inline_form() {
    if (fdat_act_.first.empty()) return;  // no FDAT_ACT in this file: the frames stay as they are
    const auto found = frame_data_.find(fdat_act_.first);
    if (found != frame_data_.end()) {
      tool_ = found->second.first;
      base_ = found->second.second;
    } else {
      tool_ = base_ = unknown_frame(
          fmt::format("FDAT_ACT={} (line {}, no DECL FDAT {} in the module)", fdat_act_.first,
                      fdat_act_.second, fdat_act_.first),
          fmt::format("the inline form's FDAT_ACT={} at {}:{} names no DECL FDAT of the module, "
                      "so its tool and base numbers are unknown",
                      fdat_act_.first, lexer_.file(), fdat_act_.second));
    }
    fdat_act_.first.clear();
  }

  // `$TOOL = TOOL_DATA[n]`, `$BASE = BASE_DATA[n]`, `$TOOL = name` (a FRAME of the module or
  // of $config.dat), `$TOOL = {X ...}` (a literal frame, which defines it); any other value
  // (an expression) or a changed component (`$TOOL.X = ...`) makes the active tool or base
  // unknown until the next assignment.
  void frame_assignment(const std::string& word) {
    const bool tool = word == "$TOOL";
    std::string& active = tool ? tool_ : base_;
    if (component_assignment()) {
      const int line = lexer_.peek().line;
      active = unknown_frame(
          fmt::format("{} (changed at line {})", word, line),
          fmt::format("{}.{} is assigned at {}:{}: its value is known only at run time", word,
                      upper(lexer_.peek(1).text), lexer_.file(), line));
      return;
    }
    if (!lexer_.peek().is('=') || lexer_.peek(1).is('=')) return;
    const Token value = lexer_.peek(1);
    if (value.is('{')) {
      lexer_.next();
      active = fmt::format("{} LITERAL AT LINE {}", word, value.line);
      define_frame(active, lexer_.next());
      return;
    }
    size_t after = 2;
    std::string name = upper(value.text);
    if (value.kind == TokenKind::Identifier && lexer_.peek(2).is('[') &&
        lexer_.peek(3).kind == TokenKind::Number && lexer_.peek(4).is(']')) {
      name = indexed(name.c_str(), lexer_.peek(3));
      after = 5;
    }
    // The value ends the statement (the next token is on a later line): a plain name.
    const Token& next = lexer_.peek(after);
    if (value.kind == TokenKind::Identifier && name[0] != '$' &&
        (next.kind == TokenKind::End || next.line > value.line))
      active = name;
    else
      active = unknown_frame(
          fmt::format("{} (set at line {})", word, value.line),
          fmt::format("{} is assigned an expression at {}:{} (a FRAME name, TOOL_DATA[n], "
                      "BASE_DATA[n] or a literal frame is read; anything else is known only at "
                      "run time)",
                      word, lexer_.file(), value.line));
  }

  // A literal FRAME `{X, Y, Z, A, B, C}` after its `{`: the tool (flange_T_tcp) or base
  // (world_T_base) named `name`. A name given two different literal values is left undefined
  // (which one is active at a point depends on the run).
  void define_frame(const std::string& name, const Token& open) {
    const std::vector<Entry>& entries = aggregate(open);
    double v[6];
    static const char* const kKeys[] = {"X", "Y", "Z", "A", "B", "C"};
    for (int k = 0; k < 6; ++k) {
      const auto e = std::find_if(entries.begin(), entries.end(),
                                  [&](const Entry& x) { return x.key == kKeys[k]; });
      if (e == entries.end())
        refuse(lexer_.file(), open,
               fmt::format("FRAME '{}' has no {}: expected {{X, Y, Z, A, B, C}} (mm, deg)", name,
                           kKeys[k]));
      if (!e->number.present || e->number.binary_digits > 0)
        refuse(lexer_.file(), e->at,
               fmt::format("FRAME '{}': {} is not a number literal", name, kKeys[k]));
      v[k] = e->number.value;
    }
    for (const Entry& e : entries)
      if (std::find(std::begin(kKeys), std::end(kKeys), e.key) == std::end(kKeys))
        refuse(lexer_.file(), e.at,
               fmt::format("FRAME '{}': unknown component {} (expected X, Y, Z, A, B, C)", name,
                           e.key));
    Pose<double> pose;
    pose.p << v[0], v[1], v[2];
    pose.R = rotation_from_euler_deg(Eigen::Vector3d(v[3], v[4], v[5]), EulerConvention::ZyxABC);
    if (varying_.count(name)) return;
    const std::string here = fmt::format("{}:{}", lexer_.file(), open.line);
    for (auto* table : {&out_.tools, &out_.frames}) {
      const auto [it, added] = table->emplace(name, pose);
      if (!added && ((it->second.p - pose.p).norm() > 0 || (it->second.R - pose.R).norm() > 0))
        return make_varying(name, fmt::format("it is given one value at {} and another at {}: "
                                              "which one is active at a point depends on the run",
                                              defined_at_[name], here));
    }
    defined_at_.emplace(name, here);
  }

  // A FRAME name with no one value (two literal values, a component assigned): no point may be
  // corrected under it.
  void make_varying(const std::string& name, std::string why) {
    out_.tools.erase(name);
    out_.frames.erase(name);
    varying_.insert(name);
    out_.unknown_frames.insert_or_assign(name, std::move(why));
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

  static std::optional<PointKind> point_type(std::string_view word) {
    if (word == "E6POS" || word == "POS") return PointKind::Position;
    if (word == "E6AXIS" || word == "AXIS") return PointKind::Axis;
    if (word == "FRAME") return PointKind::Frame;
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
        if (kind == PointKind::Frame)
          define_frame(upper(std::string(name.text) + index), lexer_.next());
        else
          point(kind, std::string(name.text) + index, /*inline_motion=*/false);
      }
      if (!(lexer_.peek().is(',') && lexer_.peek(1).kind == TokenKind::Identifier)) return;
      lexer_.next();
    }
  }

  // `name[i] = {...}` or `name = {...}` for a name declared as a point or FRAME; `name.X = ...`
  // changes a FRAME (TOOL_DATA[n] included) at run time.
  void assignment(const Token& name, PointKind kind) {
    const std::string index = array_index();
    if (kind == PointKind::Frame && component_assignment()) {
      const std::string frame = upper(std::string(name.text) + index);
      if (!varying_.count(frame))
        make_varying(frame, fmt::format("its component {} is assigned at {}:{}: its value is "
                                        "known only at run time",
                                        upper(lexer_.peek(1).text), lexer_.file(), name.line));
      return;
    }
    if (lexer_.peek().is('=') && lexer_.peek(1).is('{')) {
      lexer_.next();
      if (kind == PointKind::Frame)
        define_frame(upper(std::string(name.text) + index), lexer_.next());
      else
        point(kind, std::string(name.text) + index, false);
    }
  }

  // Motions: literal points `PTP {...}` (the kind follows the keys) and named ones `LIN XP1`,
  // `CIRC XAUX, {target}`, each taking the tool and base active here.
  void motion() {
    for (;;) {
      if (lexer_.peek().is('{')) {
        const size_t before = sites_.size();
        point(std::nullopt, "", true);
        for (size_t i = before; i < sites_.size(); ++i) {
          sites_[i].point.tool = tool_;
          sites_[i].point.frame = base_;
        }
      } else if (lexer_.peek().kind == TokenKind::Identifier &&
                 !iequals(lexer_.peek().text, "CA")) {
        named_target();
      } else {
        return;
      }
      if (!(lexer_.peek().is(',') &&
            (lexer_.peek(1).is('{') || lexer_.peek(1).kind == TokenKind::Identifier)))
        return;
      lexer_.next();
    }
  }

  // `LIN XP1`, `PTP XSEAM[2]`: a use of a declared point. In a module (.src with its .dat) a
  // name declared in neither file is refused: its value lives elsewhere and is not corrected.
  // `$` names are the controller's run-time positions; XHOME and XHOME1..5 are the home
  // positions of $config.dat (joint positions of the cell, not taught points of this module).
  void named_target() {
    const Token name = lexer_.next();
    const std::string key = upper(name.text);
    const std::string index = array_index();
    if (lexer_.peek().is(':'))
      refuse(lexer_.file(), lexer_.peek(),
             fmt::format("motion target '{}{}' combined with a geometric operator ':': only "
                         "plain and literal points are corrected",
                         name.text, index));
    const bool home = key == "XHOME" || (key.size() == 6 && key.starts_with("XHOME") &&
                                         key[5] >= '1' && key[5] <= '5');
    const auto kind = declared(key);
    if (!kind) {
      if (!module_ || key[0] == '$' || home) return;
      const std::string message = fmt::format(
          "'{}' is used here but declared neither in this .src nor in its .dat: a "
          "point defined elsewhere is not corrected",
          name.text);
      if (!options_.keep_going) refuse(lexer_.file(), name, message);
      out_.unresolved.push_back(
          {fmt::format("{}:{}:{} ({})", lexer_.file(), name.line, name.column, name.text),
           message});
      return;
    }
    if (*kind == PointKind::Frame)
      refuse(lexer_.file(), name, fmt::format("'{}' is a FRAME, not a point", name.text));
    usages_[key + index].push_back({tool_, base_, &lexer_.file(), name.line, name.column});
  }

  // A declared point takes the tool and base of the motions that use it (a variable index,
  // `XP[I]`, uses every element); one corrected value cannot serve two of them.
  // The kind of a declared name: of this file, else of the module's .dat.
  [[nodiscard]] std::optional<PointKind> declared(const std::string& name) const {
    if (const auto it = declared_.find(name); it != declared_.end()) return it->second;
    if (dat_ == nullptr) return std::nullopt;
    if (const auto it = dat_->declared_.find(name); it != dat_->declared_.end()) return it->second;
    return std::nullopt;
  }

  void assign_usages(const KrlScanner* users) {
    const auto label = [](const std::string& s) { return s.empty() ? std::string("?") : s; };
    std::vector<const std::unordered_map<std::string, std::vector<Usage>>*> tables = {&usages_};
    if (users) tables.push_back(&users->usages_);
    // Uses with a variable index (few), by their array's prefix "NAME[".
    std::vector<std::pair<std::string, const std::vector<Usage>*>> whole_arrays;
    for (const auto* table : tables)
      for (const auto& [key, list] : *table) {
        const size_t open = key.find('[');
        if (open != std::string::npos && !std::isdigit(static_cast<unsigned char>(key[open + 1])))
          whole_arrays.emplace_back(key.substr(0, open + 1), &list);
      }
    std::vector<const Usage*> uses;
    for (PointSite& site : sites_) {
      if (site.point.name.empty()) continue;
      const std::string name = upper(site.point.name);
      uses.clear();
      for (const auto* table : tables)
        if (const auto exact = table->find(name); exact != table->end())
          for (const Usage& u : exact->second) uses.push_back(&u);
      for (const auto& [prefix, list] : whole_arrays)
        if (name.starts_with(prefix))
          for (const Usage& u : *list) uses.push_back(&u);
      if (uses.empty()) continue;
      // A motion with no tool or base set before it in the .src keeps the point's FDAT pair.
      const auto frames_of = [&](const Usage& u) {
        return u.tool.empty() && u.base.empty() ? std::pair{site.point.tool, site.point.frame}
                                                : std::pair{u.tool, u.base};
      };
      const Usage& first = *uses.front();
      const auto [tool, base] = frames_of(first);
      for (const Usage* u : uses)
        if (frames_of(*u) != std::pair{tool, base})
          throw InputError(
              SourceLocation{lexer_.file(), site.point.line, site.point.column, site.point.name},
              fmt::format("used with tool {} and base {} at {}:{}:{} and with tool {} and base {} "
                          "at {}:{}:{}: one corrected value cannot serve both; give each use its "
                          "own point",
                          label(tool), label(base), *first.file, first.line, first.column,
                          label(frames_of(*u).first), label(frames_of(*u).second), *u->file,
                          u->line, u->column));
      site.point.tool = tool;
      site.point.frame = base;
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
    const std::vector<Entry>& entries = aggregate(open);
    const auto find = [&](std::string_view key) -> const Entry* {
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
    static constexpr std::string_view kPositionKeys[] = {"X", "Y", "Z", "A", "B", "C"};
    static constexpr std::string_view kAxisKeys[] = {"A1", "A2", "A3", "A4", "A5", "A6"};
    const bool axis = *kind == PointKind::Axis;
    if (axis && !options_.joints) return;
    PointSite site;
    site.fields.reserve(8);  // X Y Z A B C S T or A1..A6
    site.point.is_joint_target = axis;
    site.point.name = name;
    site.point.line = open.line;
    site.point.column = open.column;
    for (const std::string_view key : axis ? kAxisKeys : kPositionKeys) {
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
        site.point.config.reserve(2);
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

  // Reads `{[TYPE:] KEY value, ...}` after its `{`. The entries are valid until the next call
  // (their storage is reused: no allocation per point).
  const std::vector<Entry>& aggregate(const Token& open) {
    std::vector<Entry>& out = entries_;
    out.clear();
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
      Entry& entry = out.emplace_back();
      entry.key = upper(key.text);
      for (size_t i = 0; i + 1 < out.size(); ++i)
        if (out[i].key == entry.key)
          refuse(lexer_.file(), key, fmt::format("component {} given twice", entry.key));
      entry.at = lexer_.peek();
      value(entry);
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
  bool module_ = false;  ///< a .src scanned with its .dat
  std::unordered_map<std::string, PointKind> declared_;
  std::vector<PointSite> sites_;
  std::string tool_, base_;  ///< active for motion points ("" = not set in this file)
  std::map<std::string, std::pair<std::string, std::string>> frame_data_;  ///< FDAT: tool, base
  std::pair<std::string, int> fdat_act_;  ///< the last `FDAT_ACT = name` and its line
  const KrlScanner* dat_ = nullptr;       ///< the module's .dat, when this is its .src
  /// Uses by upper-case name with its index.
  std::unordered_map<std::string, std::vector<Usage>> usages_;
  std::vector<Entry> entries_;                     ///< the last aggregate read (aggregate())
  std::set<std::string> varying_;                  ///< FRAME names with no one value (make_varying)
  std::map<std::string, std::string> defined_at_;  ///< FRAME name: file:line of its value
  bool statement_start_ = false;                   ///< the identifier being handled begins its line
  ProgramScan out_;
};

}  // namespace

ProgramScan scan_krl(std::string_view text, const std::string& file,
                     const ProgramFilterOptions& options) {
  KrlScanner scanner(text, file, options);
  scanner.scan();
  return scanner.finish();
}

KrlModuleScan scan_krl_module(std::string_view src, std::string_view dat,
                              const std::string& src_file, const std::string& dat_file,
                              const ProgramFilterOptions& options) {
  require_program_language(dat, ProgramLanguage::Krl, dat_file);
  require_program_language(src, ProgramLanguage::Krl, src_file);
  KrlScanner dat_scanner(dat, dat_file, options);
  dat_scanner.scan();
  KrlScanner src_scanner(src, src_file, options, &dat_scanner);
  src_scanner.scan();
  KrlModuleScan out;
  out.dat = dat_scanner.finish(&src_scanner);
  out.src = src_scanner.finish();
  // The .src's tables started from the .dat's: they hold the module's definitions.
  out.dat.tools = out.src.tools;
  out.dat.frames = out.src.frames;
  out.dat.unknown_frames = out.src.unknown_frames;
  return out;
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
    out += fmt::format("  ; {}\n", v.label()) +
           (v.approach ? fmt::format("  PTP {}\n", axis(v.approach_deg)) : "") +
           fmt::format("  PTP {}\n", axis(v.target_deg));
    if (!v.measure) continue;
    out += fmt::format("  WAIT SEC {:.2f}\n", r.settle_s);
    if (r.hook == MeasurementHook::WaitInput)
      out += fmt::format("  WAIT FOR $IN[{}]\n", r.signal);
    else
      out += fmt::format("  PULSE($OUT[{}], TRUE, 0.5)\n", r.signal);
  }
  return out + "END\n";
}

}  // namespace robcal::detail
