#pragma once
/// \file
/// Pose-list files: TCP poses in the world frame, one per row of a CSV with the header
/// `name,x,y,z,qw,qx,qy,qz[,config]` (mm; unit quaternion w, x, y, z). `config` names the arm
/// branch: an ArmConfig label such as "front-up-noflip", or its index 0..7 (back·4 + down·2 +
/// flip, which is ABB's cfx); empty or absent leaves the choice to the reader's user. Lines
/// starting with '#' and blank lines are skipped. Read by `robcal compensate` (the wanted
/// targets) and `robcal plan --task-poses` (a task region).

#include <optional>
#include <string>
#include <vector>

#include "robcal/kinematics/inverse_kinematics.hpp"

namespace robcal {

/// One row of a pose-list file.
struct ListedPose {
  std::string name;
  Pose<double> world_T_tcp;  ///< mm
  std::optional<ArmConfig> config;
  int line = 0;  ///< in the file, for messages
};

/// Reads a pose-list file. InputError naming the file, line, column and what was expected
/// (a missing or wrong header, a cell that is not a finite number, a quaternion that is not
/// unit, an unknown configuration, a wrong number of cells, no poses).
std::vector<ListedPose> read_pose_list(const std::string& path);
/// The same from the text of a file named `file` (for messages).
std::vector<ListedPose> parse_pose_list(const std::string& text, const std::string& file);

}  // namespace robcal
