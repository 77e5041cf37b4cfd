#include "robcal/design/misfit_allowance.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>

#include "robcal/core/error.hpp"

namespace robcal {

MisfitAllowance misfit_from_cross_validation(const PriorCrossValidation& prior) {
  MisfitAllowance out;
  const double held_out_sq = prior.mean_mm * prior.mean_mm + prior.std_mm * prior.std_mm;
  out.held_out_rms_mm = std::sqrt(held_out_sq);
  out.noise_mm = std::sqrt(static_cast<double>(prior.row_dimension)) * prior.instrument_sigma_mm;
  // The prior's covariance scales with its a-posteriori σ, which holds the misfit as noise; the
  // parameter noise of the instrument alone scales with the stated σ.
  const double noise_ratio =
      prior.sigma_posterior_mm > prior.instrument_sigma_mm && prior.sigma_posterior_mm > 0
          ? prior.instrument_sigma_mm / prior.sigma_posterior_mm
          : 1.0;
  const double fold_factor = prior.folds >= 2 ? std::sqrt(prior.folds / (prior.folds - 1.0)) : 1.0;
  out.parameter_noise_mm = prior.predicted_rms_mm * noise_ratio * fold_factor;
  out.misfit_mm = std::sqrt(std::max(0.0, held_out_sq - out.noise_mm * out.noise_mm -
                                              out.parameter_noise_mm * out.parameter_noise_mm));
  return out;
}

MisfitAllowance misfit_from_prior_model(const CalibratedRobot& prior, const std::string& path,
                                        double sigma_mm) {
  const YAML::Node statistics = YAML::Load(prior.statistics);
  const YAML::Node cv = statistics.IsMap() ? statistics["cross_validation"] : YAML::Node();
  if (!cv || !cv.IsMap() || !cv["mean_mm"] || !cv["std_mm"] || !cv["folds"])
    throw InputError({path, 0, 0, "statistics.cross_validation"},
                     "the prior model holds no cross-validation, so its misfit is unknown: "
                     "calibrate it with --kfold 5 (and --sigma, the instrument's σ), or give "
                     "--misfit-mm");
  PriorCrossValidation p;
  p.instrument_sigma_mm = sigma_mm;
  try {
    p.mean_mm = cv["mean_mm"].as<double>();
    p.std_mm = cv["std_mm"].as<double>();
    p.folds = cv["folds"].as<int>();
    if (const YAML::Node test = statistics["noise_test"]; test && test["instrument_sigma_mm"])
      p.instrument_sigma_mm = test["instrument_sigma_mm"].as<double>();
    if (statistics["sigma_mm"]) p.sigma_posterior_mm = statistics["sigma_mm"].as<double>();
    // `rms` without its unit: model files written before the keys carried it.
    if (const YAML::Node predicted = statistics["predicted_position_error_mm"];
        predicted && predicted["against_truth"])
      for (const char* key : {"rms_mm", "rms"})
        if (const YAML::Node rms = predicted["against_truth"][key]) {
          p.predicted_rms_mm = rms.as<double>();
          break;
        }
    // Distances (a ballbar) leave one residual per row, points three, poses six: the held-out
    // error is then a length error (d = 1), else a 3D position error (d = 3).
    if (const YAML::Node targets = statistics["by_target"]; targets && statistics["residuals"]) {
      long rows = 0;
      for (const YAML::Node& t : targets) rows += t["rows"].as<long>();
      if (rows > 0 && statistics["residuals"].as<long>() == rows) p.row_dimension = 1;
    }
  } catch (const YAML::Exception& e) {
    throw InputError({path, 0, 0, "statistics"},
                     fmt::format("unreadable fit statistics ({}): expected numbers as "
                                 "`robcal calibrate` writes them",
                                 e.what()));
  }
  // yaml-cpp reads .inf and .nan as numbers: every figure must be finite, or the misfit is.
  const bool finite = std::isfinite(p.mean_mm) && std::isfinite(p.std_mm) &&
                      std::isfinite(p.instrument_sigma_mm) && std::isfinite(p.sigma_posterior_mm) &&
                      std::isfinite(p.predicted_rms_mm);
  if (!finite || p.mean_mm < 0 || p.std_mm < 0 || p.folds < 2)
    throw InputError({path, 0, 0, "statistics.cross_validation"},
                     "expected finite non-negative mean_mm and std_mm, finite σ and predicted "
                     "figures, and at least 2 folds");
  MisfitAllowance out = misfit_from_cross_validation(p);
  out.source = fmt::format("{}: {}-fold cross-validated error rms {:.4f} mm", path, p.folds,
                           out.held_out_rms_mm);
  return out;
}

MisfitAllowance misfit_given(double misfit_mm, const std::string& flag) {
  if (!std::isfinite(misfit_mm) || misfit_mm < 0)
    throw InputError({"", 0, 0, flag},
                     fmt::format("expected a non-negative misfit in mm, got {}", misfit_mm));
  MisfitAllowance out;
  out.misfit_mm = misfit_mm;
  out.source = fmt::format("{} {:g}", flag, misfit_mm);
  return out;
}

double rms_with_misfit(const PredictedAccuracy& noise_only, const MisfitAllowance& misfit) {
  return std::hypot(noise_only.rms_mm, misfit.misfit_mm);
}

}  // namespace robcal
