// ABB RAPID: robtarget and jointtarget literals, declared or written inline.

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <charconv>
#include <cmath>
#include <string>

#include "program_scan.hpp"
#include "robcal/core/units.hpp"

namespace robcal::detail {
namespace {

/// An aggregate `[a, b, ...]` or one of its elements.
struct Aggregate {
  Token first;  ///< `[` of an aggregate, first token of an element
  bool is_list = false;
  std::vector<Aggregate> items;
  NumberField number;  ///< elements that are a (signed) number literal
};

double parse_double(std::string_view text) {
  double value = 0;
  std::from_chars(text.data(), text.data() + text.size(), value);
  return value;
}

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
    }
    if (lexer_.peek().text != ":=") return;
    lexer_.next();
    const bool robtarget = iequals(type.text, "robtarget");
    const bool jointtarget = options_.joints && iequals(type.text, "jointtarget");
    if ((robtarget || jointtarget) && lexer_.peek().is('[')) {
      const Aggregate value = aggregate(lexer_.next());
      declared_value(value, dims, std::string(name.text), jointtarget);
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

  void declared_value(const Aggregate& value, int dims, const std::string& name, bool joint) {
    if (dims == 0) {
      if (joint ? !add_jointtarget(value, name) : !add_robtarget(value, name))
        refuse(lexer_.file(), value.first,
               fmt::format("'{}' is declared {} but its value is not a literal {}", name,
                           joint ? "jointtarget" : "robtarget",
                           joint ? "[[j1,...,j6],[e1,...,e6]]"
                                 : "[[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[e1,...,e6]]"));
      return;
    }
    if (!value.is_list)
      refuse(lexer_.file(), value.first, fmt::format("array '{}': expected an aggregate", name));
    for (size_t i = 0; i < value.items.size(); ++i)
      declared_value(value.items[i], dims - 1, fmt::format("{}{{{}}}", name, i + 1), joint);
  }

  // A robtarget or jointtarget written in an instruction (MoveL [[...]], ...; MoveAbsJ).
  void inline_literal(const Token& open) {
    const Aggregate value = aggregate(open);
    if (looks_like(value, {3, 4, 4, 6})) {
      if (!add_robtarget(value, "")) not_literal(value, "robtarget");
    } else if (options_.joints && looks_like(value, {6, 6})) {
      if (!add_jointtarget(value, "")) not_literal(value, "jointtarget");
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
    refuse(lexer_.file(), value.first,
           fmt::format("{} whose elements are not all number literals", what));
  }

  // The shape of a literal: a list of lists with these lengths.
  static bool looks_like(const Aggregate& value, std::initializer_list<size_t> sizes) {
    if (!value.is_list || value.items.size() != sizes.size()) return false;
    size_t i = 0;
    for (size_t size : sizes) {
      const Aggregate& item = value.items[i++];
      if (!item.is_list || item.items.size() != size) return false;
    }
    return true;
  }

  static bool all_numbers(const Aggregate& list, size_t count) {
    for (size_t i = 0; i < count; ++i)
      if (list.items[i].is_list || !list.items[i].number.present) return false;
    return true;
  }

  bool add_robtarget(const Aggregate& value, const std::string& name) {
    if (!looks_like(value, {3, 4, 4, 6})) return false;
    const auto& it = value.items;
    if (!all_numbers(it[0], 3) || !all_numbers(it[1], 4) || !all_numbers(it[2], 4)) return false;
    PointSite site;
    site.point.name = name;
    site.point.line = value.first.line;
    site.point.column = value.first.column;
    for (int k = 0; k < 3; ++k) site.fields.push_back(it[0].items[k].number);
    for (int k = 0; k < 4; ++k) site.fields.push_back(it[1].items[k].number);
    for (int k = 0; k < 4; ++k) site.fields.push_back(it[2].items[k].number);
    site.point.base_T_tcp.p << site.fields[0].value, site.fields[1].value, site.fields[2].value;
    Eigen::Quaterniond q(site.fields[3].value, site.fields[4].value, site.fields[5].value,
                         site.fields[6].value);
    // The controller wants unit quaternions; programs print 5-6 decimals, hence 1e-3.
    if (std::abs(q.norm() - 1.0) > 1e-3)
      refuse(lexer_.file(), it[1].first,
             fmt::format("quaternion [{},{},{},{}] is not a unit quaternion (norm {:.6f})", q.w(),
                         q.x(), q.y(), q.z(), q.norm()));
    site.point.base_T_tcp.R = q.normalized().toRotationMatrix();
    for (int k = 0; k < 4; ++k) {
      const double cf = site.fields[7 + k].value;
      if (cf != std::round(cf))
        refuse(lexer_.file(), it[2].items[k].first, "configuration values must be integers");
      site.point.config.push_back(static_cast<int>(cf));
    }
    sites_.push_back(std::move(site));
    return true;
  }

  bool add_jointtarget(const Aggregate& value, const std::string& name) {
    if (!looks_like(value, {6, 6}) || !all_numbers(value.items[0], 6)) return false;
    PointSite site;
    site.point.is_joint_target = true;
    site.point.name = name;
    site.point.line = value.first.line;
    site.point.column = value.first.column;
    for (int k = 0; k < 6; ++k) {
      site.fields.push_back(value.items[0].items[k].number);
      site.point.joints_deg[k] = site.fields.back().value;
    }
    sites_.push_back(std::move(site));
    return true;
  }

  // Reads `[ item, item, ... ]` after its `[`; items are aggregates or token runs.
  Aggregate aggregate(const Token& open) {
    Aggregate out;
    out.first = open;
    out.is_list = true;
    if (lexer_.peek().is(']')) {
      lexer_.next();
      return out;
    }
    for (;;) {
      out.items.push_back(element());
      const Token t = lexer_.next();
      if (t.is(']')) return out;
      if (!t.is(','))
        refuse(lexer_.file(), t.kind == TokenKind::End ? open : t,
               t.kind == TokenKind::End ? "aggregate '[' never closed"
                                        : fmt::format("expected ',' or ']', found '{}'", t.text));
    }
  }

  Aggregate element() {
    const Token first = lexer_.peek();
    if (first.is('[')) return aggregate(lexer_.next());
    Aggregate out;
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
      out.number.value = (first.is('-') ? -1.0 : 1.0) * parse_double(number.text);
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
