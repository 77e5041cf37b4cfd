#pragma once
/// \file
/// A poses file read with a tool file that has no `tcp`: the poses are then the flange's own
/// frame. Right for an instrument on the flange, silently wrong for one on a tool, so calibrate
/// and validate both say it.

#include <optional>
#include <string>

#include "robcal/measure/measurements.hpp"
#include "robcal/model/tool.hpp"

namespace robcal {

/// "POSES WITHOUT A TCP: …" with what to write in the tool file, for a poses set whose tool
/// has no `tcp`; nothing otherwise.
std::optional<std::string> poses_without_tcp_warning(const Tool& tool, const MeasurementSet& data);

}  // namespace robcal
