#pragma once
/// \file
/// The workflows behind `robcal frames base|tool|point|world` and Python's frames_*: each reads
/// its files, estimates the frame or target (campaign/frames.hpp) and renders the file to write
/// (a cell file or robot_base block, a tool file, a frame block) with its σ; one JSON
/// serializer per result. mm and degrees outside.

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "robcal/campaign/frames.hpp"

namespace robcal::campaign {

struct BaseFrameRequest {
  std::string robot;   ///< built-in robot name or robot file
  std::string joint1;  ///< points file of the joint-1 sweep
  std::string joint2;  ///< points file of the joint-2 sweep
  std::string target = "1";
  std::string cell;     ///< cell file whose robot_base block is replaced; empty: the block alone
  double sigma_mm = 0;  ///< instrument noise per axis; 0: estimated from the residuals
};

struct BaseFrameResult {
  std::string robot;  ///< the robot's name
  FrameEstimate base;
  std::string text;  ///< the file to write
};

BaseFrameResult frames_base(const BaseFrameRequest& request);

/// A target in the flange frame: from a joint-5 and a joint-6 sweep (frames_tool: `first`,
/// `second`), or from ≥ 4 measured configurations with the base of a cell (frames_point:
/// `first`, `cell`).
struct TargetFrameRequest {
  std::string robot;
  std::string first;
  std::string second;
  std::string cell;
  std::string target = "1";
  std::string tool;  ///< tool file to update; empty: a new tool
  double sigma_mm = 0;
};

struct TargetFrameResult {
  std::string robot;
  std::string target;
  PointEstimate point;
  std::string text;  ///< the tool file to write, with the estimate as a comment
};

TargetFrameResult frames_tool(const TargetFrameRequest& request);
TargetFrameResult frames_point(const TargetFrameRequest& request);

struct NestFrameRequest {
  std::string measured;  ///< nests as measured: name,x,y,z (mm)
  std::string nominal;   ///< nests in the frame to set up: name,x,y,z (mm)
  double sigma_mm = 0;
};

struct NestFrameResult {
  FrameEstimate frame;            ///< the nests' frame in the instrument frame
  Eigen::Vector3d instrument_mm;  ///< the instrument in the nests' frame
  std::string text;               ///< the frame block to write
};

NestFrameResult frames_world(const NestFrameRequest& request);

/// {position_mm, rotation_xyz_deg, sigma_position_mm, sigma_rotation_deg, sigma_noise_mm, rms_mm}.
nlohmann::json frame_estimate_json(const FrameEstimate& frame);
/// {target, position_mm, sigma_mm, sigma_noise_mm, rms_mm}.
nlohmann::json target_estimate_json(const std::string& target, const PointEstimate& point);
/// {frame, instrument_position_mm}.
nlohmann::json nest_frame_json(const NestFrameResult& result);

}  // namespace robcal::campaign
