#pragma once
/// \file
/// What a YAML reader checks beyond the syntax: no unknown key (a typo would silently drop a
/// field), numbers within each field's plausible range (a unit slip or a typo is refused, with
/// the range stated).

#include <Eigen/Core>
#include <initializer_list>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "robcal/io/yaml_support.hpp"

namespace robcal::yaml {

/// The plausible values of a field, stated in the error when a value falls outside.
struct Range {
  double lower = -std::numeric_limits<double>::max();
  double upper = std::numeric_limits<double>::max();
  const char* unit = "";
};

/// A finite number within `range`, else InputError located at the node.
double number_in(const Node& node, const Range& range);
/// A list of exactly `n` such numbers.
std::vector<double> numbers_in(const Node& node, int n, const Range& range);
Eigen::Vector3d vector3_in(const Node& node, const Range& range);

/// Refuses a map key not in `known`, located at the key, with the nearest known key as a
/// suggestion ("masess" → "did you mean 'masses'?").
void expect_keys(const Node& map, std::initializer_list<std::string_view> known);

/// The entry of `known` nearest to `word` by edit distance when it is close enough to be a
/// typo of it, else empty.
std::string nearest_word(std::string_view word, std::initializer_list<std::string_view> known);

}  // namespace robcal::yaml
