#include "robcal/design/design_matrix.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/kinematics/parameter_jacobian.hpp"

namespace robcal {

std::vector<int> level_parameters(std::string_view level, std::string_view flag) {
  std::vector<int> out;
  for (int i = 0; i < kBaseParamCount; ++i) out.push_back(i);
  if (level == "base") return out;
  if (level == "joints") {
    for (int link = 2; link <= kJointCount; ++link) out.push_back(link_param(link, 2));
    return out;
  }
  if (level != "kinematic" && level != "full")
    throw InputError(
        {"", 0, 0, std::string(flag)},
        fmt::format("unknown level '{}', expected base, joints, kinematic or full", level));
  for (int i = kLinkParamOffset; i < kComplianceOffset; ++i) out.push_back(i);
  if (level == "full")
    for (int i = kComplianceOffset; i < kScaleOffset; ++i) out.push_back(i);
  return out;
}

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

ParameterVector linearisation_params(const RobotModel& model, const DesignSettings& settings) {
  ParameterVector params = settings.linearisation.value_or(model.nominal());
  for (int i = kComplianceOffset; i < kScaleOffset; ++i)
    if (params[i] == 0.0) params[i] = kComplianceProbe;
  return params;
}

Eigen::MatrixXd candidate_jacobian(const RobotModel& model, const Tool& tool,
                                   const ParameterVector& params, const Candidate& candidate,
                                   const DesignSettings& settings) {
  Eigen::MatrixXd out(rows_for(settings.kind), kParameterCount);
  Eigen::Vector3d p;
  PositionJacobian J;
  if (settings.kind == MeasurementKind::Poses) {
    // Position rows of the TCP origin; orientation rows from three points at the lever arm L
    // along the TCP axes: their motion is δv_k = ω × v_k, and Σ_k v_k × δv_k = 2L²ω, so
    // L·ω = Σ_k v_k × δv_k / (2L) (rotation vector in mm at the lever arm).
    const double L = settings.orientation_lever_mm;
    const Eigen::Vector3d origin = tool.flange_T_tcp.translation();
    target_position_jacobian_autodiff(model, tool.payload, params, candidate.joints, origin, &p,
                                      &J);
    out.topRows<3>() = J;
    out.bottomRows<3>().setZero();
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d pk;
      PositionJacobian Jk;
      target_position_jacobian_autodiff(model, tool.payload, params, candidate.joints,
                                        origin + L * tool.flange_T_tcp.linear().col(k), &pk, &Jk);
      const Eigen::Vector3d v = pk - p;
      const PositionJacobian dv = Jk - J;
      for (int c = 0; c < kParameterCount; ++c)
        out.block<3, 1>(3, c) += v.cross(dv.col(c)) / (2 * L);
    }
    return out;
  }
  const Eigen::Vector3d& target =
      tool.targets.at(static_cast<size_t>(candidate.target)).position_mm;
  target_position_jacobian_autodiff(model, tool.payload, params, candidate.joints, target, &p, &J);
  if (settings.kind == MeasurementKind::Points) {
    out = J;
  } else {
    // Ballbar: d|p − c| = uᵀ dp with u the unit vector from the centre to the target.
    const Eigen::Vector3d u = (p - settings.ballbar_centre_mm).normalized();
    out = u.transpose() * J;
  }
  return out;
}

DesignMatrix build_design_matrix(const RobotModel& model, const Tool& tool,
                                 const std::vector<Candidate>& candidates,
                                 const DesignSettings& settings) {
  const ParameterVector params = linearisation_params(model, settings);
  const int r = rows_for(settings.kind);
  const auto n = static_cast<Eigen::Index>(candidates.size());
  const auto m = static_cast<Eigen::Index>(settings.parameters.size());

  Eigen::MatrixXd raw(n * r, m);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::MatrixXd full =
        candidate_jacobian(model, tool, params, candidates[static_cast<size_t>(i)], settings);
    for (Eigen::Index j = 0; j < m; ++j)
      raw.block(i * r, j, r, 1) = full.col(settings.parameters[static_cast<size_t>(j)]);
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

  // Rank test in layout order: a column whose Schur-complement pivot of the information
  // matrix is negligible lies in the span of the kept earlier columns and is dropped, so with
  // axes 2 and 3 parallel link3.d goes and link2.d stays (METHOD §3).
  const Eigen::MatrixXd info = raw.transpose() * raw;
  constexpr double kRelativePivot = 1e-9;
  std::vector<Eigen::Index> kept;
  DesignMatrix out;
  out.rows_per_candidate = r;
  Eigen::MatrixXd L(m, m);  // Cholesky factor of the kept block
  for (Eigen::Index j = 0; j < m; ++j) {
    const auto k = static_cast<Eigen::Index>(kept.size());
    Eigen::VectorXd b(k);
    for (Eigen::Index a = 0; a < k; ++a) b[a] = info(kept[static_cast<size_t>(a)], j);
    const Eigen::VectorXd l = L.topLeftCorner(k, k).triangularView<Eigen::Lower>().solve(b);
    const double pivot = info(j, j) - l.squaredNorm();
    if (!(info(j, j) > 0) || pivot <= kRelativePivot * info(j, j)) {
      out.dropped.push_back(settings.parameters[static_cast<size_t>(j)]);
      continue;
    }
    L.block(k, 0, 1, k) = l.transpose();
    L(k, k) = std::sqrt(pivot);
    kept.push_back(j);
  }
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
