#include "robcal/identify/residuals.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/kinematics/parameter_jacobian.hpp"

namespace robcal {

Eigen::Vector3d target_coordinates(const ResidualContext& context, const Eigen::VectorXd& unknowns,
                                   int target) {
  const int slot = context.layout->target_slot[static_cast<size_t>(target)];
  return slot < 0 ? context.tool->targets[static_cast<size_t>(target)].position_mm
                  : Eigen::Vector3d(unknowns.segment<3>(slot));
}

Eigen::Isometry3d tcp_frame(const ResidualContext& context, const Eigen::VectorXd& unknowns) {
  Eigen::Isometry3d T = context.tool->flange_T_tcp;
  const UnknownLayout& layout = *context.layout;
  if (layout.tcp_position >= 0) T.translation() = unknowns.segment<3>(layout.tcp_position);
  if (layout.tcp_rotation >= 0) {
    const Eigen::Vector3d phi = unknowns.segment<3>(layout.tcp_rotation);
    const double angle = phi.norm();
    if (angle > 0)
      T.linear() = T.linear() * Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
  }
  return T;
}

Eigen::Matrix3d so3_right_jacobian(const Eigen::Vector3d& phi) {
  Eigen::Matrix3d K;
  K << 0, -phi.z(), phi.y(), phi.z(), 0, -phi.x(), -phi.y(), phi.x(), 0;
  const double t = phi.norm();
  if (t < 1e-6) return Eigen::Matrix3d::Identity() - 0.5 * K + K * K / 6.0;
  return Eigen::Matrix3d::Identity() - (1 - std::cos(t)) / (t * t) * K +
         (t - std::sin(t)) / (t * t * t) * K * K;
}

void check_orientation_weight(double weight_mm) {
  if (!(weight_mm > 0) || !std::isfinite(weight_mm))
    throw InputError({"", 0, 0, "--orientation-weight"},
                     fmt::format("must be a positive number of mm per rad, not {}", weight_mm));
}

const Vector6d& row_joints(const MeasurementSet& data, size_t row) {
  switch (data.kind) {
    case MeasurementKind::Points:
      return data.points[row].joints;
    case MeasurementKind::Poses:
      return data.poses[row].joints;
    case MeasurementKind::Distances:
      return data.distances[row].joints;
  }
  return data.points[row].joints;
}

const Vector6d& row_approach(const MeasurementSet& data, size_t row) {
  switch (data.kind) {
    case MeasurementKind::Points:
      return data.points[row].approach;
    case MeasurementKind::Poses:
      return data.poses[row].approach;
    case MeasurementKind::Distances:
      return data.distances[row].approach;
  }
  return data.points[row].approach;
}

RowConditions row_conditions(const RobotModel& model, const MeasurementSet& data, size_t row) {
  const std::optional<double>& t = data.temperature_c(row);
  const std::optional<double>& time = data.time_s(row);
  return {&row_approach(data, row), t ? *t - model.reference_temperature_c : 0.0,
          time ? warmup_fraction(model, *time) : 0.0};
}

void row_residuals(const ResidualContext& context, const Eigen::VectorXd& unknowns, size_t row,
                   double* residuals, Eigen::MatrixXd* jacobian) {
  const ParameterVector params = unknowns.head<kParameterCount>();
  row_residuals(context, unknowns, row, parameter_trig(params),
                prepare_configuration(*context.model, params, row_joints(*context.data, row),
                                      row_conditions(*context.model, *context.data, row)),
                residuals, jacobian);
}

void row_residuals(const ResidualContext& context, const Eigen::VectorXd& unknowns, size_t row,
                   const ParameterTrig& trig, const PreparedConfiguration& configuration,
                   double* residuals, Eigen::MatrixXd* jacobian) {
  row_residuals(
      context, unknowns, row,
      FlangeRegressor(*context.model, context.tool->payload_of(context.data->payload(row)),
                      unknowns.head<kParameterCount>(), trig, configuration),
      residuals, jacobian);
}

void row_residuals(const ResidualContext& context, const Eigen::VectorXd& unknowns, size_t row,
                   const FlangeRegressor& regressor, double* residuals, Eigen::MatrixXd* jacobian) {
  const MeasurementSet& data = *context.data;
  const Pose<double>& flange = regressor.flange();
  if (jacobian) jacobian->setZero(data.residuals_per_row(), context.layout->size());

  switch (data.kind) {
    case MeasurementKind::Points: {
      const PointMeasurement& m = data.points[row];
      const Eigen::Vector3d p = flange * target_coordinates(context, unknowns, m.target);
      Eigen::Map<Eigen::Vector3d> r(residuals);
      r = p - m.position_mm;
      if (!jacobian) return;
      PositionJacobian J;
      regressor.jacobian<3>(point_output_map(p), &J);
      jacobian->leftCols<kParameterCount>() = J;
      const int slot = context.layout->target_slot[static_cast<size_t>(m.target)];
      if (slot >= 0) jacobian->block<3, 3>(0, slot) = flange.R;
      return;
    }
    case MeasurementKind::Poses: {
      const PoseMeasurement& m = data.poses[row];
      const Eigen::Isometry3d tcp = tcp_frame(context, unknowns);
      const Eigen::Matrix3d R = flange.R * tcp.linear();
      const Eigen::Vector3d p = flange * Eigen::Vector3d(tcp.translation());
      const Eigen::Matrix3d A = R * m.world_T_tcp.R.transpose();
      const double w = context.orientation_weight_mm;
      Eigen::Map<Eigen::Matrix<double, 6, 1>> r(residuals);
      r.head<3>() = p - m.world_T_tcp.p;
      r.tail<3>() =
          0.5 * w * Eigen::Vector3d(A(2, 1) - A(1, 2), A(0, 2) - A(2, 0), A(1, 0) - A(0, 1));
      if (!jacobian) return;
      // R → exp([δφ]×)·R gives d(A − Aᵀ) = [δφ]×·A + Aᵀ·[δφ]×, column by column.
      Eigen::Matrix<double, 6, 6> P = Eigen::Matrix<double, 6, 6>::Zero();
      P.topRows<3>() = point_output_map(p);
      for (int k = 0; k < 3; ++k) {
        Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
        E << 0, -e.z(), e.y(), e.z(), 0, -e.x(), -e.y(), e.x(), 0;
        const Eigen::Matrix3d S = E * A + A.transpose() * E;
        P.block<3, 1>(3, 3 + k) = 0.5 * w * Eigen::Vector3d(S(2, 1), S(0, 2), S(1, 0));
      }
      TwistJacobian J;
      regressor.jacobian<6>(P, &J);
      jacobian->leftCols<kParameterCount>() = J;
      const UnknownLayout& layout = *context.layout;
      if (layout.tcp_position >= 0) jacobian->block<3, 3>(0, layout.tcp_position) = flange.R;
      // φ → φ + δ turns the TCP frame by R·J_r(φ)·δ in the world.
      if (layout.tcp_rotation >= 0)
        jacobian->block<3, 3>(3, layout.tcp_rotation) =
            P.block<3, 3>(3, 3) * R * so3_right_jacobian(unknowns.segment<3>(layout.tcp_rotation));
      return;
    }
    case MeasurementKind::Distances: {
      const DistanceMeasurement& m = data.distances[row];
      const Eigen::Vector3d p = flange * target_coordinates(context, unknowns, m.target);
      const int c = context.layout->centre;
      const Eigen::Vector3d d = p - unknowns.segment<3>(c);
      const double length = d.norm();
      residuals[0] = length - m.length_mm - unknowns[context.layout->length_offset];
      if (!jacobian) return;
      const Eigen::RowVector3d u =
          length > 0 ? Eigen::RowVector3d(d.transpose() / length) : Eigen::RowVector3d::Zero();
      Eigen::Matrix<double, 1, kParameterCount> J;
      regressor.jacobian<1>(u * point_output_map(p), &J);
      jacobian->leftCols<kParameterCount>() = J;
      const int slot = context.layout->target_slot[static_cast<size_t>(m.target)];
      if (slot >= 0) jacobian->block<1, 3>(0, slot) = u * flange.R;
      jacobian->block<1, 3>(0, c) = -u;
      (*jacobian)(0, context.layout->length_offset) = -1.0;
      return;
    }
  }
}

void stacked_residuals(const ResidualContext& context, const Eigen::VectorXd& unknowns,
                       const std::vector<int>& columns, Eigen::VectorXd* residuals,
                       Eigen::MatrixXd* jacobian) {
  const int k = context.data->residuals_per_row();
  const auto rows = static_cast<Eigen::Index>(context.data->size());
  if (residuals) residuals->resize(rows * k);
  if (jacobian) jacobian->resize(rows * k, static_cast<Eigen::Index>(columns.size()));
  Eigen::VectorXd r(k);
  Eigen::MatrixXd J;
  for (Eigen::Index row = 0; row < rows; ++row) {
    row_residuals(context, unknowns, static_cast<size_t>(row), r.data(), jacobian ? &J : nullptr);
    if (residuals) residuals->segment(row * k, k) = r;
    if (jacobian)
      for (size_t c = 0; c < columns.size(); ++c)
        jacobian->block(row * k, static_cast<Eigen::Index>(c), k, 1) = J.col(columns[c]);
  }
}

Eigen::Vector3d modelled_position(const ResidualContext& context, const Eigen::VectorXd& unknowns,
                                  size_t row) {
  const MeasurementSet& data = *context.data;
  const ParameterVector params = unknowns.head<kParameterCount>();
  Pose<double> flange;
  flange_twist_jacobian(*context.model, context.tool->payload_of(data.payload(row)), params,
                        row_joints(data, row), &flange, nullptr,
                        row_conditions(*context.model, data, row));
  switch (data.kind) {
    case MeasurementKind::Points:
      return flange * target_coordinates(context, unknowns, data.points[row].target);
    case MeasurementKind::Poses:
      return flange * Eigen::Vector3d(tcp_frame(context, unknowns).translation());
    case MeasurementKind::Distances:
      return flange * target_coordinates(context, unknowns, data.distances[row].target);
  }
  return Eigen::Vector3d::Zero();
}

}  // namespace robcal
