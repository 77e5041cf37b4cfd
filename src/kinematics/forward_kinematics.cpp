#include "robcal/kinematics/forward_kinematics.hpp"

namespace robcal {

Pose<double> flange_pose(const RobotModel& model, const PointMass& payload,
                         const ParameterVector& params, const Vector6d& joints,
                         const RowConditions& row) {
  return flange_pose<double>(model, payload, params.data(), joints.data(), row);
}

}  // namespace robcal
