#include "robcal/hexapod/session_calibration.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <nlohmann/json.hpp>

#include "robcal/core/error.hpp"
#include "robcal/core/rounding.hpp"
#include "robcal/hexapod/measurement.hpp"
#include "robcal/identify/calibration_output.hpp"
#include "robcal/identify/fit_error_json.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal::hexapod {
namespace {

/// The poses CSV, the raw legs CSV and the tool file, for those of the paths given.
RenderedFiles export_files(const SessionData& data, const Tool& tool, const MeasurementSet& poses,
                           const SessionExportPaths& paths) {
  RenderedFiles files;
  if (!paths.poses.empty())
    files.emplace_back(
        paths.poses,
        write_measurements_csv(poses, tool,
                               fmt::format("tool fixture poses of {} by the ballbar hexapod's "
                                           "direct kinematics, robot frame through the world "
                                           "frame of the base cups",
                                           data.source)));
  if (!paths.legs.empty()) files.emplace_back(paths.legs, session_legs_csv(data));
  if (!paths.tool.empty()) files.emplace_back(paths.tool, tool_to_yaml(tool));
  return files;
}

/// The fit from the raw legs: the level's link and compliance parameters and the groups asked
/// for, the cups and the ballbar's offset; written in the frame of the pose fit.
void fit_legs(const std::vector<SessionData>& placements, const RobotModel& model,
              const SessionCalibrationRequest& request, SessionCalibration& out) {
  LegFitOptions options;
  for (int i : identified_model_parameters(model, out.tool, MeasurementKind::Poses, request.level,
                                           request.identify))
    if (i >= kBaseParamCount) options.free_parameters.push_back(i);
  std::vector<LegPlacement> legs;
  for (size_t p = 0; p < placements.size(); ++p)
    legs.push_back({placements[p].base_fixture(), placements[p].readings,
                    out.placement_worlds[p].robot_T_fixture});
  const SessionData& first = placements.front();
  const LegFitResult fit = fit_from_legs(model, out.tool.payload, first.tool_fixture(), legs,
                                         model.nominal(), first.flange_T_tool, options);
  out.robot = leg_fit_robot(model, out.tool.payload, fit, out.world.robot_T_fixture);
  out.robot.level = level_name(request.level);
  YAML::Node stats;
  stats["leg_fit"]["residuals"] = fit.residuals;
  stats["leg_fit"]["initial_rms_mm"] = fit.initial_rms_mm;
  stats["leg_fit"]["rms_mm"] = fit.rms_mm;
  stats["leg_fit"]["sigma_mm"] = fit.sigma_mm;  // a-posteriori σ̂, the stds' scale
  stats["leg_fit"]["iterations"] = fit.iterations;
  stats["leg_fit"]["converged"] = fit.converged;
  stats["leg_fit"]["ballbar_length_offset_mm"] = fit.length_offset_mm;
  for (const std::string& h : fit.held) stats["leg_fit"]["held"].push_back(h);
  out.model_file = calibrated_robot_to_yaml(out.robot, [&stats](YAML::Emitter& e) { e << stats; });
  out.legs = fit;
}

}  // namespace

SessionFit parse_session_fit(const std::string& text) {
  if (text == "poses") return SessionFit::Poses;
  if (text == "legs") return SessionFit::Legs;
  throw InputError({"", 0, 0, "--fit"},
                   fmt::format("unknown fit '{}': expected poses or legs", text));
}

SessionExport export_session(const SessionData& data, const PointMass& payload,
                             const SessionExportPaths& paths) {
  SessionExport out;
  out.world = session_world_frame(data);
  out.tool = hexapod_tool(payload, data.flange_T_tool, data.tool_sides);
  out.files = export_files(data, out.tool, session_pose_measurements(data), paths);
  return out;
}

nlohmann::json session_export_json(const SessionData& data, const SessionExport& exported,
                                   const SessionExportPaths& paths) {
  nlohmann::json out = session_summary_json(data, exported.world);
  out["poses"] = paths.poses;
  out["legs"] = paths.legs;
  out["tool"] = paths.tool;
  return out;
}

SessionCalibration calibrate_sessions(const std::vector<SessionData>& placements,
                                      const RobotModel& model, const PointMass& payload,
                                      const SessionCalibrationRequest& request) {
  if (placements.empty()) throw InputError({"", 0, 0, "--session"}, "expected a session");
  if (request.fit == SessionFit::Legs && request.relative)
    throw InputError({"", 0, 0, "--relative"}, "the leg fit always identifies the base cups");
  if (request.fit == SessionFit::Poses && placements.size() > 1)
    throw InputError(
        {placements[1].source, 0, 0, "--fit"},
        fmt::format("sessions of {} base-fixture placements: the pose fit has one world frame; "
                    "calibrate them together with --fit legs (each placement's base cups are "
                    "identified, docs/method/08-world-frame.md §4)",
                    placements.size()));
  if (placements.size() > 1)
    for (const auto& [flag, path] : {std::pair{"--poses-out", &request.exports.poses},
                                     std::pair{"--legs-out", &request.exports.legs}})
      if (!path->empty())
        throw InputError({*path, 0, 0, flag},
                         fmt::format("sessions of {} placements: export each placement's sessions "
                                     "with `robcal hexapod export-poses`",
                                     placements.size()));
  check_orientation_weight(request.orientation_weight_mm);
  const SessionData& data = placements.front();
  SessionCalibration out;
  out.fit = request.fit;
  out.relative = request.relative;
  out.orientation_weight_mm = request.orientation_weight_mm;
  for (const SessionData& p : placements) out.placement_worlds.push_back(session_world_frame(p));
  out.world = out.placement_worlds.front();
  out.tool = hexapod_tool(payload, data.flange_T_tool, data.tool_sides);
  out.poses = session_pose_measurements(data);
  out.exports = export_files(data, out.tool, out.poses, request.exports);
  if (request.fit == SessionFit::Legs) {
    fit_legs(placements, model, request, out);
    return out;
  }
  IdentifyOptions options;
  options.level = request.level;
  options.identify = request.identify;
  if (request.relative) options.fix = {"base.*"};
  options.orientation_weight_mm = request.orientation_weight_mm;
  options.seed = request.seed;
  IdentificationResult r = calibrate(model, out.tool, out.poses, options);
  // The poses are in the robot frame of the world the base cups define: the model's frame is that
  // world even when its base is held (the relative model).
  r.robot.base_fitted = true;
  out.robot = r.robot;
  out.model_file = calibrated_robot_to_yaml(r.robot, statistics_writer(r));
  out.identification = std::move(r);
  return out;
}

nlohmann::json session_summary_json(const SessionData& data, const WorldFrameFit& world) {
  nlohmann::json retry = nlohmann::json::array();
  for (const RetryConfiguration& r : data.retry) retry.push_back(r.config);
  nlohmann::json out{{"sessions", data.source},
                     {"configurations_measured", data.readings.size()},
                     {"configurations_to_retry", retry},
                     {"configurations_pending", data.pending},
                     {"tool_sides_mm", data.tool_sides.as_array()},
                     {"base_sides_mm", data.base_sides.as_array()},
                     {"world_frame_rms_mm", rounded(world.rms_mm)}};
  if (data.tool_cup4_mm) out["tool_cup4_mm"] = *data.tool_cup4_mm;
  if (data.base_cup4_mm) out["base_cup4_mm"] = *data.base_cup4_mm;
  return out;
}

nlohmann::json session_calibration_json(const std::vector<SessionData>& placements,
                                        const RobotModel& model, const SessionCalibration& c,
                                        const std::string& output) {
  const SessionData& data = placements.front();
  nlohmann::json out = session_summary_json(data, c.world);
  size_t readings = data.readings.size();
  if (placements.size() > 1) {
    out["placements"] = nlohmann::json::array();
    std::string sources;
    readings = 0;
    int pending = 0;
    for (size_t p = 0; p < placements.size(); ++p) {
      out["placements"].push_back(session_summary_json(placements[p], c.placement_worlds[p]));
      sources += (p > 0 ? ", " : "") + placements[p].source;
      readings += placements[p].readings.size();
      pending += placements[p].pending;
      for (const RetryConfiguration& r : placements[p].retry)
        if (p > 0) out["configurations_to_retry"].push_back(r.config);
    }
    out["sessions"] = sources;
    out["configurations_measured"] = readings;
    out["configurations_pending"] = pending;
  }
  out["robot"] = model.name;
  out["level"] = c.robot.level;
  if (c.legs) {
    const LegFitResult& fit = *c.legs;
    out["fit"] = "legs";
    out["rows"] = readings;
    out["residuals"] = fit.residuals;
    out["converged"] = fit.converged;
    out["iterations"] = fit.iterations;
    out["identified"] = fit.identified.size();
    out["held"] = fit.held;
    out["initial_rms_mm"] = rounded(fit.initial_rms_mm);
    out["rms_mm"] = rounded(fit.rms_mm);
    out["ballbar_length_offset_mm"] = rounded(fit.length_offset_mm);
    // A fitted fourth base cup by its distances to B1..B3 (next to the measured base_cup4_mm).
    for (size_t p = 0; p < fit.base_cup4_robot.size(); ++p)
      if (const auto& b4 = fit.base_cup4_robot[p]) {
        nlohmann::json d = nlohmann::json::array();
        for (const Eigen::Vector3d& b : fit.base_cups_robot[p])
          d.push_back(rounded((*b4 - b).norm()));
        (placements.size() > 1 ? out["placements"][p] : out)["base_cup4_fitted_mm"] = d;
      }
  } else {
    const IdentificationResult& r = *c.identification;
    out["relative"] = c.relative;
    out["orientation_weight_mm_per_rad"] = c.orientation_weight_mm;
    out["rows"] = c.poses.size();
    out["converged"] = r.status.converged;
    out["iterations"] = r.status.iterations;
    out["identified"] = r.identified_count;
    // One definition (the per-row 3D TCP error), at the solution and at the start, as
    // `robcal calibrate` reports it.
    out.update(residual_per_row_json(r, 9));
    out["rms_mm"] = rounded(r.rms_mm);
    out["max_mm"] = rounded(r.max_mm);
    out["sigma_mm"] = rounded(r.sigma_mm);
    out["predicted_mean_mm"] = rounded(r.predicted.mean_mm);
  }
  out["output"] = output;
  return out;
}

}  // namespace robcal::hexapod
