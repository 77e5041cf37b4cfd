#include "robcal/hexapod/device_validation.hpp"

#include <ceres/jet.h>
#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "robcal/core/error.hpp"
#include "robcal/core/rounding.hpp"
#include "robcal/core/units.hpp"
#include "robcal/hexapod/uncertainty.hpp"

namespace robcal::hexapod {
namespace {

using Jet12 = ceres::Jet<double, kDistanceCount>;

double rotation_angle_deg(const Cups<double>& a, const Cups<double>& b) {
  const Eigen::Matrix3d r = frame_from_cups(a).R.transpose() * frame_from_cups(b).R;
  return rad2deg(Eigen::AngleAxisd(r).angle());
}

}  // namespace

DeviceValidation validate_device(const DeviceValidationRequest& request) {
  const HexapodGeometry& g = request.geometry;
  fixture_cups(g.base, "--base-mm");
  fixture_cups(g.tool, "--tool-mm");
  check_gauge(request.gauge, "--gauge-range-mm", "--gauge-sigma-mm");
  if (!std::isfinite(request.reference_sigma_mm) || request.reference_sigma_mm <= 0)
    throw InputError({"", 0, 0, "--reference-sigma-mm"}, "expected a positive length (mm)");
  if (request.poses_per_mode < 1 || request.poses_per_mode > 1000000)
    throw InputError({"", 0, 0, "--poses"}, "expected 1 to 1,000,000 poses per mode");
  const double sigma = request.gauge.sigma_mm;
  const double sigma_ref = request.reference_sigma_mm;
  std::mt19937_64 rng(request.seed);
  std::uniform_real_distribution<double> leg(-0.8 * request.gauge.range_mm,
                                             0.8 * request.gauge.range_mm);
  std::normal_distribution<double> noise(0, 1);
  DeviceValidation out;
  const Distances<double> nominal = nominal_distances(g);
  for (int mode = 1; mode <= 4; ++mode) {
    ModeValidation m;
    m.mode = mode;
    double gum2 = 0, truth2 = 0, ref2 = 0, pred2 = 0, rot_truth2 = 0, rot_ref2 = 0;
    for (int k = 0; k < request.poses_per_mode; ++k) {
      Distances<double> truth = nominal;
      for (int i = 6; i < kDistanceCount; ++i) truth[i] += leg(rng);
      // The exact sensitivities at this pose (docs/method/07-hexapod.md §4).
      Distances<Jet12> jets;
      for (int i = 0; i < kDistanceCount; ++i) jets[i] = Jet12(truth[i], i);
      const auto true_cups = cups_from_distances(jets, mode_signs(mode));
      if (!true_cups) continue;
      Distances<double> read = truth;
      for (double& d : read) d += sigma * noise(rng);
      const auto device = cups_from_distances(read, mode_signs(mode));
      if (!device) continue;
      Cups<double> t, ref;
      Eigen::Matrix<double, 3, kDistanceCount> centroid_jacobian =
          Eigen::Matrix<double, 3, kDistanceCount>::Zero();
      for (int j = 0; j < 3; ++j) {
        double cup2 = 0;
        for (int a = 0; a < 3; ++a) {
          t[j][a] = (*true_cups)[j][a].a;
          centroid_jacobian.row(a) += (*true_cups)[j][a].v.transpose() / 3.0;
          cup2 += (*true_cups)[j][a].v.squaredNorm();
        }
        m.worst_cup_sigma_multiple = std::max(m.worst_cup_sigma_multiple, std::sqrt(cup2));
        ref[j] = t[j] + sigma_ref * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      }
      // Guide 98-3 eq. 10, independent distances of equal σ; the reference centroid averages three
      // cups: σ_ref/√3 per axis, σ_ref as a norm.
      const double u_device2 = sigma * sigma * centroid_jacobian.squaredNorm();
      gum2 += u_device2;
      pred2 += u_device2 + sigma_ref * sigma_ref;
      truth2 += (centroid(*device) - centroid(t)).squaredNorm();
      ref2 += (centroid(*device) - centroid(ref)).squaredNorm();
      rot_truth2 += std::pow(rotation_angle_deg(*device, t), 2);
      rot_ref2 += std::pow(rotation_angle_deg(*device, ref), 2);
      ++m.poses;
    }
    if (m.poses == 0) continue;
    const double n = m.poses;
    m.centroid_gum_mm = std::sqrt(gum2 / n);
    m.centroid_vs_truth_mm = std::sqrt(truth2 / n);
    m.centroid_reference_mm = sigma_ref;
    m.centroid_vs_reference_mm = std::sqrt(ref2 / n);
    m.centroid_predicted_mm = std::sqrt(pred2 / n);
    m.orientation_vs_truth_deg = std::sqrt(rot_truth2 / n);
    m.orientation_vs_reference_deg = std::sqrt(rot_ref2 / n);
    out.modes.push_back(m);
  }
  return out;
}

nlohmann::json device_validation_json(const DeviceValidation& v,
                                      const DeviceValidationRequest& request) {
  nlohmann::json out{{"gauge_sigma_mm", request.gauge.sigma_mm},
                     {"gauge_range_mm", request.gauge.range_mm},
                     {"reference_sigma_mm", request.reference_sigma_mm},
                     {"seed", request.seed}};
  out["modes"] = nlohmann::json::array();
  for (const ModeValidation& m : v.modes)
    out["modes"].push_back(
        {{"mode", m.mode},
         {"poses", m.poses},
         {"centroid_gum_mm", rounded(m.centroid_gum_mm, 9)},
         {"centroid_vs_truth_mm", rounded(m.centroid_vs_truth_mm, 9)},
         {"centroid_reference_mm", rounded(m.centroid_reference_mm, 9)},
         {"centroid_vs_reference_mm", rounded(m.centroid_vs_reference_mm, 9)},
         {"centroid_predicted_mm", rounded(m.centroid_predicted_mm, 9)},
         {"orientation_vs_truth_deg", rounded(m.orientation_vs_truth_deg, 9)},
         {"orientation_vs_reference_deg", rounded(m.orientation_vs_reference_deg, 9)},
         {"worst_cup_sigma_multiple", rounded(m.worst_cup_sigma_multiple, 6)}});
  return out;
}

}  // namespace robcal::hexapod
