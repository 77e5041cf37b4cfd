#pragma once
/// \file
/// The systematic error a calibration of this model leaves on this robot (model misfit), for the
/// accuracy `plan` predicts (docs/method/05-observability.md §6). The covariance prediction
/// σ²(JᵀJ)⁻¹ counts only instrument noise; the effects the model does not contain add an error
/// that more configurations do not remove. It is measured by a prior calibration's
/// cross-validation: a held-out error e holds the misfit m, the held-out measurement's noise and
/// the fold model's parameter noise, E[e²] = m² + d·σ² + p², so m² = E[e²] − d·σ² − p².

#include <string>

#include "robcal/design/predicted_accuracy.hpp"
#include "robcal/identify/accuracy_prediction.hpp"
#include "robcal/identify/calibrated_robot.hpp"

namespace robcal {

/// A prior calibration's cross-validation, as its model file records it.
struct PriorCrossValidation {
  double mean_mm = 0, std_mm = 0;  ///< held-out error per row
  int folds = 0;
  int row_dimension = 3;  ///< 3: 3D position errors (points, poses), 1: length errors (distances)
  double instrument_sigma_mm = 0;  ///< per axis
  /// The prior fit's parameter-noise prediction (rms, mm) from its a-posteriori σ, and that σ.
  double predicted_rms_mm = 0, sigma_posterior_mm = 0;
};

struct MisfitAllowance {
  double misfit_mm = 0;           ///< m: RMS systematic error per configuration
  double held_out_rms_mm = 0;     ///< √E[e²] of the prior's cross-validation (0: given directly)
  double noise_mm = 0;            ///< √d·σ: the held-out measurements' own noise
  double parameter_noise_mm = 0;  ///< p: the fold models' parameter noise
  std::string source;             ///< where it came from ("--misfit-mm 0.05", a model file)
};

/// m from a cross-validation: E[e²] = mean² + std²; the fold models, fitted on (K−1)/K of the
/// rows with the instrument's σ, have parameter noise p = predicted_rms·(σ/σ_post)·√(K/(K−1))
/// (σ_post ≥ σ: the prior's covariance holds the misfit as noise); m = √max(0, E[e²] − d·σ² − p²).
MisfitAllowance misfit_from_cross_validation(const PriorCrossValidation& prior);

/// The same from a calibrated model file's statistics (`calibrate --kfold K` writes them). The
/// instrument σ is the one its χ² test used (`calibrate --sigma`), else `sigma_mm`. InputError
/// naming `path` and the key when the file holds no cross-validation (say how to get one).
MisfitAllowance misfit_from_prior_model(const CalibratedRobot& prior, const std::string& path,
                                        double sigma_mm);

/// A misfit given directly (`plan --misfit-mm`); InputError naming the flag when negative or not
/// finite.
MisfitAllowance misfit_given(double misfit_mm, const std::string& flag = "--misfit-mm");

/// RMS TCP error over the task region expected with the misfit: √(rms_noise² + m²) (noise and
/// misfit independent; the misfit assumed as large at the task's TCP as at the prior's targets).
double rms_with_misfit(const PredictedAccuracy& noise_only, const MisfitAllowance& misfit);

}  // namespace robcal
