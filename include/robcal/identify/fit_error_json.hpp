#pragma once
/// \file
/// The one JSON form of each error summary a calibration reports (its residuals, its predicted
/// accuracy, its cross-validation): every key carries its unit (`mean_mm`, `rms_mm`, ...), as in
/// error_statistics_json. calibrate, hexapod calibrate, plan and montecarlo print them; the model
/// file writes the prediction through the same function (emit_json), in the order given here.

#include <nlohmann/json.hpp>
#include <optional>

#include "robcal/identify/accuracy_prediction.hpp"
#include "robcal/identify/cross_validation.hpp"
#include "robcal/identify/identification.hpp"

namespace robcal {

/// {mean_mm, rms_mm, max_mm}; the numbers rounded to `decimals` places when given.
nlohmann::ordered_json mean_rms_max_json(double mean_mm, double rms_mm, double max_mm,
                                         std::optional<int> decimals = std::nullopt);

/// {residual_per_row_mm, start_residual_per_row_mm}: the per-row 3D TCP error of `result` at its
/// solution and at its start, each as mean_rms_max_json (one definition for every command).
nlohmann::ordered_json residual_per_row_json(const IdentificationResult& result,
                                             std::optional<int> decimals = std::nullopt);

/// {configurations, against_truth: mean_rms_max_json, against_new_measurements: {mean_mm,
/// rms_mm}}.
nlohmann::ordered_json predicted_accuracy_json(const PredictedAccuracy& predicted,
                                               std::optional<int> decimals = std::nullopt);

/// {rows, mean_mm, std_mm, max_mm} of one fold's held-out rows.
nlohmann::ordered_json fold_errors_json(const FoldErrors& fold,
                                        std::optional<int> decimals = std::nullopt);

/// {mean_mm, std_mm, mean_plus_3std_mm, max_mm} of the pooled held-out errors.
nlohmann::ordered_json held_out_error_json(const CrossValidation& cv,
                                           std::optional<int> decimals = std::nullopt);

}  // namespace robcal
