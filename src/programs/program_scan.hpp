#pragma once
// Private to program filtering: a streaming lexer for RAPID and KRL text and the record of
// where each point's numbers sit in the text, so that only those bytes are rewritten.

#include <array>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "robcal/programs/program_filter.hpp"

namespace robcal::detail {

enum class TokenKind { Identifier, Number, BitString, String, Punct, End };

struct Token {
  TokenKind kind = TokenKind::End;
  std::string_view text;
  size_t offset = 0;
  int line = 0;
  int column = 0;
  [[nodiscard]] bool is(char punct) const {
    return kind == TokenKind::Punct && text.size() == 1 && text[0] == punct;
  }
};

/// Case-insensitive comparison (RAPID and KRL keywords and names are case-insensitive).
bool iequals(std::string_view a, std::string_view b);

/// Tokens on demand with look-ahead; comments (RAPID `!`, KRL `;` and `&` directives) and
/// white space are skipped. Memory stays small for programs with 100,000 points.
class ProgramLexer {
 public:
  /// The most tokens peek() looks ahead (the scanners look at most six ahead).
  static constexpr size_t kMaxLookAhead = 16;
  ProgramLexer(std::string_view text, ProgramLanguage language, const std::string& file);
  /// The token `ahead` after the next one; the reference stays valid until that token has been
  /// consumed by next() and kMaxLookAhead more have been read. Forced inline, as next(): the
  /// scanners call them several times per token (GCC keeps them out of line otherwise).
  [[gnu::always_inline]] const Token& peek(size_t ahead = 0) {
    if (ahead >= kMaxLookAhead) throw std::logic_error("program lexer: look-ahead too far");
    for (; count_ <= ahead; ++count_) ahead_[(first_ + count_) % kMaxLookAhead] = lex_one();
    return ahead_[(first_ + ahead) % kMaxLookAhead];
  }
  [[gnu::always_inline]] Token next() {
    if (count_ == 0) return lex_one();
    const Token& t = ahead_[first_];
    first_ = (first_ + 1) % kMaxLookAhead;
    --count_;
    return t;
  }
  [[nodiscard]] const std::string& file() const { return file_; }

 private:
  Token lex_one();
  std::string_view text_;
  ProgramLanguage language_;
  std::string file_;
  size_t pos_ = 0;
  int line_ = 1;
  size_t line_start_ = 0;
  // Look-ahead ring: tokens [first_, first_ + count_) modulo its size; no allocation per token
  // (a deque allocates and frees a block every few tokens: 2 % of a 100,000-target filter).
  std::array<Token, kMaxLookAhead> ahead_{};
  size_t first_ = 0, count_ = 0;
};

/// A number in the text: its byte range, value, and how it is written.
struct NumberField {
  bool present = false;
  size_t begin = 0;
  size_t end = 0;
  double value = 0;
  int binary_digits = 0;  ///< KRL 'B0101' literal: its digit count; 0 for decimal
};

/// A point and where its numbers are. Field order: RAPID robtarget x y z q1 q2 q3 q4 cf1 cf4
/// cf6 cfx; KRL position X Y Z A B C S T; joint targets j1..j6.
struct PointSite {
  ProgramPoint point;
  std::vector<NumberField> fields;
  /// Non-empty when the scanner took the point's tool or frame on an assumption the program
  /// does not confirm: what it assumed (listed in ProgramFilterResult::assumed).
  std::string assumption;
};

/// What a scan finds: the points, and the tools (flange_T_tcp) and frames (base_T_frame) the
/// program defines with literal values, by upper-case name.
struct ProgramScan {
  std::vector<PointSite> sites;
  std::map<std::string, Pose<double>> tools;
  std::map<std::string, Pose<double>> frames;
  /// Under keep_going: uses of points the scan cannot resolve (KRL: a name declared in neither
  /// file of the module), listed with the uncorrected points.
  std::vector<UncorrectedPoint> unresolved;
  /// Tool and frame names the program makes active but whose value the scan cannot know, by
  /// upper-case name, with why (KRL: `$TOOL` set to an expression, a FRAME given two values or
  /// changed component-wise): a point under one is refused with this reason.
  std::map<std::string, std::string> unknown_frames;
};

/// A KUKA module: its .src and its .dat, each with the tools and frames of both.
struct KrlModuleScan {
  ProgramScan src, dat;
};

ProgramScan scan_rapid(std::string_view text, const std::string& file,
                       const ProgramFilterOptions& options);
ProgramScan scan_krl(std::string_view text, const std::string& file,
                     const ProgramFilterOptions& options);
/// The .dat first (declarations, FDATs, FRAMEs), then the .src with them: each .dat point takes
/// the tool and base of the .src motions that use it (refused when they differ).
KrlModuleScan scan_krl_module(std::string_view src, std::string_view dat,
                              const std::string& src_file, const std::string& dat_file,
                              const ProgramFilterOptions& options);
/// Fanuc LS: the /POS positions of group 1, X Y Z W P R (Cartesian, config = flip, down,
/// back, t4, t5, t6 from CONFIG) or J1..J6 (joint); tool UT[n], frame UF[n].
ProgramScan scan_ls(std::string_view text, const std::string& file,
                    const ProgramFilterOptions& options);
/// Yaskawa JBI: the C positions of //POS, pulses (joint) or Cartesian (config = RCONF l..q);
/// tool TOOL[n], frame USER[n] (ROBOT and BASE: the base frame).
ProgramScan scan_jbi(std::string_view text, const std::string& file,
                     const ProgramFilterOptions& options);
/// URScript: pose literals of motions and assignments (m, rotation vector), tool from set_tcp
/// at the motion; with `joints`, movej joint lists (rad).
ProgramScan scan_urscript(std::string_view text, const std::string& file,
                          const ProgramFilterOptions& options);

/// Upper case (RAPID and KRL names are case-insensitive).
std::string upper(std::string_view text);

/// The value of a Number token, which must be one whole finite decimal literal: `364.35.4`,
/// `1e999` and `12abc` are InputErrors at the token.
double number_value(const std::string& file, const Token& number);

/// A number literal at `text[at]` (read_number: whole and finite, else InputError at
/// file:line:column) with its byte range; advances `at` past it.
NumberField read_number_field(std::string_view text, size_t& at, const std::string& file, int line,
                              size_t line_start);

/// InputError at a token.
[[noreturn]] void refuse(const std::string& file, const Token& at, const std::string& message);

}  // namespace robcal::detail
