#pragma once
/// \file
/// K-fold cross-validation of a calibration (docs/method/04-identification.md §6; 09-validation.md
/// when no separate validation set exists): the configurations are shuffled (seeded) into K folds;
/// each fold is predicted by a model calibrated on the other K − 1, so every row's error comes from
/// a model that never saw it.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "robcal/identify/identification.hpp"

namespace robcal {

/// Held-out error of one fold's rows.
struct FoldErrors {
  int rows = 0;
  double mean_mm = 0, std_mm = 0, max_mm = 0;
};

struct CrossValidation {
  int folds = 0;
  uint64_t seed = 0;
  bool user_folds = false;  ///< folds from the user's file (seed unused)
  std::vector<FoldErrors> per_fold;
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

/// The same with the user's folds (`--folds FILE`): `config_fold` maps every configuration of
/// the data to its fold 1..K (K = the largest). InputError (key `--folds`) naming a
/// configuration without a fold, or a fold with no configuration.
CrossValidation cross_validate(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const IdentifyOptions& options,
                               const std::map<std::string, int>& config_fold);

/// Reads a folds file: CSV `config,fold` (header row, `#` comments; fold an integer ≥ 1).
/// InputError naming the file, line and column.
std::map<std::string, int> read_folds_csv(const std::string& path);

}  // namespace robcal
