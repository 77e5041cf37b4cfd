#pragma once
/// \file
/// Calibration from measured hexapod sessions (`robcal hexapod calibrate`,
/// docs/method/07-hexapod.md §6): the world frame from the base cups, then either identification on
/// the tool fixture poses that the direct kinematics gives (`robcal calibrate` on them), or the fit
/// straight from the raw leg lengths with the cups and the ballbar's offset (leg_fit.hpp), written
/// in the frame of the pose fit. Sessions of several base-fixture placements calibrate together by
/// the leg fit, each placement with its own base cups (docs/method/08-world-frame.md §4).

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robcal/hexapod/leg_fit.hpp"
#include "robcal/hexapod/session_data.hpp"
#include "robcal/identify/identification.hpp"

namespace robcal::hexapod {

enum class SessionFit { Poses, Legs };
/// "poses" or "legs"; InputError (key "--fit") otherwise.
SessionFit parse_session_fit(const std::string& text);

/// The files written beside a calibration, or by `robcal hexapod export-poses` (empty: not
/// written): the tool fixture poses CSV (for `robcal calibrate`), the raw legs CSV, the tool file.
struct SessionExportPaths {
  std::string poses, legs, tool;
};

/// Files as (path, text), all rendered before any is written: an error on the way leaves none.
using RenderedFiles = std::vector<std::pair<std::string, std::string>>;

struct SessionCalibrationRequest {
  CalibrationLevel level = CalibrationLevel::Full;
  /// Opt-in groups or parameter patterns identified beyond the level (`calibrate --identify`).
  std::vector<std::string> identify;
  SessionFit fit = SessionFit::Poses;
  bool relative = false;  ///< hold the base (the published relative model); poses fit only
  double orientation_weight_mm = kDefaultOrientationWeightMm;
  uint64_t seed = 1;
  /// Poses and legs exports hold one placement: refused with sessions of several.
  SessionExportPaths exports;
};

struct SessionCalibration {
  SessionFit fit = SessionFit::Poses;
  bool relative = false;
  double orientation_weight_mm = 0;
  WorldFrameFit world;  ///< of the first placement: the calibrated model's frame
  std::vector<WorldFrameFit> placement_worlds;  ///< every placement's, in order
  Tool tool;                                    ///< the tool fixture's cups and the payload carried
  MeasurementSet poses;  ///< the tool fixture poses of the first placement (the poses fit's rows)
  std::optional<IdentificationResult> identification;  ///< poses fit
  std::optional<LegFitResult> legs;                    ///< legs fit
  CalibratedRobot robot;
  std::string model_file;  ///< the calibrated model file's text (with the fit's statistics)
  RenderedFiles exports;   ///< the request's exports, the poses being those fitted
};

/// Calibrates `model` carrying `payload` from the sessions' data, one SessionData per placement
/// (load_placements). Throws InputError for a bad request (orientation weight, the leg fit with
/// `relative`, the pose fit with several placements: it has one world frame; poses or legs
/// exports of several placements).
SessionCalibration calibrate_sessions(const std::vector<SessionData>& placements,
                                      const RobotModel& model, const PointMass& payload,
                                      const SessionCalibrationRequest& request);

/// A session's exports without calibrating (`robcal hexapod export-poses`): its world frame, the
/// tool fixture carrying `payload`, and the files of `paths`.
struct SessionExport {
  WorldFrameFit world;
  Tool tool;
  RenderedFiles files;
};
SessionExport export_session(const SessionData& data, const PointMass& payload,
                             const SessionExportPaths& paths);

/// session_summary_json and the files written: {…, poses, legs, tool} (paths, "" for none).
nlohmann::json session_export_json(const SessionData& data, const SessionExport& exported,
                                   const SessionExportPaths& paths);

/// {sessions, configurations_measured, configurations_to_retry, configurations_pending,
/// tool_sides_mm, base_sides_mm, world_frame_rms_mm}.
nlohmann::json session_summary_json(const SessionData& data, const WorldFrameFit& world);

/// The summary (over every placement; with several, `placements` holds each one's) and the
/// fit's figures, `output` naming the model file written.
nlohmann::json session_calibration_json(const std::vector<SessionData>& placements,
                                        const RobotModel& model,
                                        const SessionCalibration& calibration,
                                        const std::string& output);

}  // namespace robcal::hexapod
