#include "robcal/measure/tcp_warning.hpp"

namespace robcal {

std::optional<std::string> poses_without_tcp_warning(const Tool& tool, const MeasurementSet& data) {
  if (data.kind != MeasurementKind::Poses || tool.tcp_given) return std::nullopt;
  return "POSES WITHOUT A TCP: the tool file has no 'tcp', so the measured poses are taken as "
         "the flange's own frame; if the instrument measures a tool frame, give its pose in the "
         "flange ('tcp: {position_mm: [x, y, z], quaternion_wxyz: [w, x, y, z]}') or 'tcp: ~' "
         "to identify it (6 parameters)";
}

}  // namespace robcal
