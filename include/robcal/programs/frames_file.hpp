#pragma once
/// \file
/// The frames file: tools and frames a program uses but does not define with literal values
/// (KUKA TOOL_DATA[n] / BASE_DATA[n] live in $config.dat, RAPID tooldata may be set at run
/// time). CSV, one per line, millimetres and a unit quaternion:
///
///     kind,name,x,y,z,qw,qx,qy,qz
///     tool,tGun,10,20,150,0.9659258,0,0.2588190,0
///     frame,wTable,1000,-200,300,0.7071068,0,0,0.7071068
///     tool,TOOL_DATA[1],0,0,120,1,0,0,0
///
/// `tool`: the TCP in the flange frame; `frame`: the work object / base / user frame in the
/// robot's base frame. Names are case-insensitive.

#include <map>
#include <string>

#include "robcal/kinematics/forward_kinematics.hpp"

namespace robcal {

struct FramesFile {
  std::map<std::string, Pose<double>> tools;   ///< by upper-case name
  std::map<std::string, Pose<double>> frames;  ///< by upper-case name
};

/// Reads a frames file. InputError naming file, line, column: unknown kind, duplicate name,
/// a number that is not one whole finite literal, a quaternion whose norm is not 1 ± 1e-3.
FramesFile read_frames_file(const std::string& path);

}  // namespace robcal
