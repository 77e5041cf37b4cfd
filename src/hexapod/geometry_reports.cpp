#include "robcal/hexapod/geometry_reports.hpp"

#include <fmt/format.h>

#include <random>

#include "json_fields.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal::hexapod {

nlohmann::json dkp_json(const DkpResult& dkp) {
  nlohmann::json out;
  for (const AssemblyModeSolution& s : dkp.solutions) {
    nlohmann::json cups = nlohmann::json::array();
    for (const auto& c : s.tool) cups.push_back(vec_json(c));
    out["solutions"].push_back({{"mode", s.mode},
                                {"signs", s.signs},
                                {"tool_cups_mm", cups},
                                {"base_T_tool", pose_json(frame_from_cups(s.tool))}});
  }
  return out;
}

nlohmann::json four_cup_dkp_json(const FourCupDkpResult& dkp) {
  nlohmann::json out{{"distances", dkp.distance_names}, {"solutions", nlohmann::json::array()}};
  for (const FourCupSolution& s : dkp.solutions) {
    nlohmann::json cups = nlohmann::json::array();
    for (const Eigen::Vector3d& c : s.tool_cups) cups.push_back({c.x(), c.y(), c.z()});
    nlohmann::json sigma = nlohmann::json::array();
    for (const CupUncertainty& u : s.uncertainty) sigma.push_back(u.norm);
    out["solutions"].push_back({{"mode", s.mode},
                                {"rms_residual_mm", s.rms_residual_mm},
                                {"tool_cups_mm", cups},
                                {"uncertainty_sigma_multiple", sigma}});
  }
  return out;
}

nlohmann::json world_frame_json(const WorldFrameFit& fit) {
  nlohmann::json corrected = nlohmann::json::array();
  for (const auto& c : fit.corrected) corrected.push_back(vec_json(c));
  return {{"robot_T_world", pose_json(fit.robot_T_fixture)},
          {"corrected_cups_mm", corrected},
          {"planar",
           {{"x_mm", rounded(fit.planar[0])},
            {"y_mm", rounded(fit.planar[1])},
            {"phi_deg", rounded(rad2deg(fit.planar[2]), 12)}}},
          {"rms_mm", rounded(fit.rms_mm)},
          {"iterations", fit.iterations},
          {"converged", fit.converged}};
}

PoseSelection select_poses(const HexapodGeometry& geometry, double angle_deg, double distance_mm) {
  if (!(angle_deg >= 0))
    throw InputError(
        {"", 0, 0, "--angle-deg"},
        fmt::format("expected a non-negative threshold in degrees, found {}", angle_deg));
  if (!(distance_mm >= 0))
    throw InputError({"", 0, 0, "--distance-mm"},
                     fmt::format("expected a non-negative threshold in mm, found {}", distance_mm));
  PoseSelection s;
  s.angle_deg = angle_deg;
  s.distance_mm = distance_mm;
  s.enumerated = enumerate_poses(geometry);
  s.kept = prune_redundant(s.enumerated, deg2rad(angle_deg), distance_mm);
  const std::vector<HexapodPose>& all = s.enumerated;
  for (size_t i = 0; i < all.size(); ++i)
    for (size_t j = i + 1; j < all.size(); ++j) {
      const double a = rad2deg(rotation_distance(all[i].base_T_tool.R, all[j].base_T_tool.R));
      if (a < s.closest_orientation_deg) {
        s.closest_orientation_deg = a;
        s.closest_centres_mm = (centroid(all[i].tool_cups) - centroid(all[j].tool_cups)).norm();
      }
    }
  return s;
}

nlohmann::json pose_selection_json(const PoseSelection& s) {
  nlohmann::json out{{"enumerated", s.enumerated.size()},
                     {"kept", s.kept.size()},
                     {"angle_deg", s.angle_deg},
                     {"distance_mm", s.distance_mm},
                     {"closest_orientation_deg", rounded(s.closest_orientation_deg, 6)},
                     {"closest_orientation_centres_mm", rounded(s.closest_centres_mm, 6)}};
  out["poses"] = nlohmann::json::array();
  for (const HexapodPose& p : s.kept) {
    nlohmann::json legs = nlohmann::json::array();
    for (const PhysicalLeg& l : p.legs)
      legs.push_back(fmt::format("B{}-T{}", l.base + 1, l.tool + 1));
    nlohmann::json cups = nlohmann::json::array();
    for (const auto& c : p.tool_cups) cups.push_back(vec_json(c));
    out["poses"].push_back(
        {{"label", p.label},
         {"mode", p.mode},
         {"rotation_deg", p.rotation_deg},
         {"base_roles", {p.design.base[0] + 1, p.design.base[1] + 1, p.design.base[2] + 1}},
         {"legs", legs},
         {"tool_cups_mm", cups},
         {"base_T_tool", pose_json(p.base_T_tool)}});
  }
  return out;
}

UncertaintyStudy uncertainty_study(const HexapodGeometry& geometry, double sigma_um, uint64_t seed,
                                   int samples) {
  if (!(sigma_um > 0))
    throw InputError({"", 0, 0, "--sigma-um"},
                     fmt::format("expected a positive σ in µm, found {}", sigma_um));
  if (samples < 100)
    throw InputError({"", 0, 0, "--samples"},
                     fmt::format("expected at least 100 samples, found {}", samples));
  UncertaintyStudy s;
  s.sigma_um = sigma_um;
  s.seed = seed;
  s.samples = samples;
  std::mt19937_64 rng(seed);
  s.analytic = dkp_uncertainty(geometry);
  s.monte_carlo = dkp_uncertainty_monte_carlo(geometry, sigma_um * 1e-3, samples, rng);
  for (size_t m = 0; m < s.analytic.size(); ++m)
    for (int j = 0; j < 3; ++j) {
      const double a = s.analytic[m].cups[j].norm, b = s.monte_carlo[m].cups[j].norm;
      s.worst_norm_sigma = std::max(s.worst_norm_sigma, a);
      s.monte_carlo_max_relative_difference =
          std::max(s.monte_carlo_max_relative_difference, std::abs(b / a - 1));
    }
  return s;
}

nlohmann::json uncertainty_study_json(const UncertaintyStudy& s) {
  nlohmann::json modes = nlohmann::json::array();
  for (size_t m = 0; m < s.analytic.size(); ++m) {
    nlohmann::json cups = nlohmann::json::array();
    for (int j = 0; j < 3; ++j) {
      const CupUncertainty& a = s.analytic[m].cups[j];
      const CupUncertainty& b = s.monte_carlo[m].cups[j];
      cups.push_back({{"cup", a.cup},
                      {"per_axis_sigma", vec_json(a.per_axis, 4)},
                      {"norm_sigma", rounded(a.norm, 4)},
                      {"per_axis_um", vec_json(a.per_axis * s.sigma_um, 4)},
                      {"norm_um", rounded(a.norm * s.sigma_um, 4)},
                      {"monte_carlo_per_axis_sigma", vec_json(b.per_axis, 4)},
                      {"monte_carlo_norm_sigma", rounded(b.norm, 4)}});
    }
    modes.push_back({{"mode", s.analytic[m].mode}, {"cups", cups}});
  }
  return {
      {"sigma_um", s.sigma_um},
      {"seed", s.seed},
      {"samples", s.samples},
      {"modes", modes},
      {"worst_norm_sigma", rounded(s.worst_norm_sigma, 4)},
      {"worst_norm_um", rounded(s.worst_norm_sigma * s.sigma_um, 4)},
      {"worst_norm_um_95", rounded(2 * s.worst_norm_sigma * s.sigma_um, 4)},
      {"monte_carlo_max_relative_difference", rounded(s.monte_carlo_max_relative_difference, 5)},
      {"published_worst_sigma", 3.2}};
}

}  // namespace robcal::hexapod
