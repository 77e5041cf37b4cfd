#pragma once
/// \file
/// A JSON value written into a YAML emitter, so that a result's one JSON serializer also writes
/// the YAML of a model file: the two forms cannot drift apart.

#include <yaml-cpp/emitter.h>
#include <yaml-cpp/emitterstyle.h>

#include <nlohmann/json.hpp>

namespace robcal {

/// Writes `value` at the emitter's position, its keys in their order (numbers at the emitter's
/// double precision). An object or array at the top is written in `style`; everything nested in
/// it in flow style.
void emit_json(YAML::Emitter& out, const nlohmann::ordered_json& value,
               YAML::EmitterStyle::value style = YAML::EmitterStyle::Flow);

}  // namespace robcal
