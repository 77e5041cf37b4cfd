#include "robcal/hexapod/end_to_end_report.hpp"

#include <nlohmann/json.hpp>

#include "robcal/core/rounding.hpp"
#include "robcal/validate/error_statistics_json.hpp"

namespace robcal::hexapod {
namespace {

nlohmann::json figures_json(const ValidationFigures& f) {
  return {{"absolute", error_statistics_json(f.absolute, "mm", 6)},
          {"pairs", error_statistics_json(f.pairs, "mm", 6)}};
}

nlohmann::json stage_json(const CalibrationStage& s) {
  return {{"configurations", s.configurations},
          {"rms_mm", rounded(s.rms_mm, 6)},
          {"iterations", s.iterations},
          {"converged", s.converged},
          {"validation", figures_json(s.validation)}};
}

}  // namespace

nlohmann::json end_to_end_json(const EndToEndReport& r, const EndToEndOptions& options,
                               uint64_t seed) {
  nlohmann::json out{
      {"robot", r.robot},
      {"seed", seed},
      {"poses_enumerated", r.poses_enumerated},
      {"poses_refused_cups", r.poses_refused},
      {"poses_kept", r.poses_kept},
      {"gauge", {{"range_mm", options.cell.range_mm}, {"sigma_mm", options.cell.sigma_mm}}},
      {"poses_measurable", r.poses_measurable},
      {"configurations_planned", r.configurations_planned},
      {"measured_first_pass", r.measured_first},
      {"out_of_range_first_pass", r.retried},
      {"measured_after_replanning", r.measured_after_replan},
      {"legs_read", r.legs_read},
      {"legs_read_tool_cup4", r.legs_read_fourth_cup},
      {"world_frame_rms_mm", rounded(r.world_frame_rms_mm, 6)},
      {"world_frame_error_mm", rounded(r.world_frame_error_mm, 6)},
      {"world_frame_error_deg", rounded(r.world_frame_error_deg, 6)},
      {"relative_pose_fit", options.relative_pose_fit},
      {"validation_configurations", r.validation_configurations},
      {"nominal", figures_json(r.nominal)},
      {"preliminary", stage_json(r.preliminary)},
      {"final", stage_json(r.final_pose_fit)}};
  if (options.cell.design.tool_cup4_mm) out["tool_cup4_mm"] = *options.cell.design.tool_cup4_mm;
  if (options.cell.design.base_cup4_mm) {
    out["base_cup4_mm"] = *options.cell.design.base_cup4_mm;
    out["legs_read_base_cup4"] = r.legs_read_base_cup4;
  }
  if (options.leg_fit) {
    out["leg_fit"] = stage_json(r.leg_fit);
    out["leg_fit"]["length_offset_mm"] = rounded(r.leg_fit_offset_mm, 6);
    if (r.leg_fit_base_cup4_error_mm)
      out["leg_fit"]["base_cup4_error_mm"] = rounded(*r.leg_fit_base_cup4_error_mm, 6);
    if (r.leg_fit_base_cup4_distance_error_mm)
      out["leg_fit"]["base_cup4_distance_error_mm"] =
          rounded(*r.leg_fit_base_cup4_distance_error_mm, 6);
  }
  // The published run on a real LR Mate 200iC (docs/method/08-world-frame.md §3), for comparison.
  out["published"] = {{"poses", 46},
                      {"configurations", 124},
                      {"nominal_mean_mm", 1.355},
                      {"front_up_46_mean_max_mm", {0.517, 1.223}},
                      {"all_61_mean_max_mm", {0.796, 1.630}},
                      {"pairs_before_mean_mm", 1.062},
                      {"pairs_after_mean_max_mm", {0.400, 1.666}},
                      {"laser_tracker_50_mean_max_mm", {0.156, 0.490}}};
  return out;
}

}  // namespace robcal::hexapod
