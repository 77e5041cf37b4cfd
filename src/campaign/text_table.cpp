#include "robcal/campaign/text_table.hpp"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cmath>
#include <optional>

namespace robcal::campaign {
namespace {

bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

struct Line {
  int number = 0;
  std::string_view text;
};

/// Non-blank, non-comment lines (BOM removed, CR dropped), with their numbers.
std::vector<Line> content_lines(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  std::vector<Line> lines;
  int number = 0;
  size_t start = 0;
  while (start < text.size()) {
    const size_t newline = text.find('\n', start);
    std::string_view line = text.substr(
        start, newline == std::string_view::npos ? text.size() - start : newline - start);
    start = newline == std::string_view::npos ? text.size() : newline + 1;
    ++number;
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#' || content.substr(0, 2) == "//") continue;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back({number, line});
  }
  return lines;
}

/// Fields of one line split at `delimiter` (' ': runs of blanks), honouring double quotes.
/// Returns std::nullopt for an unterminated quote.
std::optional<TextRow> split(const Line& line, char delimiter) {
  TextRow row;
  row.line = line.number;
  const std::string_view s = line.text;
  size_t i = 0;
  const auto skip_blanks = [&] {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
  };
  if (delimiter == ' ') skip_blanks();
  while (true) {
    if (delimiter != ' ') {
      while (i < s.size() && s[i] == ' ') ++i;
    }
    const int column = static_cast<int>(i) + 1;
    std::string field;
    if (i < s.size() && s[i] == '"') {
      ++i;
      bool closed = false;
      while (i < s.size()) {
        if (s[i] == '"') {
          if (i + 1 < s.size() && s[i + 1] == '"') {
            field += '"';
            i += 2;
            continue;
          }
          closed = true;
          ++i;
          break;
        }
        field += s[i++];
      }
      if (!closed) return std::nullopt;
      // Anything between the closing quote and the delimiter is kept (trimmed).
      const size_t end = delimiter == ' ' ? s.find_first_of(" \t", i) : s.find(delimiter, i);
      field +=
          std::string(trim(s.substr(i, end == std::string_view::npos ? s.size() - i : end - i)));
      i = end == std::string_view::npos ? s.size() : end;
    } else {
      const size_t end = delimiter == ' ' ? s.find_first_of(" \t", i) : s.find(delimiter, i);
      field =
          std::string(trim(s.substr(i, end == std::string_view::npos ? s.size() - i : end - i)));
      i = end == std::string_view::npos ? s.size() : end;
    }
    row.fields.push_back(std::move(field));
    row.columns.push_back(column);
    if (i >= s.size()) break;
    if (delimiter == ' ') {
      skip_blanks();
      if (i >= s.size()) break;
    } else {
      ++i;  // past the delimiter
    }
  }
  return row;
}

/// True when every sampled line splits at `delimiter` into the same number (≥ 2) of fields
/// and, for a comma, no unquoted field holds blanks (a blank-separated file with decimal
/// commas would otherwise pass).
bool splits_consistently(const std::vector<Line>& sample, char delimiter) {
  size_t count = 0;
  for (const Line& line : sample) {
    const auto row = split(line, delimiter);
    if (!row || row->fields.size() < 2) return false;
    if (count != 0 && row->fields.size() != count) return false;
    count = row->fields.size();
    if (delimiter == ',')
      for (size_t f = 0; f < row->fields.size(); ++f)
        if (line.text[static_cast<size_t>(row->columns[f] - 1)] != '"' &&
            row->fields[f].find_first_of(" \t") != std::string::npos)
          return false;
  }
  return count >= 2;
}

/// "12,5", "-0,001", "1,5e-3": a number written with a decimal comma.
bool has_decimal_comma(std::string_view field) {
  const size_t comma = field.find(',');
  if (comma == std::string_view::npos || field.find(',', comma + 1) != std::string_view::npos ||
      field.find('.') != std::string_view::npos)
    return false;
  std::string copy(field);
  copy[comma] = '.';
  if (!copy.empty() && copy.front() == '+') copy.erase(0, 1);
  double value = 0;
  const auto [end, ec] = std::from_chars(copy.data(), copy.data() + copy.size(), value);
  return ec == std::errc() && end == copy.data() + copy.size();
}

std::string delimiter_name(char d) {
  return d == '\t' ? "tab" : d == ' ' ? "blanks" : std::string(1, d);
}

}  // namespace

TextTable read_text_table(std::string_view text, const std::string& file,
                          const TextDialect& dialect) {
  TextTable table;
  table.file = file;
  const std::vector<Line> lines = content_lines(text);
  if (lines.empty())
    throw InputError({file, 0, 0, ""}, "no data lines (only blank or comment lines)");

  table.dialect = dialect;
  if (table.dialect.delimiter == 0) {
    // The header may differ from the data (fewer names), so the sample skips the first line
    // when there are others.
    const size_t first = lines.size() > 1 ? 1 : 0;
    const std::vector<Line> sample(
        lines.begin() + static_cast<long>(first),
        lines.begin() + static_cast<long>(std::min(lines.size(), first + 20)));
    for (const char candidate : {'\t', ';', ',', ' '})
      if (splits_consistently(sample, candidate)) {
        table.dialect.delimiter = candidate;
        break;
      }
    if (table.dialect.delimiter == 0)
      throw InputError({file, sample.front().number, 0, ""},
                       "cannot tell how the fields are separated (tried tab, ';', ',' and "
                       "blanks: the lines split into different numbers of fields); give the "
                       "delimiter");
  }
  for (const Line& line : lines) {
    auto row = split(line, table.dialect.delimiter);
    if (!row) throw InputError({file, line.number, 0, ""}, "unterminated double quote");
    table.rows.push_back(std::move(*row));
  }
  if (table.dialect.decimal == 0) {
    table.dialect.decimal = '.';
    if (table.dialect.delimiter != ',')
      for (const TextRow& row : table.rows)
        for (const std::string& field : row.fields)
          if (has_decimal_comma(field)) table.dialect.decimal = ',';
  }
  if (table.dialect.decimal == ',' && table.dialect.delimiter == ',')
    throw InputError({file, 0, 0, ""},
                     "decimal commas cannot be read in a file whose fields are separated by "
                     "commas: expected ';', tab or blanks as the delimiter");
  if (table.dialect.delimiter != ',' && table.dialect.delimiter != ';' &&
      table.dialect.delimiter != '\t' && table.dialect.delimiter != ' ')
    throw InputError({file, 0, 0, "delimiter"},
                     fmt::format("unknown delimiter '{}': expected ',', ';', tab or blanks",
                                 delimiter_name(table.dialect.delimiter)));
  return table;
}

double parse_number(std::string_view field, char decimal, const SourceLocation& where,
                    std::string_view expected) {
  std::string text(field);
  if (text.empty()) throw InputError(where, fmt::format("empty field: expected {}", expected));
  if (decimal == ',') {
    if (text.find('.') != std::string::npos)
      throw InputError(where, fmt::format("'{}' has a decimal point but the file uses decimal "
                                          "commas: expected {}",
                                          field, expected));
    for (char& c : text)
      if (c == ',') c = '.';
  }
  std::string_view digits = text;
  if (digits.front() == '+') digits.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (end != digits.data() + digits.size() || digits.empty() ||
      (ec != std::errc() && ec != std::errc::result_out_of_range))
    throw InputError(where, fmt::format("'{}' is not a number: expected {}", field, expected));
  if (ec == std::errc::result_out_of_range || !std::isfinite(value))
    throw InputError(where, fmt::format("'{}' is not finite: expected {}", field, expected));
  return value;
}

namespace {

/// Days from 1970-01-01 to a proleptic Gregorian date (Howard Hinnant's days_from_civil).
long days_from_civil(long y, unsigned m, unsigned d) {
  y -= m <= 2;
  const long era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<long>(doe) - 719468;
}

/// Whole number in s[pos, pos+width), or -1.
long digits_at(std::string_view s, size_t pos, size_t width) {
  if (pos + width > s.size()) return -1;
  long value = 0;
  for (size_t i = pos; i < pos + width; ++i) {
    if (s[i] < '0' || s[i] > '9') return -1;
    value = value * 10 + (s[i] - '0');
  }
  return value;
}

}  // namespace

double parse_time_seconds(std::string_view field, char decimal, const SourceLocation& where) {
  const std::string_view expected =
      "a time: seconds, hh:mm:ss[.f] or YYYY-MM-DD hh:mm:ss[.f] (ISO 8601)";
  if (field.find(':') == std::string_view::npos)
    return parse_number(field, decimal, where, expected);
  long day = 0;
  std::string_view clock = field;
  if (field.size() > 10 && field[4] == '-' && field[7] == '-' &&
      (field[10] == 'T' || field[10] == ' ')) {
    const long y = digits_at(field, 0, 4), m = digits_at(field, 5, 2), d = digits_at(field, 8, 2);
    if (y < 0 || m < 1 || m > 12 || d < 1 || d > 31)
      throw InputError(where,
                       fmt::format("'{}' is not a valid date: expected {}", field, expected));
    day = days_from_civil(y, static_cast<unsigned>(m), static_cast<unsigned>(d));
    clock = field.substr(11);
  }
  const long h = digits_at(clock, 0, 2), mi = digits_at(clock, 3, 2);
  if (clock.size() < 8 || h < 0 || h > 23 || clock[2] != ':' || mi < 0 || mi > 59 ||
      clock[5] != ':')
    throw InputError(where, fmt::format("'{}' is not a time: expected {}", field, expected));
  std::string_view seconds_text = clock.substr(6);
  if (!seconds_text.empty() && seconds_text.back() == 'Z') seconds_text.remove_suffix(1);
  const double seconds = parse_number(seconds_text, decimal, where, expected);
  if (seconds < 0 || seconds >= 61)
    throw InputError(where,
                     fmt::format("'{}' has seconds out of range: expected {}", field, expected));
  return static_cast<double>(day) * 86400.0 + static_cast<double>(h * 3600 + mi * 60) + seconds;
}

SourceLocation field_location(const TextTable& table, const TextRow& row, size_t index,
                              const std::string& key) {
  return {table.file, row.line, index < row.columns.size() ? row.columns[index] : 0, key};
}

}  // namespace robcal::campaign
