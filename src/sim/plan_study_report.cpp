#include "robcal/sim/plan_study_report.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "robcal/core/error.hpp"
#include "robcal/core/rounding.hpp"

namespace robcal {
namespace {

nlohmann::json design_json(const std::vector<StudyOutcome>& outcomes) {
  nlohmann::json per_seed = nlohmann::json::array();
  for (const StudyOutcome& o : outcomes)
    per_seed.push_back(
        {{"achieved_mean_mm", rounded(o.achieved.mean_mm, 6)},
         {"achieved_rms_mm", rounded(o.achieved.rms_mm, 6)},
         {"achieved_max_mm", rounded(o.achieved.max_mm, 6)},
         {"predicted_mean_mm", rounded(o.predicted.mean_mm, 6)},
         {"predicted_rms_mm", rounded(o.predicted.rms_mm, 6)},
         {"predicted_max_mm", rounded(o.predicted.max_mm, 6)},
         {"predicted_rms_with_misfit_mm", rounded(o.predicted_rms_with_misfit_mm, 6)},
         {"O1", rounded(o.O1, 6)},
         {"measured", o.measured},
         {"converged", o.converged}});
  const StudySummary s = summarize(outcomes);
  return {{"achieved_mean_mm", rounded(s.achieved_mean_mm, 6)},
          {"achieved_rms_mm", rounded(s.achieved_rms_mm, 6)},
          {"achieved_max_mm", rounded(s.achieved_max_mm, 6)},
          {"predicted_mean_mm", rounded(s.predicted_mean_mm, 6)},
          {"predicted_rms_mm", rounded(s.predicted_rms_mm, 6)},
          {"predicted_rms_with_misfit_mm", rounded(s.predicted_rms_with_misfit_mm, 6)},
          {"O1", rounded(s.O1, 6)},
          {"per_seed", per_seed}};
}

}  // namespace

void check_plan_study_options(const PlanStudyOptions& options) {
  if (options.counts.empty()) throw InputError({"", 0, 0, "--counts"}, "expected counts");
  for (const int c : options.counts)
    if (c <= 0)
      throw InputError({"", 0, 0, "--counts"},
                       fmt::format("expected positive whole counts, found {}", c));
  if (options.seeds <= 0)
    throw InputError({"", 0, 0, "--seeds"},
                     fmt::format("expected at least 1, got {}", options.seeds));
  if (options.task_count <= 0)
    throw InputError({"", 0, 0, "--task-count"},
                     fmt::format("expected at least 1, got {}", options.task_count));
  if (options.noise_mm < 0)
    throw InputError({"", 0, 0, "--noise-mm"}, "expected a non-negative noise");
  if (options.criterion == SelectionCriterion::Published)
    throw InputError(
        {"", 0, 0, "--criterion"},
        "the published exchange is not offered in the study: expected default, d or i");
  // Each fold model of the prior must identify the full model: 20 configurations leave 16 per
  // fold at 5 folds, 48 residuals for 30 unknowns.
  constexpr int kMinPriorCount = 20;
  if (options.prior_count != 0 && options.prior_count < kMinPriorCount)
    throw InputError({"", 0, 0, "--prior-count"},
                     fmt::format("expected 0 (no prior calibration) or at least {}, got {}",
                                 kMinPriorCount, options.prior_count));
}

std::string task_region_description(const PlanStudyOptions& options) {
  if (!options.task_poses_file.empty())
    return fmt::format("TCP poses of {}", options.task_poses_file);
  if (!options.task_box) return "random configurations in the constrained joint box";
  const TaskBox& b = *options.task_box;
  return fmt::format("TCP box {},{},{},{},{},{} mm (world frame), tool pointing down", b.min_mm.x(),
                     b.max_mm.x(), b.min_mm.y(), b.max_mm.y(), b.min_mm.z(), b.max_mm.z());
}

double nominal_mean_mm(const PlanStudyResult& result) {
  double nominal = 0;
  for (const RegionError& e : result.nominal)
    nominal += e.mean_mm / static_cast<double>(result.seeds.size());
  return nominal;
}

nlohmann::json plan_study_json(const PlanStudyResult& r, const PlanStudyOptions& options) {
  nlohmann::json out;
  out["seeds"] = r.seeds;
  out["instrument"] = instrument_name(options.instrument);
  out["cell"] = options.cell ? options.cell->name : "the simulator's standard cell";
  out["level"] = level_name(options.plan.level);
  out["sigma_mm"] = r.sigma_mm;
  out["candidates"] = r.candidates;
  out["task_region"] = task_region_description(options);
  out["task_configurations"] = r.task_configurations;
  out["nominal_mean_mm"] = rounded(nominal_mean_mm(r), 6);
  out["prior_count"] = options.prior_count;
  out["misfit_mm"] = nlohmann::json::array();
  for (const MisfitAllowance& m : r.misfit)
    out["misfit_mm"].push_back({{"misfit", rounded(m.misfit_mm, 6)},
                                {"held_out_rms", rounded(m.held_out_rms_mm, 6)},
                                {"noise", rounded(m.noise_mm, 6)},
                                {"parameter_noise", rounded(m.parameter_noise_mm, 6)}});
  out["rows"] = nlohmann::json::array();
  for (const StudyRow& row : r.rows)
    out["rows"].push_back({{"count", row.count},
                           {"optimal", design_json(row.optimal)},
                           {"random", design_json(row.random)},
                           {"gain", rounded(summarize(row.random).achieved_mean_mm /
                                                summarize(row.optimal).achieved_mean_mm,
                                            4)}});
  return out;
}

}  // namespace robcal
