#pragma once
/// \file
/// K-fold cross-validation of a calibration (METHOD §9 when no separate validation set
/// exists): the configurations are shuffled (seeded) into K folds; each fold is predicted by a
/// model calibrated on the other K − 1, so every row's error comes from a model that never saw
/// it.

#include <cstdint>
#include <vector>

#include "robcal/identify/identification.hpp"

namespace robcal {

struct CrossValidation {
  int folds = 0;
  uint64_t seed = 0;
  /// Held-out error per row (data order): position error (mm) for points and poses, |length
  /// error| for distances.
  std::vector<double> errors_mm;
  double mean_mm = 0, std_mm = 0, max_mm = 0;
  [[nodiscard]] double mean_plus_3std_mm() const { return mean_mm + 3 * std_mm; }
};

/// Throws InputError when K < 2 or K exceeds the number of configurations, or when a fold's
/// training rows cannot identify the unknowns (naming the fold).
CrossValidation cross_validate(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const IdentifyOptions& options,
                               int folds, uint64_t seed);

}  // namespace robcal
