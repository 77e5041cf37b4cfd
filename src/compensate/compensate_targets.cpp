#include "robcal/compensate/compensate_targets.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "robcal/core/rounding.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal {

CompensateTargetsResult compensate_targets(const CompensateTargetsRequest& request) {
  const Compensation c = prepare_compensation(request.setup);
  CompensateTargetsResult result;
  result.robot = c.robot.model.name;
  result.method = request.method;
  result.payload_kg = c.comp.payload.mass_kg;
  result.rows =
      correct_targets(c.comp, c.robot, request.targets, request.targets_file, request.method);
  if (request.truth)
    result.closed_loop = closed_loop_check(c.comp, *request.truth, request.targets, result.rows);
  result.csv = corrected_targets_csv(result.rows, c.robot.model);
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
