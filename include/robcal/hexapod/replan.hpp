#pragma once
/// \file
/// The re-plan of `robcal hexapod replan` (docs/method/07-hexapod.md §5, the two-stage
/// calibration): the configurations whose legs were out of the ballbar's range, solved again on the
/// preliminary model for the flange pose that puts every leg at the ballbar's length. The new plan
/// keeps the first plan's cell and the fixture sides already measured, so the next session asks
/// only for the legs.

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robcal/hexapod/plan_file.hpp"
#include "robcal/hexapod/session_data.hpp"
#include "robcal/identify/calibrated_robot.hpp"

namespace robcal::hexapod {

struct ReplanFailure {
  std::string config;  ///< the retry's label
  std::string why;     ///< the numeric IK's status, or "outside joint limits"
};

struct Replan {
  HexapodPlan plan;                   ///< the plan of the next session
  int retry = 0;                      ///< configurations to retry
  std::vector<ReplanFailure> failed;  ///< those the preliminary model cannot reach
};

/// Re-plans the retries of `data` (its first plan file read again) on `robot`, whose file is
/// `model_file` (kept in the plan).
Replan replan_retries(const SessionData& data, const CalibratedRobot& robot,
                      const std::string& model_file);

/// {sessions, model, retry, replanned, failed: [{config, why}], plan: `plan_file`}.
nlohmann::json replan_json(const Replan& replan, const std::string& plan_file);

}  // namespace robcal::hexapod
