#include "robcal/design/design_matrix.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "robcal/core/error.hpp"
#include "robcal/core/progress.hpp"
#include "robcal/identify/identifiability.hpp"
#include "robcal/kinematics/parameter_jacobian.hpp"

namespace robcal {

Eigen::MatrixXd DesignMatrix::stacked(const std::vector<int>& subset) const {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(subset.size()) * rows_per_candidate, columns());
  for (size_t k = 0; k < subset.size(); ++k)
    out.middleRows(static_cast<Eigen::Index>(k) * rows_per_candidate, rows_per_candidate) =
        block(subset[k]);
  return out;
}

namespace {

int rows_for(MeasurementKind kind) {
  return kind == MeasurementKind::Points ? 3 : kind == MeasurementKind::Poses ? 6 : 1;
}

}  // namespace

Eigen::MatrixXd candidate_jacobian(const RobotModel& model, const Tool& tool,
                                   const ParameterVector& params, const Candidate& candidate,
                                   const DesignSettings& settings) {
  // The analytic kinematic regressor (identify's): world twist of the flange per parameter.
  Pose<double> world_T_flange;
  TwistJacobian twist;
  RowConditions conditions;
  conditions.approach = &candidate.approach;
  flange_twist_jacobian(model, tool.payload_of(candidate.payload), params, candidate.joints,
                        &world_T_flange, &twist, conditions);
  if (settings.kind == MeasurementKind::Poses) {
    // TCP position rows, and the flange's rotation rows ω times the lever arm (mm).
    Eigen::MatrixXd out(6, kParameterCount);
    out.topRows<3>() = point_jacobian_from_twist(
        twist, world_T_flange * Eigen::Vector3d(tool.flange_T_tcp.translation()));
    out.bottomRows<3>() = settings.orientation_lever_mm * twist.bottomRows<3>();
    return out;
  }
  const Eigen::Vector3d p =
      world_T_flange * tool.targets.at(static_cast<size_t>(candidate.target)).position_mm;
  const PositionJacobian J = point_jacobian_from_twist(twist, p);
  if (settings.kind == MeasurementKind::Points) return J;
  // Ballbar: d|p − c| = uᵀ dp with u the unit vector from the centre to the target.
  return (p - settings.ballbar_centre_mm).normalized().transpose() * J;
}

DesignMatrix build_design_matrix(const RobotModel& model, const Tool& tool,
                                 const std::vector<Candidate>& candidates,
                                 const DesignSettings& settings) {
  const ParameterVector params = settings.linearisation.value_or(model.nominal());
  const int r = rows_for(settings.kind);
  const auto n = static_cast<Eigen::Index>(candidates.size());
  const auto m = static_cast<Eigen::Index>(settings.parameters.size());

  Eigen::MatrixXd raw(n * r, m);
  Progress progress("identification Jacobians of the candidates", n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::MatrixXd full =
        candidate_jacobian(model, tool, params, candidates[static_cast<size_t>(i)], settings);
    for (Eigen::Index j = 0; j < m; ++j)
      raw.block(i * r, j, r, 1) = full.col(settings.parameters[static_cast<size_t>(j)]);
    progress.advance();
  }

  // Unit RMS column norm per candidate (see the file comment); a column with no effect at all
  // is unidentifiable and is dropped below (its scale stays 1).
  Eigen::VectorXd scale(m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const double rms =
        raw.col(j).norm() / std::sqrt(static_cast<double>(std::max<Eigen::Index>(n, 1)));
    scale[j] = rms > 0 ? 1.0 / rms : 1.0;
  }
  raw = raw * scale.asDiagonal();

  // Identifiability over the whole candidate set (identify's rank analysis, columns examined
  // in layout order): with axes 2 and 3 parallel link3.d goes and link2.d stays
  // (docs/method/03-error-model.md §2).
  std::vector<int> order(static_cast<size_t>(m));
  std::iota(order.begin(), order.end(), 0);
  const RankAnalysis rank = analyse_rank(raw, order);
  DesignMatrix out;
  out.rows_per_candidate = r;
  for (const Dependency& d : rank.dropped)
    out.dropped.push_back(settings.parameters[static_cast<size_t>(d.column)]);
  std::vector<int> kept = rank.kept;
  std::sort(kept.begin(), kept.end());
  out.rows.resize(n * r, static_cast<Eigen::Index>(kept.size()));
  out.column_scale.resize(static_cast<Eigen::Index>(kept.size()));
  for (size_t c = 0; c < kept.size(); ++c) {
    out.rows.col(static_cast<Eigen::Index>(c)) = raw.col(kept[c]);
    out.column_scale[static_cast<Eigen::Index>(c)] = scale[kept[c]];
    out.parameters.push_back(settings.parameters[static_cast<size_t>(kept[c])]);
  }
  return out;
}

}  // namespace robcal
