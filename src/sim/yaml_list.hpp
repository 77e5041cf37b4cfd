#pragma once
/// \file
/// Private to the simulation files' writers: a 3-vector as the list yaml-cpp writes as [x, y, z].

#include <Eigen/Core>
#include <vector>

namespace robcal {

inline std::vector<double> as_list(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace robcal
