#pragma once
/// \file
/// Robot and tool files (YAML, mm and degrees). The formats are documented in the README;
/// `data/robots/*.yaml` are the built-in robots.

#include <filesystem>
#include <string>
#include <vector>

#include "robcal/io/yaml_support.hpp"
#include "robcal/model/robot_model.hpp"
#include "robcal/model/tool.hpp"

namespace robcal {

/// The folder with the built-in data: $ROBCAL_DATA_DIR if set, else the first share/robcal/data
/// found beside (or a few folders above) the file holding the library's code or the running
/// program: <prefix>/share/robcal/data once installed, <build>/share/robcal/data (a link to the
/// source data/) in a build tree. Throws InputError saying to set ROBCAL_DATA_DIR if none.
std::filesystem::path data_directory();

/// Names of the built-in robots (file stems under data/robots/), sorted.
std::vector<std::string> builtin_robot_names();

/// A built-in robot by name ("abb-irb120") or a robot file by path.
RobotModel load_robot(const std::string& name_or_path);

/// Parses a robot description; errors name the file, line, column and key.
RobotModel parse_robot(const yaml::Node& root);

/// The robot as YAML in the same format (round-trips through parse_robot).
std::string robot_to_yaml(const RobotModel& model);

/// Emits the robot's fields into an open YAML map (shared by robot and calibrated-model files).
void emit_robot_fields(YAML::Emitter& out, const RobotModel& model);

/// The robot's gravity from a robot or truth file (docs/method/03-error-model.md §7): at most one
/// of `gravity_m_s2` (world frame, the default (0, 0, −9.81)), `gravity_base_m_s2` (robot base
/// frame) or `mounting_deg: [rx, ry]` (the base tilted by Rot_x(rx)·Rot_y(ry) from a level floor:
/// [90, 0] a wall, [180, 0] the ceiling; gravity 9.81 m/s² in the base frame).
void parse_gravity(const yaml::Node& root, RobotModel& model);

/// Writes the gravity as `gravity_m_s2` or `gravity_base_m_s2` (round-trips through
/// parse_gravity).
void emit_gravity(YAML::Emitter& out, const RobotModel& model);

/// Tool file: payload, targets (a target written `~` is to be identified), optional tcp.
Tool load_tool(const std::string& path);
Tool parse_tool(const yaml::Node& root);

/// Writes the tool as a map at the emitter's position: the one writer of tool files and of
/// calibrated models' `tool:`. It leaves the emitter at the tool's 12 significant digits (yaml-cpp
/// neither tells a caller's precision nor keeps a local one across nested maps): a caller
/// writing on at another precision sets it again.
void emit_tool(YAML::Emitter& out, const Tool& tool);

/// The tool file's text (emit_tool; round-trips through parse_tool).
std::string tool_to_yaml(const Tool& tool);

}  // namespace robcal
