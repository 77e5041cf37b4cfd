#pragma once
/// \file
/// Uncertainty of the ballbar hexapod (docs/method/07-hexapod.md §4, ISO/IEC Guide 98-3): how the
/// standard uncertainty σ of each of the 12 measured distances propagates to the tool-cup
/// coordinates. Sensitivity coefficients are the exact derivatives of the templated cascade (Jets);
/// the Monte Carlo version draws the distances instead, to confirm the linear propagation.
///
/// Frame: the base fixture frame built from the measured base sides (b1 at the origin, b2 on x),
/// so the base sides' uncertainty is part of the result.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "robcal/hexapod/poses.hpp"

namespace robcal::hexapod {

/// The 12 distances: b12, b23, b31, t12, t23, t31, ρ11, ρ12, ρ21, ρ22, ρ23, ρ31.
inline constexpr int kDistanceCount = 12;
template <typename T>
using Distances = std::array<T, kDistanceCount>;

/// Names of the 12 distances in their order ("b12", …, "rho31").
const std::array<std::string, kDistanceCount>& distance_names();

/// The 12 distances of a geometry's nominal pose: every leg at geometry.leg_mm.
Distances<double> nominal_distances(const HexapodGeometry& geometry);

/// Tool cups t1..t3 in the base fixture frame from the 12 distances, for one Tri sign triple;
/// nullopt when a step has no real solution.
template <typename T>
std::optional<Cups<T>> cups_from_distances(const Distances<T>& d, const std::array<int, 3>& signs) {
  const Cups<T> base = triangle_from_sides(d[0], d[1], d[2]);
  const LegLengths<T> legs{d[6], d[7], d[8], d[9], d[10], d[11]};
  CascadeSolution<T> s = cascade(base, std::array<T, 3>{d[3], d[4], d[5]}, legs, signs);
  if (!s.real) return std::nullopt;
  return s.tool;
}

/// One tool cup's standard uncertainty, in multiples of the distances' σ.
struct CupUncertainty {
  std::string cup;                                     ///< "T1", "T2", "T3"
  Eigen::Vector3d per_axis = Eigen::Vector3d::Zero();  ///< σ_x, σ_y, σ_z / σ
  double norm = 0;                                     ///< √(σ_x² + σ_y² + σ_z²) / σ
};

struct ModeUncertainty {
  int mode = 0;  ///< assembly mode 1..4
  std::array<CupUncertainty, 3> cups;
  /// ∂(t_j coordinate)/∂(distance): rows t1x, t1y, t1z, t2x, …, columns as distance_names().
  /// Zero for the Monte Carlo estimate.
  Eigen::Matrix<double, 9, kDistanceCount> sensitivity =
      Eigen::Matrix<double, 9, kDistanceCount>::Zero();
};

/// Sensitivity coefficients and the resulting uncertainties (independent distances of equal σ)
/// for each assembly mode that is real for this geometry.
std::vector<ModeUncertainty> dkp_uncertainty(const HexapodGeometry& geometry);

/// Monte Carlo estimate: `samples` draws with independent N(0, sigma_mm) errors on the 12
/// distances; sample standard deviations divided by sigma_mm.
std::vector<ModeUncertainty> dkp_uncertainty_monte_carlo(const HexapodGeometry& geometry,
                                                         double sigma_mm, int samples,
                                                         std::mt19937_64& rng);

}  // namespace robcal::hexapod
