#pragma once
/// \file
/// Error mechanisms (STYLE practice 11): user-input errors are thrown as `InputError` with the
/// place they come from; solver outcomes are returned as status objects, never thrown.

#include <stdexcept>
#include <string>

namespace robcal {

/// Where a piece of user input came from. Empty/zero fields are simply not printed.
struct SourceLocation {
  std::string file;
  int line = 0;     ///< 1-based, 0 when unknown
  int column = 0;   ///< 1-based, 0 when unknown
  std::string key;  ///< YAML key path, CSV column name or CLI flag

  /// "file:line:column (key)" with the unknown parts left out.
  [[nodiscard]] std::string describe() const;
};

/// Bad input from a user: a file, a flag, a value out of range. The message names the place
/// and says what was expected.
class InputError : public std::runtime_error {
 public:
  InputError(const SourceLocation& where, const std::string& what);
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
  [[nodiscard]] const SourceLocation& where() const { return where_; }

 private:
  SourceLocation where_;
};

}  // namespace robcal
