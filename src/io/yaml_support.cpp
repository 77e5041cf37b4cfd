#include "robcal/io/yaml_support.hpp"

#include <fmt/format.h>
#include <cmath>

#include "robcal/io/atomic_file.hpp"

namespace robcal::yaml {

namespace {
std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}
}  // namespace

InputError Node::error(const std::string& what) const {
  SourceLocation where{file, 0, 0, path};
  if (node.IsDefined()) {
    const YAML::Mark mark = node.Mark();
    if (mark.line >= 0) {
      where.line = mark.line + 1;
      where.column = mark.column + 1;
    }
  }
  return InputError(where, what);
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
  const std::string text = node.Scalar();
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used != text.size() || !std::isfinite(value)) throw std::invalid_argument(text);
    return value;
  } catch (const std::exception&) {
    throw error(fmt::format("expected a finite number, got '{}'", text));
  }
}

int Node::as_int() const {
  const double value = as_double();
  if (value != std::floor(value)) throw error(fmt::format("expected an integer, got {}", value));
  return static_cast<int>(value);
}

std::string Node::as_string() const {
  if (!node.IsScalar()) throw error("expected a text value");
  return node.Scalar();
}

std::vector<double> Node::as_doubles(int n) const {
  if (!node.IsSequence())
    throw error(n >= 0 ? fmt::format("expected a list of {} numbers", n) : "expected a list");
  if (n >= 0 && static_cast<int>(node.size()) != n)
    throw error(fmt::format("expected {} numbers, got {}", n, node.size()));
  std::vector<double> out;
  for (size_t i = 0; i < node.size(); ++i) out.push_back(at(i).as_double());
  return out;
}

Eigen::Vector3d Node::as_vector3() const {
  const auto v = as_doubles(3);
  return {v[0], v[1], v[2]};
}

std::vector<std::string> Node::keys() const {
  if (!node.IsMap()) throw error("expected a map");
  std::vector<std::string> out;
  for (const auto& kv : node) out.push_back(kv.first.as<std::string>());
  return out;
}

Node parse(const std::string& text, const std::string& file) {
  try {
    return {YAML::Load(text), file, ""};
  } catch (const YAML::Exception& e) {
    throw InputError({file, e.mark.line + 1, e.mark.column + 1, ""}, "YAML syntax error: " + e.msg);
  }
}

Node load_file(const std::string& path) {
  return parse(read_text_file(path), path);
}

}  // namespace robcal::yaml
