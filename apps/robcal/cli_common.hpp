#pragma once
/// \file
/// Shared pieces of the command-line program: parsing joint lists and poses, loading robots
/// and tools, printing JSON, progress on a terminal.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal::cli {

/// Comma-separated numbers ("10,-20,30"); `what` names the flag in errors. Exactly `count`
/// values unless count < 0.
std::vector<double> parse_numbers(const std::string& text, int count, const std::string& what);

/// Six controller joint values given in degrees → radians.
Vector6d parse_joints_deg(const std::string& text, const std::string& what = "--joints");

/// A rotation from a unit quaternion "qw,qx,qy,qz" (InputError naming `what` otherwise).
Eigen::Matrix3d parse_orientation(const std::string& text, const std::string& what);

/// An arm configuration label such as "front-up-noflip" (InputError naming `what` otherwise).
ArmConfig parse_config(const std::string& text, const std::string& what = "--config");

/// `--out -`: standard output then carries the data alone, so that it can be piped; everything
/// else the command prints (its report, --json, "wrote -") goes to standard error. Call once,
/// before the command runs.
void reserve_stdout_for_data();

/// Prints JSON (2-space indent) to stdout.
void print_json(const nlohmann::json& value);

/// True when stdout is a terminal (progress output is shown only then).
bool stdout_is_terminal();

/// Rounds for printing: keeps JSON readable and removes -0.
double tidy(double value, int decimals = 9);

}  // namespace robcal::cli
