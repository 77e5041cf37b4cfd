#pragma once
/// \file
/// What `robcal plan-study` reports of a study (sim/plan_study.hpp): the task region in words
/// and the study as JSON (figures to 1e-6 mm, the gain to 1e-4).

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "robcal/sim/plan_study.hpp"

namespace robcal {

/// Throws InputError naming the option (as its flag: "--seeds") unless the counts are positive
/// whole numbers, seeds ≥ 1, task count ≥ 1, noise ≥ 0, the criterion not the published
/// exchange, and the prior count 0 or at least 20.
void check_plan_study_options(const PlanStudyOptions& options);

/// "TCP poses of FILE", "TCP box x0,x1,y0,y1,z0,z1 mm (world frame), tool pointing down" or
/// "random configurations in the constrained joint box".
std::string task_region_description(const PlanStudyOptions& options);

/// The nominal robot's mean TCP error over the task region, averaged over the true robots.
double nominal_mean_mm(const PlanStudyResult& result);

/// {seeds, instrument, level, sigma_mm, candidates, task_region, task_configurations,
/// nominal_mean_mm, rows: [{count, optimal, random, gain}]}.
nlohmann::json plan_study_json(const PlanStudyResult& result, const PlanStudyOptions& options);

}  // namespace robcal
