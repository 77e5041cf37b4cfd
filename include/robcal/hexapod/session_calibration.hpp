#pragma once
/// \file
/// Calibration from measured hexapod sessions (`robcal hexapod calibrate`,
/// docs/method/07-hexapod.md): the world frame from the base cups, then either identification on
/// the tool fixture poses that the direct kinematics gives (`robcal calibrate` on them), or the fit
/// straight from the raw leg lengths with the cups and the ballbar's offset (leg_fit.hpp), written
/// in the frame of the pose fit.

#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "robcal/hexapod/leg_fit.hpp"
#include "robcal/hexapod/session_data.hpp"
#include "robcal/identify/identification.hpp"

namespace robcal::hexapod {

enum class SessionFit { Poses, Legs };
/// "poses" or "legs"; InputError (key "--fit") otherwise.
SessionFit parse_session_fit(const std::string& text);

struct SessionCalibrationRequest {
  CalibrationLevel level = CalibrationLevel::Full;
  SessionFit fit = SessionFit::Poses;
  bool relative = false;  ///< hold the base (the published relative model); poses fit only
  double orientation_weight_mm = kDefaultOrientationWeightMm;
  uint64_t seed = 1;
};

struct SessionCalibration {
  SessionFit fit = SessionFit::Poses;
  bool relative = false;
  double orientation_weight_mm = 0;
  WorldFrameFit world;
  Tool tool;             ///< the tool fixture's cups and the payload carried
  MeasurementSet poses;  ///< the tool fixture poses (the poses fit's rows)
  std::optional<IdentificationResult> identification;  ///< poses fit
  std::optional<LegFitResult> legs;                    ///< legs fit
  CalibratedRobot robot;
  std::string model_file;  ///< the calibrated model file's text (with the fit's statistics)
};

/// Calibrates `model` carrying `payload` from the sessions' data. Throws InputError for a bad
/// request (orientation weight, the leg fit with `relative`).
SessionCalibration calibrate_sessions(const SessionData& data, const RobotModel& model,
                                      const PointMass& payload,
                                      const SessionCalibrationRequest& request);

/// {sessions, configurations_measured, configurations_to_retry, configurations_pending,
/// tool_sides_mm, base_sides_mm, world_frame_rms_mm}.
nlohmann::json session_summary_json(const SessionData& data, const WorldFrameFit& world);

/// The summary and the fit's figures, `output` naming the model file written.
nlohmann::json session_calibration_json(const SessionData& data, const RobotModel& model,
                                        const SessionCalibration& calibration,
                                        const std::string& output);

}  // namespace robcal::hexapod
