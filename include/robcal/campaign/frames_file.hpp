#pragma once
/// \file
/// Files of `robcal frames`: sweeps read from measurement CSV files (what `robcal import`
/// writes), nest lists, and the estimated frames written into the cell file (`robot_base`
/// block, campaign/cell.hpp) or as a frame block, each with its σ. mm and degrees.

#include <string>
#include <utility>
#include <vector>

#include "robcal/campaign/frames.hpp"
#include "robcal/campaign/instrument_import.hpp"
#include "robcal/measure/measurements.hpp"

namespace robcal::campaign {

/// The sweep of joint `joint` in a points file of one target. Joints are compared as the
/// model's angles (through the robot's joint map: on a Fanuc, J3 follows J2 in a joint-2
/// sweep). \throws InputError naming the file and line of the first row where another joint
/// moved, a second target, or a poses / distances file.
JointSweep sweep_from_measurements(const MeasurementSet& set, int joint, const RobotModel& model);

/// A target's flange coordinates from the rows of a points file (≥ 4 configurations with
/// different orientations), the flange poses given by the nominal model with the base
/// `params` (e.g. Cell::robot_params): tool_point_from_poses with measured points.
/// \throws InputError naming the file for a poses/distances file, rows of several targets or
///   fewer than 4 rows.
PointEstimate tool_point_from_measurements(const RobotModel& model, const ParameterVector& params,
                                           const MeasurementSet& set, double sigma_mm = 0);

/// The `robot_base:` block of a cell file for a measured base, with its σ (YAML, 2-space
/// indent, ending in a newline).
std::string robot_base_block(const FrameEstimate& base);

/// `cell_text` (a cell file) with its top-level `robot_base:` block replaced by
/// robot_base_block(base) and `comment` lines (`# `) put before it; every other line is kept
/// byte for byte. The result is checked by parse_cell. \throws InputError naming `cell_file`
/// when it has no top-level robot_base block or the result does not parse.
std::string cell_with_base(const std::string& cell_text, const std::string& cell_file,
                           const FrameEstimate& base, const std::string& comment);

/// A frame as YAML: `key: {position_mm, rotation_xyz_deg, sigma: {…}, rms_mm}` after `comment`.
std::string frame_yaml(const std::string& key, const FrameEstimate& frame,
                       const std::string& comment);

/// A named point of a nest list, with its line.
struct NamedPoint {
  std::string name;
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();
  int line = 0;
};

/// Named points `name,x,y,z` (mm; any delimiter, decimal mark, comments; a header line with
/// the names name,x,y,z is optional). \throws InputError naming file, line and column.
std::vector<NamedPoint> read_named_points(const NamedText& file);

/// The nests of `measured` and `nominal` paired by name. \throws InputError naming the file
/// and line of a nest the other file does not have, or a name given twice.
FrameEstimate frame_from_named_nests(const NamedText& measured, const NamedText& nominal,
                                     double sigma_mm = 0);

}  // namespace robcal::campaign
