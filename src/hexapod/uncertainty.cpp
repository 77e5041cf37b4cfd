#include "robcal/hexapod/uncertainty.hpp"

#include <ceres/jet.h>

#include <cmath>

namespace robcal::hexapod {
namespace {

using Jet12 = ceres::Jet<double, kDistanceCount>;

std::array<CupUncertainty, 3> uncertainties_from_variances(const Eigen::Matrix<double, 9, 1>& var) {
  std::array<CupUncertainty, 3> cups;
  for (int j = 0; j < 3; ++j) {
    cups[j].cup = "T" + std::to_string(j + 1);
    cups[j].per_axis = var.segment<3>(3 * j).cwiseSqrt();
    cups[j].norm = std::sqrt(var.segment<3>(3 * j).sum());
  }
  return cups;
}

}  // namespace

const std::array<std::string, kDistanceCount>& distance_names() {
  static const std::array<std::string, kDistanceCount> kNames{"b12",   "b23",   "b31",   "t12",
                                                              "t23",   "t31",   "rho11", "rho12",
                                                              "rho21", "rho22", "rho23", "rho31"};
  return kNames;
}

Distances<double> nominal_distances(const HexapodGeometry& g) {
  return {g.base.d12, g.base.d23, g.base.d31, g.tool.d12, g.tool.d23, g.tool.d31,
          g.leg_mm,   g.leg_mm,   g.leg_mm,   g.leg_mm,   g.leg_mm,   g.leg_mm};
}

std::vector<ModeUncertainty> dkp_uncertainty(const HexapodGeometry& geometry) {
  fixture_cups(geometry.base, "base fixture");
  fixture_cups(geometry.tool, "tool fixture");
  const Distances<double> d0 = nominal_distances(geometry);
  Distances<Jet12> d;
  for (int i = 0; i < kDistanceCount; ++i) d[i] = Jet12(d0[i], i);
  std::vector<ModeUncertainty> out;
  for (int mode = 1; mode <= 4; ++mode) {
    const auto cups = cups_from_distances(d, mode_signs(mode));
    if (!cups) continue;
    ModeUncertainty m;
    m.mode = mode;
    for (int j = 0; j < 3; ++j)
      for (int a = 0; a < 3; ++a) m.sensitivity.row(3 * j + a) = (*cups)[j][a].v.transpose();
    // Independent distances of equal σ: u²(x) = Σ_k c_k² σ² (Guide 98-3, eq. 10).
    m.cups = uncertainties_from_variances(m.sensitivity.rowwise().squaredNorm());
    out.push_back(m);
  }
  return out;
}

std::vector<ModeUncertainty> dkp_uncertainty_monte_carlo(const HexapodGeometry& geometry,
                                                         double sigma_mm, int samples,
                                                         std::mt19937_64& rng) {
  fixture_cups(geometry.base, "base fixture");
  fixture_cups(geometry.tool, "tool fixture");
  const Distances<double> d0 = nominal_distances(geometry);
  std::normal_distribution<double> noise(0.0, sigma_mm);
  std::vector<ModeUncertainty> out;
  for (int mode = 1; mode <= 4; ++mode) {
    const auto reference = cups_from_distances(d0, mode_signs(mode));
    if (!reference) continue;
    // Accumulate deviations from the noise-free solution (shifted data keeps the sums exact).
    Eigen::Matrix<double, 9, 1> sum = Eigen::Matrix<double, 9, 1>::Zero(), sum2 = sum;
    int used = 0;
    for (int s = 0; s < samples; ++s) {
      Distances<double> d = d0;
      for (double& x : d) x += noise(rng);
      const auto cups = cups_from_distances(d, mode_signs(mode));
      if (!cups) continue;
      Eigen::Matrix<double, 9, 1> dev;
      for (int j = 0; j < 3; ++j) dev.segment<3>(3 * j) = (*cups)[j] - (*reference)[j];
      sum += dev;
      sum2 += dev.cwiseProduct(dev);
      ++used;
    }
    ModeUncertainty m;
    m.mode = mode;
    const Eigen::Matrix<double, 9, 1> mean = sum / used;
    const Eigen::Matrix<double, 9, 1> var = (sum2 / used - mean.cwiseProduct(mean)) *
                                            (double(used) / (used - 1)) / (sigma_mm * sigma_mm);
    m.cups = uncertainties_from_variances(var);
    out.push_back(m);
  }
  return out;
}

}  // namespace robcal::hexapod
