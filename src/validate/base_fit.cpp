#include "robcal/validate/base_fit.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/validate/position_error.hpp"

namespace robcal {

CalibratedRobot fit_base(const CalibratedRobot& robot, const MeasurementSet& set) {
  const Eigen::Matrix3Xd predicted = predicted_positions(robot, set);
  Eigen::Matrix3Xd measured(3, predicted.cols());
  for (size_t r = 0; r < set.size(); ++r)
    measured.col(static_cast<Eigen::Index>(r)) =
        set.kind == MeasurementKind::Points  ? set.points[r].position_mm
        : set.kind == MeasurementKind::Poses ? set.poses[r].world_T_tcp.p
                                             : Eigen::Vector3d::Constant(NAN);
  if (set.kind == MeasurementKind::Distances)
    throw InputError({set.file, 0, 0, ""},
                     "a distances (ballbar) file has no positions to fit a world frame to");
  // A frame needs three points off one line: the second singular value of the centred
  // positions must not vanish (relative to their spread).
  const Eigen::Matrix3Xd centred = measured.colwise() - measured.rowwise().mean();
  const Eigen::Vector3d spread = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
  if (measured.cols() < 3 || !(spread[1] > 1e-9 * spread[0]))
    throw InputError({set.file, 0, 0, ""},
                     fmt::format("{} measured positions do not fix a world frame: at least 3 "
                                 "positions not on one line are needed",
                                 measured.cols()));

  const Eigen::Matrix4d fit = Eigen::umeyama(predicted, measured, false);
  const Eigen::Matrix3d R_fit = fit.topLeftCorner<3, 3>();
  const Eigen::Vector3d t_fit = fit.topRightCorner<3, 1>();

  // Old base: Trans(x, y, d1 + z) · Rx(α) Ry(β) Rz(γ) (· Rz(θ1)); new = T_fit · old.
  const ParameterVector& p = robot.params;
  const double d1 = robot.model.mdh[0].d;
  const Eigen::Matrix3d R_old = (Eigen::AngleAxisd(p[3], Eigen::Vector3d::UnitX()) *
                                 Eigen::AngleAxisd(p[4], Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(p[5], Eigen::Vector3d::UnitZ()))
                                    .toRotationMatrix();
  const Eigen::Matrix3d R = R_fit * R_old;
  const Eigen::Vector3d origin = t_fit + R_fit * Eigen::Vector3d(p[0], p[1], d1 + p[2]);

  CalibratedRobot out = robot;
  out.params[0] = origin.x();
  out.params[1] = origin.y();
  out.params[2] = origin.z() - d1;
  // R = Rx(α)·Ry(β)·Rz(γ): R(0,2) = sin β, R(1,2) = −sin α cos β, R(2,2) = cos α cos β,
  // R(0,1) = −cos β sin γ, R(0,0) = cos β cos γ.
  out.params[4] = std::atan2(R(0, 2), std::hypot(R(0, 0), R(0, 1)));
  out.params[3] = std::atan2(-R(1, 2), R(2, 2));
  out.params[5] = std::atan2(-R(0, 1), R(0, 0));
  out.base_fitted = true;
  return out;
}

}  // namespace robcal
