#include "robcal/identify/initial_guess.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "robcal/core/error.hpp"

namespace robcal {

Vector6d base_parameters_from_transform(const Eigen::Isometry3d& world_T_base, double d1_mm) {
  // world_T_base · Trans(0, 0, d1)·Rot_z(θ1) = Trans(t + R·(0, 0, d1)) · R · Rot_z(θ1), and
  // R = Rot_x(α)·Rot_y(β)·Rot_z(γ): R02 = sin β, R12 = −sin α cos β, R22 = cos α cos β,
  // R01 = −cos β sin γ, R00 = cos β cos γ.
  const Eigen::Matrix3d R = world_T_base.linear();
  const Eigen::Vector3d o = world_T_base.translation() + R.col(2) * d1_mm;
  Vector6d base;
  base << o.x(), o.y(), o.z() - d1_mm, std::atan2(-R(1, 2), R(2, 2)),
      std::asin(std::clamp(R(0, 2), -1.0, 1.0)), std::atan2(-R(0, 1), R(0, 0));
  return base;
}

namespace {

/// Least-squares coordinates of each unknown target: p_meas = F_k · t, so t = mean of F_kᵀ·p.
void fit_unknown_targets(const ResidualContext& context, Eigen::VectorXd& unknowns) {
  const MeasurementSet& data = *context.data;
  if (data.kind != MeasurementKind::Points) return;
  const UnknownLayout& layout = *context.layout;
  std::vector<Eigen::Vector3d> sum(layout.target_slot.size(), Eigen::Vector3d::Zero());
  std::vector<int> count(layout.target_slot.size(), 0);
  const ParameterVector params = unknowns.head<kParameterCount>();
  for (size_t row = 0; row < data.points.size(); ++row) {
    const PointMeasurement& m = data.points[row];
    if (layout.target_slot[static_cast<size_t>(m.target)] < 0) continue;
    const Pose<double> F = flange_pose(*context.model, context.tool->payload_of(m.payload), params,
                                       m.joints, row_conditions(*context.model, data, row));
    sum[static_cast<size_t>(m.target)] += F.R.transpose() * (m.position_mm - F.p);
    ++count[static_cast<size_t>(m.target)];
  }
  for (size_t t = 0; t < sum.size(); ++t)
    if (layout.target_slot[t] >= 0 && count[t] > 0)
      unknowns.segment<3>(layout.target_slot[t]) = sum[t] / count[t];
}

/// Least-squares TCP parts of pose measurements with the base placed: position t from
/// p_meas = F_k·t (t = mean of F_kᵀ·(p − F_k.p)); rotation from R_meas = F_k.R·S·exp([φ]×), the
/// rotation nearest to the mean of (F_k.R·S)ᵀ·R_meas (S the tool's start rotation).
void fit_unknown_tcp(const ResidualContext& context, Eigen::VectorXd& unknowns) {
  const MeasurementSet& data = *context.data;
  const UnknownLayout& layout = *context.layout;
  if (data.kind != MeasurementKind::Poses) return;
  const ParameterVector params = unknowns.head<kParameterCount>();
  const Eigen::Matrix3d S = context.tool->flange_T_tcp.linear();
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Zero();
  for (size_t row = 0; row < data.poses.size(); ++row) {
    const PoseMeasurement& m = data.poses[row];
    const Pose<double> F = flange_pose(*context.model, context.tool->payload_of(m.payload), params,
                                       m.joints, row_conditions(*context.model, data, row));
    position += F.R.transpose() * (m.world_T_tcp.p - F.p);
    rotation += (F.R * S).transpose() * m.world_T_tcp.R;
  }
  if (layout.tcp_position >= 0)
    unknowns.segment<3>(layout.tcp_position) = position / static_cast<double>(data.size());
  if (layout.tcp_rotation >= 0) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rotation,
                                                Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
    const Eigen::AngleAxisd phi(Eigen::Matrix3d(svd.matrixU() * D * svd.matrixV().transpose()));
    unknowns.segment<3>(layout.tcp_rotation) = phi.angle() * phi.axis();
  }
}

void fit_base(const ResidualContext& context, Eigen::VectorXd& unknowns) {
  const MeasurementSet& data = *context.data;
  const auto n = static_cast<Eigen::Index>(data.size());
  Eigen::Matrix3Xd modelled(3, n), measured(3, n);
  Eigen::VectorXd at_origin = unknowns;
  at_origin.head<kBaseParamCount>().setZero();
  for (Eigen::Index row = 0; row < n; ++row) {
    modelled.col(row) = modelled_position(context, at_origin, static_cast<size_t>(row));
    measured.col(row) = data.kind == MeasurementKind::Points
                            ? data.points[static_cast<size_t>(row)].position_mm
                            : data.poses[static_cast<size_t>(row)].world_T_tcp.p;
  }
  const Eigen::Matrix3Xd centred = modelled.colwise() - modelled.rowwise().mean();
  const Eigen::JacobiSVD<Eigen::Matrix3Xd> svd(centred);
  if (n < 3 || svd.singularValues()[1] < 1e-6 * std::max(1.0, svd.singularValues()[0]))
    throw InputError({data.file, 0, 0, ""},
                     "cannot place the robot in the world: the measurements need at least "
                     "three rows at positions that are not on one line");
  Eigen::Isometry3d world_T_base(Eigen::umeyama(modelled, measured, false));
  unknowns.head<kBaseParamCount>() =
      base_parameters_from_transform(world_T_base, context.model->mdh[0].d);
}

void fit_ballbar_centre(const ResidualContext& context, Eigen::VectorXd& unknowns) {
  // |p − c|² = L²  ⇔  2 p·c − |c|² = |p|² − L²: linear in (c, |c|²).
  const MeasurementSet& data = *context.data;
  const auto n = static_cast<Eigen::Index>(data.size());
  Eigen::MatrixXd A(n, 4);
  Eigen::VectorXd b(n);
  for (Eigen::Index row = 0; row < n; ++row) {
    const Eigen::Vector3d p = modelled_position(context, unknowns, static_cast<size_t>(row));
    const double L = data.distances[static_cast<size_t>(row)].length_mm;
    A.row(row) << 2 * p.transpose(), -1.0;
    b[row] = p.squaredNorm() - L * L;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (n < 4 || qr.rank() < 4)
    throw InputError({data.file, 0, 0, ""},
                     "cannot locate the ballbar centre: the distances need at least four rows "
                     "with the target at positions not on one plane");
  unknowns.segment<3>(context.layout->centre) = qr.solve(b).head<3>();
}

}  // namespace

void initial_guess(const ResidualContext& context, bool fit_base_frame, Eigen::VectorXd& unknowns) {
  const MeasurementSet& data = *context.data;
  if (data.kind == MeasurementKind::Distances) {
    fit_ballbar_centre(context, unknowns);
    return;
  }
  bool unknown_targets = context.layout->tcp_position >= 0 || context.layout->tcp_rotation >= 0;
  for (int slot : context.layout->target_slot) unknown_targets = unknown_targets || slot >= 0;
  // A target without coordinates starts at the flange centre; alternating the rigid fit and
  // the target fit refines both (a few rounds reach millimetres, the fit does the rest).
  const int rounds = fit_base_frame && unknown_targets ? 5 : 1;
  for (int round = 0; round < rounds; ++round) {
    if (fit_base_frame) fit_base(context, unknowns);
    if (unknown_targets) fit_unknown_targets(context, unknowns);
    if (unknown_targets) fit_unknown_tcp(context, unknowns);
  }
}

}  // namespace robcal
