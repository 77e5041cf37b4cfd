#include "robcal/io/yaml_support.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "robcal/io/atomic_file.hpp"
#include "robcal/io/number_text.hpp"
#include "robcal/io/yaml_checks.hpp"

namespace robcal::yaml {

namespace {
std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

SourceLocation locate(const YAML::Mark& mark, const std::string& file, const std::string& path) {
  SourceLocation where{file, 0, 0, path};
  if (mark.line >= 0) {
    where.line = mark.line + 1;
    where.column = mark.column + 1;
  }
  return where;
}

std::string describe_range(const Range& range) {
  const char* space = *range.unit ? " " : "";
  return fmt::format("[{}, {}]{}{}", range.lower, range.upper, space, range.unit);
}

size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitution});
    }
  }
  return row[b.size()];
}

/// Refuses a key given twice in any map of the document. The walk keeps its own stack: the
/// depth of a document is the author's choice, not ours to recurse on.
void reject_duplicate_keys(const YAML::Node& root, const std::string& file) {
  std::vector<std::pair<YAML::Node, std::string>> pending{{root, ""}};
  // An alias shares its anchor's node (same mark): each collection is checked once, so that
  // nested aliases cannot make the walk exponential.
  std::set<std::pair<int, int>> visited;
  while (!pending.empty()) {
    auto [node, path] = std::move(pending.back());
    pending.pop_back();
    if ((node.IsSequence() || node.IsMap()) &&
        !visited.emplace(node.Mark().line, node.Mark().column).second)
      continue;
    if (node.IsSequence()) {
      for (size_t i = 0; i < node.size(); ++i)
        pending.emplace_back(node[i], fmt::format("{}[{}]", path, i));
    } else if (node.IsMap()) {
      std::map<std::string, int> first_line;
      for (const auto& kv : node) {
        if (!kv.first.IsScalar())
          throw InputError(locate(kv.first.Mark(), file, path),
                           "expected a plain key (a name), found a list or map as key");
        const std::string key = kv.first.Scalar();
        const auto [it, inserted] = first_line.emplace(key, kv.first.Mark().line + 1);
        if (!inserted)
          throw InputError(
              locate(kv.first.Mark(), file, join(path, key)),
              fmt::format("key '{}' given twice in this map (first on line {})", key, it->second));
        pending.emplace_back(kv.second, join(path, key));
      }
    }
  }
}

}  // namespace

std::string nearest_word(std::string_view word, std::initializer_list<std::string_view> known) {
  std::string best;
  size_t best_distance = std::string::npos;
  for (const std::string_view candidate : known) {
    const size_t d = edit_distance(word, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  // A typo changes a few letters; beyond a third of the word it is another word.
  return best_distance <= std::max<size_t>(2, word.size() / 3) ? best : std::string();
}

InputError Node::error(const std::string& what) const {
  if (!node.IsDefined()) return InputError({file, 0, 0, path}, what);
  return InputError(locate(node.Mark(), file, path), what);
}

bool Node::has(const std::string& key) const {
  return node.IsMap() && node[key].IsDefined() && !node[key].IsNull();
}

Node Node::get(const std::string& key) const {
  if (!node.IsMap()) throw error(fmt::format("expected a map with key '{}'", key));
  return {node[key], file, join(path, key)};
}

Node Node::at(const std::string& key) const {
  Node child = get(key);
  if (!child.defined()) throw error(fmt::format("missing key '{}'", key));
  return child;
}

Node Node::at(size_t index) const {
  if (!node.IsSequence() || index >= node.size())
    throw error(fmt::format("expected a list with at least {} entries", index + 1));
  return {node[index], file, fmt::format("{}[{}]", path, index)};
}

double Node::as_double() const {
  if (!node.IsScalar()) throw error("expected a number");
  const std::string& text = node.Scalar();
  const std::optional<double> value = parse_number(text);
  if (!value) throw error(describe_bad_number(text));
  return *value;
}

int Node::as_int() const {
  const double value = as_double();
  if (value != std::floor(value) || std::abs(value) > std::numeric_limits<int>::max())
    throw error(fmt::format("expected an integer, got {}", node.Scalar()));
  return static_cast<int>(value);
}

std::string Node::as_string() const {
  if (!node.IsScalar()) throw error("expected a text value");
  return node.Scalar();
}

std::vector<double> Node::as_doubles(int n) const {
  return numbers_in(*this, n, Range{});
}

Eigen::Vector3d Node::as_vector3() const {
  return vector3_in(*this, Range{});
}

std::vector<std::string> Node::keys() const {
  if (!node.IsMap()) throw error("expected a map");
  std::vector<std::string> out;
  for (const auto& kv : node) out.push_back(kv.first.Scalar());
  return out;
}

double number_in(const Node& node, const Range& range) {
  const double value = node.as_double();
  if (value < range.lower || value > range.upper)
    throw node.error(fmt::format("{} is outside the plausible range {}", node.node.Scalar(),
                                 describe_range(range)));
  return value;
}

std::vector<double> numbers_in(const Node& node, int n, const Range& range) {
  if (!node.node.IsSequence())
    throw node.error(n >= 0 ? fmt::format("expected a list of {} numbers", n) : "expected a list");
  if (n >= 0 && static_cast<int>(node.size()) != n)
    throw node.error(fmt::format("expected {} numbers, got {}", n, node.size()));
  std::vector<double> out;
  for (size_t i = 0; i < node.size(); ++i) out.push_back(number_in(node.at(i), range));
  return out;
}

Eigen::Vector3d vector3_in(const Node& node, const Range& range) {
  const auto v = numbers_in(node, 3, range);
  return {v[0], v[1], v[2]};
}

void expect_keys(const Node& map, std::initializer_list<std::string_view> known) {
  if (!map.node.IsMap()) throw map.error("expected a map");
  for (const auto& kv : map.node) {
    const std::string key = kv.first.Scalar();
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string expected;
    for (const std::string_view k : known)
      expected += fmt::format("{}{}", expected.empty() ? "" : ", ", k);
    const std::string suggestion = nearest_word(key, known);
    throw InputError(locate(kv.first.Mark(), map.file, join(map.path, key)),
                     suggestion.empty()
                         ? fmt::format("unknown key '{}' (expected one of: {})", key, expected)
                         : fmt::format("unknown key '{}': did you mean '{}'? (expected one of: {})",
                                       key, suggestion, expected));
  }
}

Node parse(const std::string& text, const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError({file, e.mark.line + 1, e.mark.column + 1, ""}, "YAML syntax error: " + e.msg);
  }
  reject_duplicate_keys(root, file);
  return {root, file, ""};
}

Node load_file(const std::string& path) {
  return parse(read_text_file(path), path);
}

}  // namespace robcal::yaml
