#include <ceres/jet.h>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/parameter_jacobian.hpp"

namespace robcal {

void target_position_jacobian_autodiff(const RobotModel& model, const PointMass& payload,
                                       const ParameterVector& params, const Vector6d& joints,
                                       const Eigen::Vector3d& target_flange_mm,
                                       Eigen::Vector3d* position_mm, PositionJacobian* jacobian,
                                       const RowConditions& row) {
  using Jet = ceres::Jet<double, kParameterCount>;
  std::array<Jet, kParameterCount> p;
  for (int i = 0; i < kParameterCount; ++i) p[i] = Jet(params[i], i);
  std::array<Jet, kJointCount> q;
  for (int i = 0; i < kJointCount; ++i) q[i] = Jet(joints[i]);
  const Pose<Jet> pose = flange_pose<Jet>(model, payload, p.data(), q.data(), row);
  const Vector3<Jet> x = pose * target_flange_mm.cast<Jet>();
  for (int r = 0; r < 3; ++r) {
    if (position_mm) (*position_mm)[r] = x[r].a;
    if (jacobian) jacobian->row(r) = x[r].v.transpose();
  }
}

}  // namespace robcal
