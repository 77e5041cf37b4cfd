#pragma once
/// \file
/// Delimited text as instrument software writes it (SpatialAnalyzer, PolyWorks, CAM2, Leica
/// exports; robot joint logs): a UTF-8 byte-order mark, CR/LF line ends, `#` and `//` comment
/// lines, fields separated by `,` `;` a tab or runs of blanks, optional double quotes around a
/// field, and decimal points or commas. Every field keeps its line and column for messages.
/// (The project's own CSV files use io/csv_fields.hpp; this reader is for foreign files.)

#include <string>
#include <string_view>
#include <vector>

#include "robcal/core/error.hpp"

namespace robcal::campaign {

/// How the fields of a file are written. `0` means "detect from the file".
struct TextDialect {
  char delimiter = 0;  ///< ',', ';', '\t' or ' ' (any run of blanks)
  char decimal = 0;    ///< '.' or ','
};

/// One non-comment line: its 1-based number and fields (quotes removed, blanks trimmed) with
/// the 1-based character column where each starts.
struct TextRow {
  int line = 0;
  std::vector<std::string> fields;
  std::vector<int> columns;
};

struct TextTable {
  std::string file;     ///< for messages
  TextDialect dialect;  ///< as given or detected (never 0 after reading)
  std::vector<TextRow> rows;
};

/// Splits `text` into rows with the given or detected dialect.
/// Delimiter detection: the first of tab, `;`, `,`, blanks that splits every sampled line into
/// the same number (≥ 2) of fields without blanks inside an unquoted comma field. Decimal
/// detection: a comma when the delimiter is not a comma and some field reads as a number
/// with a decimal comma ("12,5"); otherwise a point.
/// \throws InputError naming the file (and line) for an unterminated quote, a decimal comma
///   with a comma delimiter, or a file without any data line.
TextTable read_text_table(std::string_view text, const std::string& file,
                          const TextDialect& dialect = {});

/// The number in `field` written with decimal mark `decimal` (a leading `+` is allowed).
/// \throws InputError at `where` saying what was expected (`expected`, e.g. "a length in mm").
double parse_number(std::string_view field, char decimal, const SourceLocation& where,
                    std::string_view expected);

/// A time as seconds: a plain number (seconds), `hh:mm:ss[.f]` (seconds since midnight) or an
/// ISO-8601 date-time `YYYY-MM-DD[T ]hh:mm:ss[.f]` (seconds since 1970-01-01, no time zone:
/// both files of a join must be in the same zone). Decimal mark as `decimal`.
/// \throws InputError at `where` for anything else.
double parse_time_seconds(std::string_view field, char decimal, const SourceLocation& where);

/// `where` for field `index` of `row` in `table`, with `key` as the column name.
SourceLocation field_location(const TextTable& table, const TextRow& row, size_t index,
                              const std::string& key);

}  // namespace robcal::campaign
