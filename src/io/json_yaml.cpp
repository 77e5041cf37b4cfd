#include "robcal/io/json_yaml.hpp"

#include <yaml-cpp/yaml.h>

namespace robcal {

void emit_json(YAML::Emitter& out, const nlohmann::ordered_json& value,
               YAML::EmitterStyle::value style) {
  const YAML::EMITTER_MANIP group = style == YAML::EmitterStyle::Block ? YAML::Block : YAML::Flow;
  switch (value.type()) {
    case nlohmann::ordered_json::value_t::object:
      out << group << YAML::BeginMap;
      for (const auto& [key, item] : value.items()) {
        out << YAML::Key << key << YAML::Value;
        emit_json(out, item);
      }
      out << YAML::EndMap;
      return;
    case nlohmann::ordered_json::value_t::array:
      out << group << YAML::BeginSeq;
      for (const nlohmann::ordered_json& item : value) emit_json(out, item);
      out << YAML::EndSeq;
      return;
    case nlohmann::ordered_json::value_t::boolean:
      out << value.get<bool>();
      return;
    case nlohmann::ordered_json::value_t::number_integer:
      out << value.get<long long>();
      return;
    case nlohmann::ordered_json::value_t::number_unsigned:
      out << value.get<unsigned long long>();
      return;
    case nlohmann::ordered_json::value_t::number_float:
      out << value.get<double>();
      return;
    case nlohmann::ordered_json::value_t::string:
      out << value.get<std::string>();
      return;
    default:
      out << YAML::Null;
  }
}

}  // namespace robcal
