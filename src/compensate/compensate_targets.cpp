#include "robcal/compensate/compensate_targets.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <set>

#include "robcal/core/rounding.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"

namespace robcal {

namespace {

/// The condition `target` is reached under: its own approach, temperature, warm-up time and
/// payload where the targets file gives them (docs/method/10-compensation.md §6), the run's
/// otherwise.
ReachCondition condition_of(const Compensation& c, const WantedTarget& target,
                            const std::string& file) {
  ReachCondition condition = c.comp.condition;
  if (target.approach) condition.approach = *target.approach;
  if (target.temperature_c)
    condition.temperature_rise_k = *target.temperature_c - c.robot.model.reference_temperature_c;
  if (target.time_s) {
    condition.warmup_time_s = target.time_s;
    condition.warmup_fraction = warmup_fraction(c.robot.model, *target.time_s);
  }
  if (!target.payload.empty()) {
    const int index =
        payload_index_of(target.payload, c.robot.tool,
                         {file, target.line, target.payload_column, "payload"}, "the run's");
    condition.payload = c.robot.tool.payload_of(index);
    condition.payload_name = target.payload;
  }
  return condition;
}

bool has_own_condition(const WantedTarget& target) {
  return target.approach || target.temperature_c || target.time_s || !target.payload.empty();
}

}  // namespace

CompensateTargetsResult compensate_targets(const CompensateTargetsRequest& request) {
  const Compensation c = prepare_compensation(request.setup);
  CompensatorsByCondition compensators(c);
  std::vector<const Compensator*> comps;
  for (const WantedTarget& target : request.targets)
    comps.push_back(&compensators.at(condition_of(c, target, request.targets_file)));
  CompensateTargetsResult result;
  result.robot = c.robot.model.name;
  result.method = request.method;
  result.payload_kg = c.comp.condition.payload.mass_kg;
  result.conditions =
      static_cast<int>(std::set<const Compensator*>(comps.begin(), comps.end()).size());
  result.rows =
      correct_targets(comps, c.robot, request.targets, request.targets_file, request.method);
  if (request.truth)
    result.closed_loop = closed_loop_check(comps, *request.truth, request.targets, result.rows);
  result.csv = corrected_targets_csv(
      result.rows, c.robot.model,
      std::any_of(request.targets.begin(), request.targets.end(), has_own_condition));
  for (const CorrectedTarget& r : result.rows) {
    result.max_iterations = std::max(result.max_iterations, r.ik.iterations);
    result.max_residual_mm = std::max(result.max_residual_mm, r.ik.position_error_mm);
    if (r.confidence95_mm)
      result.max_confidence95_mm =
          std::max(result.max_confidence95_mm.value_or(0.0), *r.confidence95_mm);
  }
  if (!request.out.empty()) {
    write_file_atomically(request.out, result.csv);
    result.out = request.out;
  }
  return result;
}

namespace {

nlohmann::json stats_json(const ToolErrorStats& s) {
  return {{"count", s.count},
          {"mean_mm", rounded(s.mean_mm, 6)},
          {"rms_mm", rounded(s.rms_mm, 6)},
          {"max_mm", rounded(s.max_mm, 6)},
          {"mean_deg", rounded(s.mean_deg, 6)},
          {"max_deg", rounded(s.max_deg, 6)}};
}

}  // namespace

void to_json(nlohmann::json& j, const CompensateTargetsResult& result) {
  j = nlohmann::json::object();
  j["robot"] = result.robot;
  j["targets"] = result.rows.size();
  j["out"] = result.out;
  j["method"] = ik_method_name(result.method);
  j["payload_kg"] = result.payload_kg;
  j["conditions"] = result.conditions;
  j["max_iterations"] = result.max_iterations;
  j["max_residual_mm"] = result.max_residual_mm;
  j["max_confidence95_mm"] = result.max_confidence95_mm
                                 ? nlohmann::json(rounded(*result.max_confidence95_mm, 6))
                                 : nlohmann::json();
  if (result.closed_loop) {
    j["closed_loop"]["compensated"] = stats_json(result.closed_loop->compensated);
    j["closed_loop"]["uncompensated"] = stats_json(result.closed_loop->uncompensated);
  }
}

}  // namespace robcal
