#include "robcal/core/error.hpp"

#include <fmt/format.h>

namespace robcal {

std::string SourceLocation::describe() const {
  std::string out = file;
  if (line > 0) {
    out += fmt::format(":{}", line);
    if (column > 0) out += fmt::format(":{}", column);
  }
  if (!key.empty()) out += out.empty() ? key : fmt::format(" ({})", key);
  return out;
}

InputError::InputError(const SourceLocation& where, const std::string& what)
    : std::runtime_error(where.describe().empty() ? what : where.describe() + ": " + what),
      where_(where) {}

}  // namespace robcal
