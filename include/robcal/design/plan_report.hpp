#pragma once
/// \file
/// What `robcal plan` reports of a plan (calibration_planning.hpp) as JSON: the one serializer
/// the CLI prints and Python returns (indices to 9 decimals, errors to 1e-6 mm).

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "robcal/design/calibration_planning.hpp"

namespace robcal {

/// {selected, random (O1…O5), count, d_efficiency, d_efficiency_random, candidates, pooled,
/// parameters, dropped (names), criterion, guard, near_edge {selected, random, limit},
/// exchanges, notes, restarts, seed, instrument, cell, level, sigma_mm, predicted_error_mm
/// {task_configurations, task_region, basis, selected, random: {mean_mm, rms_mm, max_mm}},
/// predicted_error_with_misfit_mm {misfit_rms_mm, source, held_out_rms_mm, held_out_noise_mm,
/// held_out_parameter_noise_mm, selected, random: {rms_mm}} (when the misfit is known), out:
/// `written_to`}.
nlohmann::json plan_json(const PlanRequest& request, const PlanResult& result,
                         const std::string& written_to);

}  // namespace robcal
