#pragma once
/// \file
/// The world frame from table nests (`robcal frames world`, campaign/frames.hpp
/// frame_from_nests) applied to measurements: readings the instrument took in its own frame,
/// expressed in the frame of the nests (the robot's world), as the identification expects them.

#include <string>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/measure/measurements.hpp"

namespace robcal::campaign {

/// The set expressed in the frame F, given instrument_T_F: every measured position
/// m_F = F_T_instrument·m, every measured orientation R_F = F_R_instrument·R; distance rows
/// are unchanged (a length has no frame). Joints, names and lines are kept.
MeasurementSet measurements_in_frame(const MeasurementSet& set,
                                     const Pose<double>& instrument_T_frame);

/// instrument_T_F from the `frame:` block of a file `robcal frames world` wrote
/// (position_mm, rotation_xyz_deg: R = Rx(α)·Ry(β)·Rz(γ)). \throws InputError naming the file,
/// line and key when the block or one of its entries is missing or not three numbers.
Pose<double> parse_world_frame(const std::string& yaml_text, const std::string& file);
Pose<double> load_world_frame(const std::string& path);

/// The comment line of a measurement file whose positions are in the world frame of the frame
/// file `file` (session, import): says which frame, so the file is not taken for raw readings.
std::string world_frame_comment(const std::string& file);

}  // namespace robcal::campaign
