#include "robcal/model/robot_model.hpp"

#include <Eigen/LU>

namespace robcal {

Vector6d JointMap::to_controller(const Vector6d& model) const {
  if (is_identity()) return model;
  return matrix.partialPivLu().solve(model - offset);
}

ParameterVector RobotModel::nominal() const {
  ParameterVector p = ParameterVector::Zero();
  for (int link = 2; link <= kJointCount; ++link) {
    const MdhRow& row = mdh[link - 1];
    p[link_param(link, 0)] = row.alpha;
    p[link_param(link, 1)] = row.a;
    p[link_param(link, 2)] = row.theta_offset;
    p[link_param(link, 3)] = row.d;
  }
  for (int joint = 1; joint <= kJointCount; ++joint) p[scale_param(joint)] = 1.0;
  return p;
}

bool RobotModel::within_limits(const Vector6d& controller_joints, double tolerance) const {
  for (int i = 0; i < kJointCount; ++i) {
    if (controller_joints[i] < limits[i].lower - tolerance ||
        controller_joints[i] > limits[i].upper + tolerance)
      return false;
  }
  return true;
}

}  // namespace robcal
