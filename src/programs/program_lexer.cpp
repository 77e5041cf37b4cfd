#include <fmt/format.h>

#include <charconv>

#include "measurement_writers.hpp"
#include "program_scan.hpp"
#include "robcal/core/error.hpp"

namespace robcal::detail {
namespace {

// ASCII classes (what <cctype> gives in the "C" locale, without a call per byte: the lexer
// reads every byte of a 20 MB program twice).
constexpr bool is_digit(char c) {
  return c >= '0' && c <= '9';
}
constexpr bool is_alpha(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}
constexpr bool is_alnum(char c) {
  return is_digit(c) || is_alpha(c);
}
constexpr char ascii_upper(char c) {
  return c >= 'a' && c <= 'z' ? static_cast<char>(c - 32) : c;
}
constexpr bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

}  // namespace

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (ascii_upper(a[i]) != ascii_upper(b[i])) return false;
  return true;
}

std::string upper(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = ascii_upper(c);
  return out;
}

void refuse(const std::string& file, const Token& at, const std::string& message) {
  throw InputError(SourceLocation{file, at.line, at.column, ""}, message);
}

double number_value(const std::string& file, const Token& number) {
  // The whole token must be one decimal literal (digits, one optional point, an optional
  // exponent) whose value is finite: from_chars stops at a second point and reports
  // overflow, neither of which may pass as a prefix or as 0.
  double value = 0;
  const char* first = number.text.data();
  const char* last = first + number.text.size();
  const auto [ptr, ec] = std::from_chars(first, last, value, std::chars_format::general);
  if (ec == std::errc::result_out_of_range)
    refuse(file, number, fmt::format("number '{}' is out of range", number.text));
  if (ec != std::errc() || ptr != last)
    refuse(file, number, fmt::format("malformed number '{}'", number.text));
  return value;
}

NumberField read_number_field(std::string_view text, size_t& at, const std::string& file, int line,
                              size_t line_start) {
  NumberField n;
  n.present = true;
  n.begin = at;
  n.value = read_number(text, at, file, line, line_start);
  n.end = at;
  return n;
}

ProgramLexer::ProgramLexer(std::string_view text, ProgramLanguage language, const std::string& file)
    : text_(text), language_(language), file_(file) {}

Token ProgramLexer::lex_one() {
  const auto at_end = [&] { return pos_ >= text_.size(); };
  const auto ch = [&](size_t k = 0) { return pos_ + k < text_.size() ? text_[pos_ + k] : '\0'; };
  const char comment = language_ == ProgramLanguage::Rapid ? '!' : ';';
  // Skip white space, comments and (KRL) `&` directive lines.
  while (!at_end()) {
    const char c = ch();
    if (c == '\n') {
      ++pos_;
      ++line_;
      line_start_ = pos_;
    } else if (is_space(c)) {
      ++pos_;
    } else if (c == comment ||
               (language_ == ProgramLanguage::Krl && c == '&' && pos_ == line_start_)) {
      while (!at_end() && ch() != '\n') ++pos_;
    } else {
      break;
    }
  }
  Token t;
  t.offset = pos_;
  t.line = line_;
  t.column = static_cast<int>(pos_ - line_start_) + 1;
  if (at_end()) {
    t.kind = TokenKind::End;
    return t;
  }
  const char c = ch();
  const auto ident_char = [&](char x) {
    return is_alnum(x) || x == '_' || (language_ == ProgramLanguage::Krl && x == '$');
  };
  if (is_alpha(c) || c == '_' || (language_ == ProgramLanguage::Krl && (c == '$' || c == '#'))) {
    ++pos_;
    while (!at_end() && ident_char(ch())) ++pos_;
    t.kind = TokenKind::Identifier;
  } else if (is_digit(c) || (c == '.' && is_digit(ch(1)))) {
    // The whole run of characters a number could be made of (`364.35.4`, `1e5x` included),
    // so that number_value() sees a malformed literal whole instead of a valid prefix of it.
    while (!at_end()) {
      const char d = ch();
      // The character before `d` inside this token (the token's first character is a digit or
      // a point, never a sign: nothing before it counts).
      const char before = pos_ > t.offset ? text_[pos_ - 1] : '\0';
      if (is_alnum(d) || d == '.' || d == '_' ||
          ((d == '+' || d == '-') && (before == 'e' || before == 'E')))
        ++pos_;
      else
        break;
    }
    t.kind = TokenKind::Number;
  } else if (c == '"' || (c == '\'' && language_ == ProgramLanguage::Krl)) {
    ++pos_;
    while (!at_end() && ch() != c && ch() != '\n') ++pos_;
    if (ch() != c) {
      t.text = text_.substr(t.offset, 1);
      refuse(file_, t, "unterminated string or bit literal");
    }
    ++pos_;
    t.kind = c == '"' ? TokenKind::String : TokenKind::BitString;
  } else if (c == ':' && ch(1) == '=') {
    pos_ += 2;
    t.kind = TokenKind::Punct;
  } else {
    ++pos_;
    t.kind = TokenKind::Punct;
  }
  t.text = text_.substr(t.offset, pos_ - t.offset);
  return t;
}

}  // namespace robcal::detail
