#pragma once
/// \file
/// Reading YAML with errors that name the file, line, column and key (yaml-cpp marks).
/// Every YAML reader of the project goes through these helpers.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "robcal/core/error.hpp"

namespace robcal::yaml {

/// A node together with the file it came from and its key path, for error messages.
struct Node {
  YAML::Node node;
  std::string file;
  std::string path;  ///< e.g. "masses.2.cog_mm"

  [[nodiscard]] bool has(const std::string& key) const;
  /// The child `key`; throws InputError "missing key" when absent.
  [[nodiscard]] Node at(const std::string& key) const;
  /// The child `key`, or an undefined node when absent (check with `defined()`).
  [[nodiscard]] Node get(const std::string& key) const;
  [[nodiscard]] Node at(size_t index) const;
  [[nodiscard]] bool defined() const { return node.IsDefined() && !node.IsNull(); }
  [[nodiscard]] size_t size() const { return node.size(); }

  [[nodiscard]] double as_double() const;  ///< finite number or InputError
  [[nodiscard]] int as_int() const;
  [[nodiscard]] std::string as_string() const;
  /// A sequence of exactly `n` finite numbers (n < 0: any length).
  [[nodiscard]] std::vector<double> as_doubles(int n = -1) const;
  [[nodiscard]] Eigen::Vector3d as_vector3() const;
  /// Keys of a map, in file order.
  [[nodiscard]] std::vector<std::string> keys() const;

  /// An InputError located at this node ("file:line:col (path): what").
  [[nodiscard]] InputError error(const std::string& what) const;
};

/// Parses YAML text; `file` names it in errors. Syntax errors carry yaml-cpp's line/column.
Node parse(const std::string& text, const std::string& file);
/// Loads and parses a YAML file.
Node load_file(const std::string& path);

}  // namespace robcal::yaml
