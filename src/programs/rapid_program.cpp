// ABB RAPID: robtarget and jointtarget literals, declared or written inline.

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "measurement_writers.hpp"
#include "program_scan.hpp"
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

  std::vector<PointSite> run() {
    for (;;) {
      const Token t = lexer_.next();
      if (t.kind == TokenKind::End) break;
      if (t.kind == TokenKind::Identifier &&
          (iequals(t.text, "CONST") || iequals(t.text, "PERS") || iequals(t.text, "VAR")))
        declaration();
      else if (t.is('\\'))
        optional_argument();
      else if (t.is('['))
        inline_literal(t);
    }
    return std::move(sites_);
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
      const Aggregate value = aggregate(lexer_.next());
      declared_value(value, 0, dims, std::string(name.text), jointtarget);
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
    const Aggregate value = aggregate(open);
    if (looks_like(value, 0, {3, 4, 4, 6})) {
      if (!add_robtarget(value, 0, "")) not_literal(value, "robtarget");
    } else if (options_.joints && looks_like(value, 0, {6, 6})) {
      if (!add_jointtarget(value, 0, "")) not_literal(value, "jointtarget");
    }
  }

  // `\WObj:=name`: targets relative to a work object other than wobj0 are not in the base frame.
  void optional_argument() {
    if (!iequals(lexer_.peek().text, "WObj") || lexer_.peek(1).text != ":=") return;
    const Token object = lexer_.peek(2);
    if (object.kind == TokenKind::Identifier && !iequals(object.text, "wobj0"))
      refuse(lexer_.file(), object,
             fmt::format("targets relative to work object '{}': its frame is not known here; "
                         "convert the targets to wobj0 (the base frame) first",
                         object.text));
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

  // The numbers of list `node`'s items, or an empty vector when one is not a number literal.
  static std::vector<NumberField> numbers(const Aggregate& tree, size_t node) {
    std::vector<NumberField> out;
    for (size_t item : tree[node].items) {
      if (tree[item].is_list || !tree[item].number.present) return {};
      out.push_back(tree[item].number);
    }
    return out;
  }

  bool add_robtarget(const Aggregate& tree, size_t node, const std::string& name) {
    if (!looks_like(tree, node, {3, 4, 4, 6})) return false;
    const auto& it = tree[node].items;
    PointSite site;
    for (int part = 0; part < 3; ++part) {
      const std::vector<NumberField> values = numbers(tree, it[part]);
      if (values.empty()) return false;
      site.fields.insert(site.fields.end(), values.begin(), values.end());
    }
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
    site.fields = numbers(tree, tree[node].items[0]);
    if (site.fields.empty()) return false;
    site.point.is_joint_target = true;
    site.point.name = name;
    site.point.line = tree[node].first.line;
    site.point.column = tree[node].first.column;
    for (int k = 0; k < 6; ++k) site.point.joints_deg[k] = site.fields[k].value;
    sites_.push_back(std::move(site));
    return true;
  }

  // Reads `[ item, item, ... ]` after its `[`; items are aggregates or token runs. Iterative:
  // the stack of open lists is a vector, so 30,000 nested `[` cost memory, not the call stack.
  Aggregate aggregate(const Token& open) {
    Aggregate tree;
    tree.push_back({open, true, {}, {}});
    std::vector<size_t> open_lists{0};
    bool just_opened = true;
    while (!open_lists.empty()) {
      if (!(just_opened && lexer_.peek().is(']'))) {
        const size_t item = tree.size();
        if (lexer_.peek().is('[')) {
          tree.push_back({lexer_.next(), true, {}, {}});
          tree[open_lists.back()].items.push_back(item);
          open_lists.push_back(item);
          just_opened = true;
          continue;
        }
        tree.push_back(element());
        tree[open_lists.back()].items.push_back(item);
      }
      // After an item: `,` starts the next one, `]` closes this list (and maybe the parents).
      just_opened = false;
      for (;;) {
        const Token t = lexer_.next();
        if (t.is(',')) break;
        if (!t.is(']'))
          refuse(lexer_.file(), t.kind == TokenKind::End ? tree[open_lists.back()].first : t,
                 t.kind == TokenKind::End ? "aggregate '[' never closed"
                                          : fmt::format("expected ',' or ']', found '{}'", t.text));
        open_lists.pop_back();
        if (open_lists.empty()) break;
      }
    }
    return tree;
  }

  AggregateNode element() {
    const Token first = lexer_.peek();
    AggregateNode out;
    out.first = first;
    // A number literal, possibly signed; anything else is an expression kept as written.
    size_t k = 0;
    if (first.is('-') || first.is('+')) k = 1;
    const Token& number = lexer_.peek(k);
    const Token& after = lexer_.peek(k + 1);
    if (number.kind == TokenKind::Number && (after.is(',') || after.is(']'))) {
      out.number.present = true;
      out.number.begin = first.offset;
      out.number.end = number.offset + number.text.size();
      out.number.value = (first.is('-') ? -1.0 : 1.0) * number_value(lexer_.file(), number);
      for (size_t i = 0; i <= k; ++i) lexer_.next();
      return out;
    }
    int depth = 0;
    for (;;) {
      const Token& t = lexer_.peek();
      if (t.kind == TokenKind::End) refuse(lexer_.file(), first, "aggregate never closed");
      if (depth == 0 && (t.is(',') || t.is(']') || t.is(';'))) return out;
      if (t.is('(') || t.is('[') || t.is('{')) ++depth;
      if (t.is(')') || t.is(']') || t.is('}')) --depth;
      lexer_.next();
    }
  }

  ProgramLexer lexer_;
  const ProgramFilterOptions& options_;
  std::vector<PointSite> sites_;
};

}  // namespace

std::vector<PointSite> scan_rapid(std::string_view text, const std::string& file,
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
  std::string out = fmt::format(
      "MODULE {0}\n"
      "    ! robcal measurement program, {1}.\n"
      "    ! Each configuration is approached from q - {2:g} deg on every joint (backlash,\n"
      "    ! METHOD 6), reached at a fine point, then the arm settles {3:g} s.\n"
      "    PROC {0}_run()\n"
      "        VelSet {4:g}, 5000;\n",
      part.program, part_description(part), r.approach_deg, r.settle_s, r.joint_speed_percent);
  for (const Visit& v : part.visits) {
    const Vector6d& q = v.target_deg;
    out += fmt::format(
        "        ! {} joints {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f}\n"
        "        MoveAbsJ {}\\NoEOffs, v1000, fine, tool0;\n"
        "        MoveAbsJ {}\\NoEOffs, v1000, fine, tool0;\n"
        "        WaitTime {:.2f};\n",
        v.name, q[0], q[1], q[2], q[3], q[4], q[5], joints(v.approach_deg), joints(q), r.settle_s);
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
