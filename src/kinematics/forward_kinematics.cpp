#include "robcal/kinematics/forward_kinematics.hpp"

namespace robcal {

Pose<double> flange_pose(const RobotModel& model, const PointMass& payload,
                         const ParameterVector& params, const Vector6d& joints,
                         const Vector6d* approach) {
  return flange_pose<double>(model, payload, params.data(), joints.data(),
                             approach ? approach->data() : nullptr);
}

}  // namespace robcal
