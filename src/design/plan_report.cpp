#include "robcal/design/plan_report.hpp"

#include <nlohmann/json.hpp>

#include "robcal/core/rounding.hpp"
#include "robcal/identify/fit_error_json.hpp"

namespace robcal {
namespace {

nlohmann::json indices_json(const ObservabilityIndices& o) {
  return {{"O1", rounded(o.O1)},
          {"O2", rounded(o.O2)},
          {"O3", rounded(o.O3)},
          {"O4", rounded(o.O4)},
          {"O5", rounded(o.O5)}};
}

nlohmann::json accuracy_json(const PredictedAccuracy& a) {
  return mean_rms_max_json(a.mean_mm, a.rms_mm, a.max_mm, 6);
}

}  // namespace

nlohmann::json plan_json(const PlanRequest& request, const PlanResult& r,
                         const std::string& written_to) {
  std::vector<std::string> dropped;
  for (int p : r.dropped) dropped.push_back(parameter_table()[static_cast<size_t>(p)].name);
  nlohmann::json out;
  out["selected"] = indices_json(r.selected);
  out["random"] = indices_json(r.random);
  out["count"] = request.count;
  out["d_efficiency"] = rounded(r.d_efficiency_selected, 4);
  out["d_efficiency_random"] = rounded(r.d_efficiency_random, 4);
  out["candidates"] = r.candidates;
  out["pooled"] = r.pooled;
  out["parameters"] = r.parameters.size();
  out["dropped"] = dropped;
  out["criterion"] = criterion_name(r.criterion);
  out["guard"] = request.guard.enabled && r.criterion == SelectionCriterion::IOptimal;
  out["near_edge"] = {
      {"selected", r.near_edge}, {"random", r.near_edge_random}, {"limit", r.edge_limit}};
  out["exchanges"] = r.exchanges;
  out["notes"] = r.notes;
  out["restarts"] = r.restarts;
  out["seed"] = request.seed;
  out["instrument"] = r.instrument;
  out["cell"] = r.cell;
  out["level"] = level_name(request.level);
  out["identify"] = request.identify;
  out["approach"] = r.approach_varied ? "varied" : "below";
  out["payloads"] = r.payloads_varied ? "varied" : "own";
  out["sigma_mm"] = r.sigma_mm;
  out["predicted_error_mm"] = {{"task_configurations", r.task_configurations},
                               {"task_region", r.region},
                               {"basis", "instrument noise only"},
                               {"selected", accuracy_json(r.predicted_selected)},
                               {"random", accuracy_json(r.predicted_random)}};
  if (r.misfit)
    out["predicted_error_with_misfit_mm"] = {
        {"misfit_rms_mm", rounded(r.misfit->misfit_mm, 6)},
        {"source", r.misfit->source},
        {"held_out_rms_mm", rounded(r.misfit->held_out_rms_mm, 6)},
        {"held_out_noise_mm", rounded(r.misfit->noise_mm, 6)},
        {"held_out_parameter_noise_mm", rounded(r.misfit->parameter_noise_mm, 6)},
        {"selected", {{"rms_mm", rounded(r.predicted_rms_with_misfit_selected, 6)}}},
        {"random", {{"rms_mm", rounded(r.predicted_rms_with_misfit_random, 6)}}}};
  out["out"] = written_to;
  return out;
}

}  // namespace robcal
