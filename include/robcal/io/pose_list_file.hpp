#pragma once
/// \file
/// Pose-list files: TCP poses in the world frame, one per row of a CSV with the header
/// `name,x,y,z,qw,qx,qy,qz` (mm; unit quaternion w, x, y, z), then any of the optional columns
/// `config`, `approach`, `temperature`, `time_s`, `payload` in any order. `config` names the arm
/// branch: an ArmConfig label such as "front-up-noflip", or its index 0..7 (back·4 + down·2 +
/// flip, which is ABB's cfx); empty or absent leaves the choice to the reader's user. The others
/// say how `robcal compensate` reaches the pose (docs/method/10-compensation.md §6), with the
/// measurement file's conventions (io/measurement_file.hpp): `approach` each joint's side
/// (`++-+++`), `temperature` the arm's °C, `time_s` how long the arm has worked (s, or `warm`:
/// fully warm), `payload` a name of the tool's `payloads`; empty or absent: the run's
/// (`--approach`, `--temperature-c`, `--warmup-time-s`/`--warm`, `--payload`). Trailing optional
/// cells may be left out. Lines starting with '#' and blank lines are skipped. Read by `robcal
/// compensate` (the wanted targets) and `robcal plan --task-poses` (a task region, which uses the
/// poses and configurations only).

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "robcal/kinematics/inverse_kinematics.hpp"

namespace robcal {

/// A `time_s` cell `warm`: the arm fully warm, as after an unbounded time (φ = 1,
/// docs/method/03-error-model.md §10).
inline constexpr const char* kWarmCell = "warm";
inline constexpr double kFullyWarmS = std::numeric_limits<double>::infinity();

/// One row of a pose-list file.
struct ListedPose {
  std::string name;
  Pose<double> world_T_tcp;  ///< mm
  std::optional<ArmConfig> config;
  int line = 0;                         ///< in the file, for messages
  std::optional<Vector6d> approach;     ///< each joint's side (+1 below, −1 above, 0 unknown)
  std::optional<double> temperature_c;  ///< the arm's temperature, °C
  /// How long the arm has worked (s), the warm-up group's input; kFullyWarmS: fully warm.
  std::optional<double> time_s;
  std::string payload;     ///< a name of the tool's `payloads`; empty: none given
  int payload_column = 0;  ///< of the `payload` cell, for messages
};

/// Reads a pose-list file. InputError naming the file, line, column and what was expected
/// (a missing or wrong header, a cell that is not a finite number, a quaternion that is not
/// unit, an unknown configuration, an approach, temperature or time the measurement reader
/// would refuse, a wrong number of cells, no poses). Payload names are checked against the tool by
/// their user.
std::vector<ListedPose> read_pose_list(const std::string& path);
/// The same from the text of a file named `file` (for messages).
std::vector<ListedPose> parse_pose_list(const std::string& text, const std::string& file);

}  // namespace robcal
