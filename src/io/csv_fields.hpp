#pragma once
// Splitting one line of the project's CSV files (names and numbers only: no quoting), shared by
// the measurement and pose-list readers.

#include <string_view>
#include <vector>

namespace robcal::csv {

/// `s` without blanks (space, tab, CR) at either end.
inline std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

/// The comma-separated fields of `line`, each trimmed; `columns`, when given, receives the
/// 1-based character column in `line` where each field starts (for error messages).
inline std::vector<std::string_view> split_fields(std::string_view line,
                                                  std::vector<int>* columns = nullptr) {
  std::vector<std::string_view> fields;
  if (columns) columns->clear();
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (columns) columns->push_back(static_cast<int>(start) + 1);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

/// `text` without the UTF-8 byte-order mark that Excel writes at the start of a CSV file.
inline std::string_view without_bom(std::string_view text) {
  constexpr std::string_view kBom = "\xEF\xBB\xBF";
  return text.substr(0, kBom.size()) == kBom ? text.substr(kBom.size()) : text;
}

}  // namespace robcal::csv
