#pragma once
// The measurements as Python holds them, shared by the bindings that take or return them.
#include <pybind11/pybind11.h>

#include <Eigen/Core>

#include <string>
#include <vector>

#include "robcal/io/yaml_support.hpp"
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

/// A dict given where a file is read, as the file's YAML root (named "<dict>" in errors).
yaml::Node dict_as_file(const pybind11::dict& d);

}  // namespace robcal::python
