#include "robcal/identify/fit_error_json.hpp"

#include "robcal/core/rounding.hpp"

namespace robcal {

nlohmann::ordered_json mean_rms_max_json(double mean_mm, double rms_mm, double max_mm,
                                         std::optional<int> decimals) {
  return {{"mean_mm", rounded_if(mean_mm, decimals)},
          {"rms_mm", rounded_if(rms_mm, decimals)},
          {"max_mm", rounded_if(max_mm, decimals)}};
}

nlohmann::ordered_json residual_per_row_json(const IdentificationResult& r,
                                             std::optional<int> decimals) {
  return {{"residual_per_row_mm", mean_rms_max_json(r.mean_mm, r.rms_mm, r.max_mm, decimals)},
          {"start_residual_per_row_mm",
           mean_rms_max_json(r.start_mean_mm, r.start_rms_mm, r.start_max_mm, decimals)}};
}

nlohmann::ordered_json predicted_accuracy_json(const PredictedAccuracy& p,
                                               std::optional<int> decimals) {
  return {{"configurations", p.configurations},
          {"against_truth", mean_rms_max_json(p.mean_mm, p.rms_mm, p.max_mm, decimals)},
          {"against_new_measurements",
           {{"mean_mm", rounded_if(p.mean_vs_measurements_mm, decimals)},
            {"rms_mm", rounded_if(p.rms_vs_measurements_mm, decimals)}}}};
}

nlohmann::ordered_json fold_errors_json(const FoldErrors& f, std::optional<int> decimals) {
  return {{"rows", f.rows},
          {"mean_mm", rounded_if(f.mean_mm, decimals)},
          {"std_mm", rounded_if(f.std_mm, decimals)},
          {"max_mm", rounded_if(f.max_mm, decimals)}};
}

nlohmann::ordered_json held_out_error_json(const CrossValidation& cv, std::optional<int> decimals) {
  return {{"mean_mm", rounded_if(cv.mean_mm, decimals)},
          {"std_mm", rounded_if(cv.std_mm, decimals)},
          {"mean_plus_3std_mm", rounded_if(cv.mean_plus_3std_mm(), decimals)},
          {"max_mm", rounded_if(cv.max_mm, decimals)}};
}

}  // namespace robcal
