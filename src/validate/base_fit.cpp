#include "robcal/validate/base_fit.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/identify/initial_guess.hpp"
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

  Eigen::Isometry3d world_T_fit(Eigen::umeyama(predicted, measured, false));

  // The robot's current base frame (nominal base at the origin for a nominal robot):
  // world_A_1 = Trans(x, y, d1 + z)·R(α, β, γ)·Rot_z(θ1) = world_T_base · Trans(0, 0,
  // d1)·Rot_z(θ1).
  const ParameterVector& p = robot.params;
  const double d1 = robot.model.mdh[0].d;
  Eigen::Isometry3d world_T_base = Eigen::Isometry3d::Identity();
  world_T_base.linear() = (Eigen::AngleAxisd(p[3], Eigen::Vector3d::UnitX()) *
                           Eigen::AngleAxisd(p[4], Eigen::Vector3d::UnitY()) *
                           Eigen::AngleAxisd(p[5], Eigen::Vector3d::UnitZ()))
                              .toRotationMatrix();
  world_T_base.translation() =
      Eigen::Vector3d(p[0], p[1], d1 + p[2]) - world_T_base.linear().col(2) * d1;

  CalibratedRobot out = robot;
  out.params.head<6>() = base_parameters_from_transform(world_T_fit * world_T_base, d1);
  out.base_fitted = true;
  return out;
}

}  // namespace robcal
