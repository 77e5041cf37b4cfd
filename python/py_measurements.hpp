#pragma once
// The measurements as Python holds them, shared by the bindings that take or return them.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>

#include <string>
#include <vector>

#include "robcal/io/yaml_support.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/model/tool.hpp"

namespace robcal::python {

/// Rows of one kind and the tool whose target indices they use.
struct Measurements {
  MeasurementSet set;
  Tool tool;
  std::vector<std::string> warnings;  ///< ignored columns of the file read
};

/// Point rows from arrays: joints N×6 (deg), target names (N), positions N×3 (mm).
Measurements points_from_arrays(const Tool& tool, const Eigen::MatrixXd& joints_deg,
                                const std::vector<std::string>& targets,
                                const Eigen::MatrixXd& positions_mm);

/// kind, config, target, joints_deg (N×6), position_mm, quaternion_wxyz or length_mm, warnings.
pybind11::dict measurements_dict(const Measurements& measurements);

/// {'position_mm': N×3, 'quaternion_wxyz': N×4} of the poses pose_of(0) … pose_of(n − 1).
template <typename PoseOf>
pybind11::dict pose_arrays(Eigen::Index n, const PoseOf& pose_of) {
  Eigen::MatrixXd position(n, 3), quaternion(n, 4);
  for (Eigen::Index r = 0; r < n; ++r) {
    const Pose<double> pose = pose_of(r);
    const Eigen::Quaterniond q = to_quaternion(pose.R);
    position.row(r) = pose.p.transpose();
    quaternion.row(r) << q.w(), q.x(), q.y(), q.z();
  }
  pybind11::dict out;
  out["position_mm"] = position;
  out["quaternion_wxyz"] = quaternion;
  return out;
}

/// {'position_mm': 3, 'quaternion_wxyz': 4} of one pose.
inline pybind11::dict pose_dict(const Pose<double>& pose) {
  const Eigen::Quaterniond q = to_quaternion(pose.R);
  pybind11::dict d;
  d["position_mm"] = Eigen::Vector3d(pose.p);
  d["quaternion_wxyz"] = Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
  return d;
}

/// A dict given where a file is read, as the file's YAML root (named "<dict>" in errors).
yaml::Node dict_as_file(const pybind11::dict& d);

}  // namespace robcal::python
