// ABB RAPID: robtarget and jointtarget literals, declared or written inline.

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>

#include "measurement_writers.hpp"
#include "program_scan.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal::detail {
namespace {

/// An aggregate `[a, b, ...]` read into a flat tree (node 0 the outer list): no recursion
/// and no recursive destruction, however deep the input nests.
struct AggregateNode {
  Token first;  ///< `[` of a list, first token of an element
  bool is_list = false;
  std::vector<size_t> items;  ///< node indices
  NumberField number;         ///< elements that are a (signed) number literal
};
using Aggregate = std::vector<AggregateNode>;

/// RAPID arrays have at most three dimensions (`name{a,b,c}`).
constexpr int kMaxArrayDimensions = 3;

class RapidScanner {
 public:
  RapidScanner(std::string_view text, const std::string& file, const ProgramFilterOptions& options)
      : lexer_(text, ProgramLanguage::Rapid, file), options_(options) {}

  ProgramScan run() {
    Token previous;
    int depth = 0;  // parentheses: routine parameter lists are not statements
    for (;;) {
      const Token t = lexer_.next();
      if (t.kind == TokenKind::End) break;
      if (t.is('(')) ++depth;
      if (t.is(')')) depth = std::max(depth - 1, 0);
      if (t.kind != TokenKind::Identifier) {
        if (t.is('[')) inline_literal(t);
      } else if (iequals(t.text, "CONST") || iequals(t.text, "PERS") || iequals(t.text, "VAR")) {
        declaration();
      } else if (const MoveSpec* spec = move_spec(t.text)) {
        move_instruction(*spec);
      } else if (depth == 0 && procedure_call(previous, t)) {
        other_instruction(t);
      }
      previous = t;
    }
    assign_usages();
    ProgramScan out{std::move(sites_), std::move(tools_), std::move(frames_), {}, {}};
    out.unresolved = std::move(unresolved_);
    return out;
  }

 private:
  // `CONST type name[{dims}] [:= value];` (also routine parameters, which have no value).
  void declaration() {
    const Token type = lexer_.next();
    const Token name = lexer_.next();
    if (type.kind != TokenKind::Identifier || name.kind != TokenKind::Identifier) return;
    int dims = 0;
    if (lexer_.peek().is('{')) {
      dims = 1;
      for (Token t = lexer_.next(); !t.is('}'); t = lexer_.next()) {
        if (t.kind == TokenKind::End) refuse(lexer_.file(), name, "unterminated array size");
        if (t.is(',')) ++dims;
      }
      if (dims > kMaxArrayDimensions)
        refuse(lexer_.file(), name,
               fmt::format("array '{}' has {} dimensions; RAPID allows at most {}", name.text, dims,
                           kMaxArrayDimensions));
    }
    if (lexer_.peek().text != ":=") return;
    lexer_.next();
    const bool robtarget = iequals(type.text, "robtarget");
    const bool jointtarget = options_.joints && iequals(type.text, "jointtarget");
    if ((robtarget || jointtarget) && lexer_.peek().is('[')) {
      const Aggregate& value = aggregate(lexer_.next());
      declared_value(value, 0, dims, std::string(name.text), jointtarget);
      return;
    }
    const bool tooldata = iequals(type.text, "tooldata");
    if ((tooldata || iequals(type.text, "wobjdata")) && dims == 0 && lexer_.peek().is('[')) {
      const Aggregate& value = aggregate(lexer_.next());
      if (tooldata)
        tool_value(value, name);
      else
        wobj_value(value, name);
      return;
    }
    // Any other initialiser (another type, or a copy of another point) stays as written.
    int depth = 0;
    for (;;) {
      const Token t = lexer_.peek();
      if (t.kind == TokenKind::End || (depth == 0 && t.is(';'))) return;
      if (t.is('[') || t.is('(')) ++depth;
      if (t.is(']') || t.is(')')) --depth;
      lexer_.next();
    }
  }

  void declared_value(const Aggregate& tree, size_t node, int dims, const std::string& name,
                      bool joint) {
    const AggregateNode& value = tree[node];
    if (dims == 0) {
      if (joint ? !add_jointtarget(tree, node, name) : !add_robtarget(tree, node, name))
        refuse(lexer_.file(), value.first,
               fmt::format("'{}' is declared {} but its value is not a literal {}", name,
                           joint ? "jointtarget" : "robtarget",
                           joint ? "[[j1,...,j6],[e1,...,e6]]"
                                 : "[[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[e1,...,e6]]"));
      return;
    }
    if (!value.is_list)
      refuse(lexer_.file(), value.first, fmt::format("array '{}': expected an aggregate", name));
    // Recursion bounded by kMaxArrayDimensions.
    for (size_t i = 0; i < value.items.size(); ++i)
      declared_value(tree, value.items[i], dims - 1, fmt::format("{}{{{}}}", name, i + 1), joint);
  }

  // A robtarget or jointtarget written in an instruction (MoveL [[...]], ...; MoveAbsJ).
  void inline_literal(const Token& open) {
    const Aggregate& value = aggregate(open);
    if (looks_like(value, 0, {3, 4, 4, 6})) {
      if (!add_robtarget(value, 0, "")) not_literal(value, "robtarget");
    } else if (options_.joints && looks_like(value, 0, {6, 6})) {
      if (!add_jointtarget(value, 0, "")) not_literal(value, "jointtarget");
    }
  }

  // tooldata [robhold, [[x,y,z],[q1..q4]], loaddata]: the TCP in the flange frame.
  void tool_value(const Aggregate& tree, const Token& name) {
    const auto& it = tree[0].items;
    if (it.size() != 3) return;  // not a literal: the frames file must give it
    if (!tree[it[0]].is_list && iequals(tree[it[0]].first.text, "FALSE"))
      refuse(lexer_.file(), name,
             fmt::format("tool '{}' is stationary (robhold FALSE): targets of a stationary "
                         "tool are not corrected",
                         name.text));
    if (const auto pose = literal_pose(tree, it[1])) tools_[upper(name.text)] = *pose;
  }

  // wobjdata [robhold, ufprog, ufmec, uframe, oframe]: targets are relative to the object
  // frame, which sits at uframe · oframe in the base frame.
  void wobj_value(const Aggregate& tree, const Token& name) {
    const auto& it = tree[0].items;
    if (it.size() != 5) return;
    const auto word = [&](size_t k) { return tree[it[k]].first.text; };
    if (!tree[it[0]].is_list && iequals(word(0), "TRUE"))
      refuse(lexer_.file(), name,
             fmt::format("work object '{}' is held by the robot (robhold TRUE, stationary "
                         "tool): its targets are not corrected",
                         name.text));
    if (!tree[it[1]].is_list && iequals(word(1), "FALSE"))
      refuse(lexer_.file(), name,
             fmt::format("work object '{}' is moved by a mechanical unit (ufprog FALSE): its "
                         "frame is not fixed, its targets are not corrected",
                         name.text));
    const auto user = literal_pose(tree, it[3]);
    const auto object = literal_pose(tree, it[4]);
    if (user && object) frames_[upper(name.text)] = *user * *object;
  }

  // [[x,y,z],[q1,q2,q3,q4]] (pose data); nullopt when not a literal.
  std::optional<Pose<double>> literal_pose(const Aggregate& tree, size_t node) {
    if (!looks_like(tree, node, {3, 4})) return std::nullopt;
    std::vector<NumberField> p, q;
    if (!append_numbers(tree, tree[node].items[0], p) ||
        !append_numbers(tree, tree[node].items[1], q))
      return std::nullopt;
    const Eigen::Quaterniond quat(q[0].value, q[1].value, q[2].value, q[3].value);
    if (std::abs(quat.norm() - 1.0) > 1e-3)
      refuse(lexer_.file(), tree[tree[node].items[1]].first,
             fmt::format("quaternion of norm {:.6f}: expected a unit quaternion", quat.norm()));
    Pose<double> pose;
    pose.p << p[0].value, p[1].value, p[2].value;
    pose.R = quat.normalized().toRotationMatrix();
    return pose;
  }

  /// A motion instruction: which positional arguments are targets, which is the tool.
  struct MoveSpec {
    const char* name;
    std::array<int, 2> targets;  ///< -1: none
    size_t tool;
  };
  static const MoveSpec* move_spec(std::string_view word) {
    static const MoveSpec kSpecs[] = {
        {"MoveL", {0, -1}, 3},     {"MoveJ", {0, -1}, 3},   {"MoveAbsJ", {0, -1}, 3},
        {"MoveLDO", {0, -1}, 3},   {"MoveJDO", {0, -1}, 3}, {"MoveLSync", {0, -1}, 3},
        {"MoveJSync", {0, -1}, 3}, {"MoveC", {0, 1}, 4},    {"MoveCDO", {0, 1}, 4},
        {"MoveCSync", {0, 1}, 4},  {"TriggL", {0, -1}, 4},  {"TriggJ", {0, -1}, 4},
        {"TriggC", {0, 1}, 5},     {"SearchL", {2, -1}, 4}, {"SearchC", {2, 3}, 5},
    };
    for (const MoveSpec& s : kSpecs)
      if (iequals(word, s.name)) return &s;
    return nullptr;
  }

  // The tokens of one statement up to its `;` at bracket depth 0, which is consumed. Each is
  // consumed, then handed to `visit` with the depth it stands at; a `[` is then read as an
  // inline literal (the points written in the statement), brackets change the depth.
  template <typename Visit>
  void statement_tokens(Visit&& visit) {
    int depth = 0;
    for (;;) {
      const Token t = lexer_.peek();
      if (t.kind == TokenKind::End) break;
      if (depth == 0 && t.is(';')) {
        lexer_.next();
        break;
      }
      lexer_.next();
      visit(t, depth);
      if (t.is('[')) {
        inline_literal(t);
      } else if (t.is('(') || t.is('{')) {
        ++depth;
      } else if (t.is(')') || t.is('}')) {
        --depth;
      }
    }
  }

  // `MoveL ToPoint, Speed, Zone, Tool [\WObj:=wobj];`: the points written inline in it take
  // its tool and work object; the names in its target arguments are recorded for their
  // declarations (assign_usages).
  void move_instruction(const MoveSpec& spec) {
    const size_t first_site = sites_.size();
    const int line = lexer_.peek().line;
    int argument = -1;  // the positional argument being read
    bool piece_start = true;
    std::string tool, wobj;
    target_names_.clear();  // identifiers in the target arguments
    const auto is_target = [&] {
      return argument == spec.targets[0] || argument == spec.targets[1];
    };
    statement_tokens([&](const Token& t, int depth) {
      if (piece_start && !t.is('\\') && !t.is(',')) {
        ++argument;
        if (static_cast<size_t>(argument) == spec.tool && t.kind == TokenKind::Identifier)
          tool = upper(t.text);
        piece_start = false;
      }
      if (depth == 0 && t.is(',')) {
        piece_start = true;
      } else if (depth == 0 && t.is('\\')) {
        optional_argument(wobj);
      } else if (t.kind == TokenKind::Identifier && argument >= 0 && is_target()) {
        target_names_.push_back(upper(t.text));
      }
    });
    const std::string frame = upper(wobj);
    for (size_t i = first_site; i < sites_.size(); ++i) {
      sites_[i].point.tool = tool;
      sites_[i].point.frame = frame;
    }
    for (const std::string& name : target_names_) usages_[name].push_back({tool, frame, line});
  }

  static bool keyword(std::string_view word) {
    static constexpr std::string_view kKeywords[] = {
        "AND",     "CASE",    "CONNECT", "DEFAULT",   "DIV",     "DO",       "ELSE",     "ELSEIF",
        "ENDFOR",  "ENDFUNC", "ENDIF",   "ENDMODULE", "ENDPROC", "ENDTEST",  "ENDTRAP",  "ENDWHILE",
        "ERROR",   "EXIT",    "FOR",     "FROM",      "FUNC",    "GOTO",     "IF",       "INOUT",
        "LOCAL",   "MOD",     "MODULE",  "NOT",       "OR",      "PROC",     "RAISE",    "RECORD",
        "RETRY",   "RETURN",  "STEP",    "TASK",      "TEST",    "THEN",     "TO",       "TRAP",
        "TRYNEXT", "UNDO",    "WHILE",   "WITH",      "XOR",     "BACKWARD", "ENDRECORD"};
    for (std::string_view k : kKeywords)
      if (iequals(word, k)) return true;
    return false;
  }

  // `Name argument ...;`: a procedure call (RAPID calls procedures without parentheses), not
  // a keyword, a routine's or module's name, nor the left side of an assignment.
  bool procedure_call(const Token& previous, const Token& name) {
    if (keyword(name.text)) return false;
    if (previous.kind == TokenKind::Identifier &&
        (iequals(previous.text, "PROC") || iequals(previous.text, "FUNC") ||
         iequals(previous.text, "TRAP") || iequals(previous.text, "MODULE") ||
         iequals(previous.text, "RECORD") || iequals(previous.text, "GOTO")))
      return false;
    const Token& next = lexer_.peek();
    return (next.kind == TokenKind::Identifier && !keyword(next.text)) || next.is('[') ||
           next.is('\\') || next.kind == TokenKind::Number || next.kind == TokenKind::String;
  }

  // A procedure call robcal does not know the arguments of (ArcL, SpotL, a user routine): the
  // targets it is given, written inline or by name, may be moved to with any tool, so they are
  // not corrected: refused, or under keep_going left as written and listed (assign_usages).
  void other_instruction(const Token& instruction) {
    const size_t first_site = sites_.size();
    statement_tokens([&](const Token& t, int) {
      if (t.kind == TokenKind::Identifier)
        unknown_uses_[upper(t.text)].push_back({std::string(instruction.text), instruction.line});
    });
    for (size_t i = first_site; i < sites_.size(); ++i)
      other_user_[i] = fmt::format("{} (line {})", instruction.text, instruction.line);
  }

  // `\Name` (a switch) or `\Name:=value`, never a positional argument. The RAPID grammar
  // wants one identifier after the backslash and a value after `:=`; `tool0\\WObj:=w` or
  // `\WObj:=` would otherwise pass and leave the points in the wrong frame. The work object
  // must be a plain name (the frame is looked up by it): anything else (`wobjs{2}`,
  // `wobj1.uframe`) is refused rather than corrected in the base frame.
  void optional_argument(std::string& wobj) {
    const Token option = lexer_.next();
    if (option.kind != TokenKind::Identifier)
      refuse(lexer_.file(), option,
             fmt::format("expected the name of an optional argument after '\\', found '{}'",
                         option.kind == TokenKind::End ? "end of file" : std::string(option.text)));
    if (lexer_.peek().text != ":=") {
      if (iequals(option.text, "WObj"))
        refuse(lexer_.file(), option, "expected \\WObj:=<work object name>");
      return;
    }
    const Token assign = lexer_.next();
    const Token value = lexer_.peek();
    if (value.kind == TokenKind::End || value.is(',') || value.is(';') || value.is('\\'))
      refuse(lexer_.file(), value.kind == TokenKind::End ? assign : value,
             fmt::format("expected a value after '\\{}:='", option.text));
    if (iequals(option.text, "WObj")) {
      const Token& after = lexer_.peek(1);
      if (value.kind != TokenKind::Identifier ||
          !(after.is(',') || after.is(';') || after.is('\\')))
        refuse(lexer_.file(), value,
               "expected the name of a work object after '\\WObj:=' (its frame is looked up "
               "by name)");
      wobj = value.text;
    }
    skip_value();
  }

  // The value of an optional argument: up to the next ',' ';' or '\' outside brackets.
  void skip_value() {
    int depth = 0;
    for (;;) {
      const Token& t = lexer_.peek();
      if (t.kind == TokenKind::End) return;
      if (depth == 0 && (t.is(',') || t.is(';') || t.is('\\'))) return;
      if (t.is('(') || t.is('[') || t.is('{')) ++depth;
      if (t.is(')') || t.is(']') || t.is('}')) --depth;
      lexer_.next();
    }
  }

  // Declared targets take the tool and work object of the instructions that use them; one
  // value cannot be corrected for two of them.
  void assign_usages() {
    const auto label = [](const std::string& name, const char* none) {
      return name.empty() ? std::string(none) : name;
    };
    for (size_t i = 0; i < sites_.size(); ++i) {
      PointSite& site = sites_[i];
      const std::string base = upper(site.point.name.substr(0, site.point.name.find('{')));
      if (const auto other = unknown_uses_.find(base);
          !base.empty() && other != unknown_uses_.end())
        other_user_.try_emplace(i, fmt::format("{} (line {})", other->second.front().instruction,
                                               other->second.front().line));
      if (site.point.name.empty()) continue;
      const auto found = usages_.find(base);
      if (found == usages_.end()) continue;
      const Usage& first = found->second.front();
      for (const Usage& u : found->second)
        if (u.tool != first.tool || u.frame != first.frame)
          throw InputError(
              SourceLocation{lexer_.file(), site.point.line, site.point.column, site.point.name},
              fmt::format("used with tool {} and work object {} (line {}) and with tool {} and "
                          "work object {} (line {}): one corrected value cannot serve both; give "
                          "each use its own target",
                          label(first.tool, "?"), label(first.frame, "WOBJ0"), first.line,
                          label(u.tool, "?"), label(u.frame, "WOBJ0"), u.line));
      site.point.tool = first.tool;
      site.point.frame = first.frame;
    }
    // Targets given to an instruction robcal does not know (other_instruction): not corrected.
    if (other_user_.empty()) return;
    std::vector<PointSite> kept;
    kept.reserve(sites_.size());
    for (size_t i = 0; i < sites_.size(); ++i) {
      const auto other = other_user_.find(i);
      if (other == other_user_.end()) {
        kept.push_back(std::move(sites_[i]));
        continue;
      }
      const ProgramPoint& p = sites_[i].point;
      const SourceLocation where{lexer_.file(), p.line, p.column, p.name};
      const std::string message = fmt::format(
          "{} uses this target; robcal knows the tool argument of MoveL/MoveJ/MoveC/MoveAbsJ "
          "and their DO/Sync/Trigg/Search variants only, so the target is not corrected",
          other->second);
      if (!options_.keep_going)
        throw InputError(where, message + " (--keep-going leaves it as written)");
      unresolved_.push_back({where.describe(), message});
    }
    sites_ = std::move(kept);
  }

  [[noreturn]] void not_literal(const Aggregate& value, const char* what) {
    refuse(lexer_.file(), value[0].first,
           fmt::format("{} whose elements are not all number literals", what));
  }

  // The shape of a literal: a list of lists with these lengths.
  static bool looks_like(const Aggregate& tree, size_t node, std::initializer_list<size_t> sizes) {
    const AggregateNode& value = tree[node];
    if (!value.is_list || value.items.size() != sizes.size()) return false;
    size_t i = 0;
    for (size_t size : sizes) {
      const AggregateNode& item = tree[value.items[i++]];
      if (!item.is_list || item.items.size() != size) return false;
    }
    return true;
  }

  // Appends the numbers of list `node`'s items to `out`; false (out unchanged) when one is not
  // a number literal.
  static bool append_numbers(const Aggregate& tree, size_t node, std::vector<NumberField>& out) {
    for (size_t item : tree[node].items)
      if (tree[item].is_list || !tree[item].number.present) return false;
    for (size_t item : tree[node].items) out.push_back(tree[item].number);
    return true;
  }

  bool add_robtarget(const Aggregate& tree, size_t node, const std::string& name) {
    if (!looks_like(tree, node, {3, 4, 4, 6})) return false;
    const auto& it = tree[node].items;
    PointSite site;
    site.fields.reserve(11);  // x y z, q1..q4, cf1 cf4 cf6 cfx
    for (int part = 0; part < 3; ++part)
      if (!append_numbers(tree, it[part], site.fields)) return false;
    site.point.name = name;
    site.point.line = tree[node].first.line;
    site.point.column = tree[node].first.column;
    site.point.base_T_tcp.p << site.fields[0].value, site.fields[1].value, site.fields[2].value;
    Eigen::Quaterniond q(site.fields[3].value, site.fields[4].value, site.fields[5].value,
                         site.fields[6].value);
    // The controller wants unit quaternions; programs print 5-6 decimals, hence 1e-3.
    if (std::abs(q.norm() - 1.0) > 1e-3)
      refuse(lexer_.file(), tree[it[1]].first,
             fmt::format("quaternion [{},{},{},{}] is not a unit quaternion (norm {:.6f})", q.w(),
                         q.x(), q.y(), q.z(), q.norm()));
    site.point.base_T_tcp.R = q.normalized().toRotationMatrix();
    for (int k = 0; k < 4; ++k) {
      const double cf = site.fields[7 + k].value;
      if (cf != std::round(cf) || std::abs(cf) > 1e6)
        refuse(lexer_.file(), tree[tree[it[2]].items[k]].first,
               "configuration values must be integers");
      site.point.config.push_back(static_cast<int>(cf));
    }
    sites_.push_back(std::move(site));
    return true;
  }

  bool add_jointtarget(const Aggregate& tree, size_t node, const std::string& name) {
    if (!looks_like(tree, node, {6, 6})) return false;
    PointSite site;
    if (!append_numbers(tree, tree[node].items[0], site.fields)) return false;
    site.point.is_joint_target = true;
    site.point.name = name;
    site.point.line = tree[node].first.line;
    site.point.column = tree[node].first.column;
    for (int k = 0; k < 6; ++k) site.point.joints_deg[k] = site.fields[k].value;
    sites_.push_back(std::move(site));
    return true;
  }

  // A node of the aggregate being read, reusing the storage of the previous ones (no
  // allocation per node once a few targets have been read).
  size_t new_node(const Token& first, bool is_list) {
    if (used_nodes_ == nodes_.size()) nodes_.emplace_back();
    AggregateNode& node = nodes_[used_nodes_];
    node.first = first;
    node.is_list = is_list;
    node.items.clear();
    node.number = {};
    return used_nodes_++;
  }

  // Reads `[ item, item, ... ]` after its `[`; items are aggregates or token runs. Iterative:
  // the stack of open lists is a vector, so 30,000 nested `[` cost memory, not the call stack.
  // The tree is valid until the next call (its nodes are reused).
  const Aggregate& aggregate(const Token& open) {
    used_nodes_ = 0;
    new_node(open, true);
    std::vector<size_t>& open_lists = open_lists_;
    open_lists.assign(1, 0);
    bool just_opened = true;
    while (!open_lists.empty()) {
      if (!(just_opened && lexer_.peek().is(']'))) {
        if (lexer_.peek().is('[')) {
          const size_t item = new_node(lexer_.next(), true);
          nodes_[open_lists.back()].items.push_back(item);
          open_lists.push_back(item);
          just_opened = true;
          continue;
        }
        const size_t item = element();
        nodes_[open_lists.back()].items.push_back(item);
      }
      // After an item: `,` starts the next one, `]` closes this list (and maybe the parents).
      just_opened = false;
      for (;;) {
        const Token t = lexer_.next();
        if (t.is(',')) break;
        if (!t.is(']'))
          refuse(lexer_.file(), t.kind == TokenKind::End ? nodes_[open_lists.back()].first : t,
                 t.kind == TokenKind::End ? "aggregate '[' never closed"
                                          : fmt::format("expected ',' or ']', found '{}'", t.text));
        open_lists.pop_back();
        if (open_lists.empty()) break;
      }
    }
    return nodes_;  // nodes past used_nodes_ are stale; only indices from node 0 are followed
  }

  // An element that is not a list: its node.
  size_t element() {
    const Token first = lexer_.peek();
    const size_t node = new_node(first, false);
    NumberField& number_field = nodes_[node].number;
    // A number literal, possibly signed; anything else is an expression kept as written.
    size_t k = 0;
    if (first.is('-') || first.is('+')) k = 1;
    const Token& number = lexer_.peek(k);
    const Token& after = lexer_.peek(k + 1);
    if (number.kind == TokenKind::Number && (after.is(',') || after.is(']'))) {
      number_field.present = true;
      number_field.begin = first.offset;
      number_field.end = number.offset + number.text.size();
      number_field.value = (first.is('-') ? -1.0 : 1.0) * number_value(lexer_.file(), number);
      for (size_t i = 0; i <= k; ++i) lexer_.next();
      return node;
    }
    int depth = 0;
    for (;;) {
      const Token& t = lexer_.peek();
      if (t.kind == TokenKind::End) refuse(lexer_.file(), first, "aggregate never closed");
      if (depth == 0 && (t.is(',') || t.is(']') || t.is(';'))) return node;
      if (t.is('(') || t.is('[') || t.is('{')) ++depth;
      if (t.is(')') || t.is(']') || t.is('}')) --depth;
      lexer_.next();
    }
  }

  struct Usage {
    std::string tool, frame;
    int line = 0;
  };

  ProgramLexer lexer_;
  const ProgramFilterOptions& options_;
  Aggregate nodes_;  ///< the last aggregate read (aggregate()), and spare nodes after it
  size_t used_nodes_ = 0;
  std::vector<size_t> open_lists_;  ///< aggregate()'s stack of open lists
  std::vector<PointSite> sites_;
  std::map<std::string, Pose<double>> tools_, frames_;
  std::unordered_map<std::string, std::vector<Usage>> usages_;  ///< by upper-case target name
  std::vector<std::string> target_names_;                       ///< move_instruction's scratch
  struct OtherUse {
    std::string instruction;
    int line = 0;
  };
  /// Names given to instructions robcal does not know, by upper-case name.
  std::map<std::string, std::vector<OtherUse>> unknown_uses_;
  std::map<size_t, std::string> other_user_;  ///< by site index: the instruction that uses it
  std::vector<UncorrectedPoint> unresolved_;
};

}  // namespace

ProgramScan scan_rapid(std::string_view text, const std::string& file,
                       const ProgramFilterOptions& options) {
  return RapidScanner(text, file, options).run();
}

}  // namespace robcal::detail

// Measurement programs in RAPID. Grammar constraints relied on: module and routine names are
// identifiers of at most 32 characters (a letter, then letters, digits, '_'); a string
// literal holds at most 80 characters (TPWrite); comments run from '!' to the end of the
// line; `num` is a 32-bit float on the controller, so 6 decimals of a joint in degrees are
// more than it keeps (the text carries them so that the plan reads back exactly). Signals
// named in WaitDI / PulseDO must be defined in the controller's I/O configuration.
namespace robcal::detail {

std::string write_rapid_measurement(const MeasurementPart& part) {
  const MeasurementProgramRequest& r = part.request;
  const auto joints = [](const Vector6d& q) {
    return fmt::format(
        "[[{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}],"
        "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]]",
        q[0], q[1], q[2], q[3], q[4], q[5]);
  };
  std::string out = fmt::format("MODULE {}\n", part.program) +
                    header_comment(part, "    !", "reached at a fine point") +
                    fmt::format("    PROC {}_run()\n        VelSet {:g}, 5000;\n", part.program,
                                r.joint_speed_percent);
  const auto move = [&](const Vector6d& q) {
    return fmt::format("        MoveAbsJ {}\\NoEOffs, v1000, fine, tool0;\n", joints(q));
  };
  for (const Visit& v : part.visits) {
    const Vector6d& q = v.target_deg;
    out += fmt::format("        ! {} joints {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f}\n", v.label(),
                       q[0], q[1], q[2], q[3], q[4], q[5]) +
           (v.approach ? move(v.approach_deg) : "") + move(q);
    if (!v.measure) continue;
    out += fmt::format("        WaitTime {:.2f};\n", r.settle_s);
    switch (r.hook) {
      case MeasurementHook::WaitInput:
        out += fmt::format("        WaitDI {}, 1;\n",
                           r.rapid_signal.empty() ? "diRobcalMeasured" : r.rapid_signal);
        break;
      case MeasurementHook::PulseOutput:
        out += fmt::format("        PulseDO \\PLength:=0.5, {};\n",
                           r.rapid_signal.empty() ? "doRobcalMeasure" : r.rapid_signal);
        break;
      case MeasurementHook::LogLine:
        // Two lines: each stays below the 80-character string limit.
        out += fmt::format(
            "        TPWrite \"robcal config {}\";\n"
            "        TPWrite \"joints {:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f}\";\n",
            v.name, q[0], q[1], q[2], q[3], q[4], q[5]);
        break;
    }
  }
  return out + "    ENDPROC\nENDMODULE\n";
}

}  // namespace robcal::detail
