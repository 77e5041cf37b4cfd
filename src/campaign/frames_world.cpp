#include "robcal/campaign/frames_world.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/yaml_support.hpp"

namespace robcal::campaign {

MeasurementSet measurements_in_frame(const MeasurementSet& set,
                                     const Pose<double>& instrument_T_frame) {
  const Pose<double> frame_T_instrument = instrument_T_frame.inverse();
  MeasurementSet out = set;
  for (PointMeasurement& m : out.points) m.position_mm = frame_T_instrument * m.position_mm;
  for (PoseMeasurement& m : out.poses) m.world_T_tcp = frame_T_instrument * m.world_T_tcp;
  return out;
}

Pose<double> parse_world_frame(const std::string& yaml_text, const std::string& file) {
  const yaml::Node root = yaml::parse(yaml_text, file);
  const yaml::Node frame = root.at("frame");
  const Eigen::Vector3d angles = frame.at("rotation_xyz_deg").as_vector3() * kDegToRad;
  Pose<double> pose;
  pose.p = frame.at("position_mm").as_vector3();
  pose.R = (Eigen::AngleAxisd(angles.x(), Eigen::Vector3d::UnitX()) *
            Eigen::AngleAxisd(angles.y(), Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(angles.z(), Eigen::Vector3d::UnitZ()))
               .toRotationMatrix();
  return pose;
}

std::string world_frame_comment(const std::string& file) {
  return fmt::format("positions in the world frame of {} (robcal frames world)", file);
}

Pose<double> load_world_frame(const std::string& path) {
  return parse_world_frame(read_text_file(path), path);
}

}  // namespace robcal::campaign
