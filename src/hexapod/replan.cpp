#include "robcal/hexapod/replan.hpp"

#include <nlohmann/json.hpp>

#include "robcal/core/units.hpp"
#include "robcal/kinematics/numeric_ik.hpp"

namespace robcal::hexapod {

Replan replan_retries(const SessionData& data, const CalibratedRobot& robot,
                      const std::string& model_file) {
  const WorldFrameFit world = session_world_frame(data);
  Replan out;
  out.retry = static_cast<int>(data.retry.size());
  out.plan = read_hexapod_plan(data.plan_file);
  SessionPlan& session = out.plan.session;
  session.configurations.clear();
  session.tool_sides = data.tool_fixture();
  session.base_sides = data.base_fixture();
  out.plan.replanned = Replanned{data.source, model_file, {}};
  for (const RetryConfiguration& r : data.retry) {
    // Newton from the planned joints on the preliminary model, for the flange pose that puts every
    // leg at the ballbar's length.
    const NumericIkResult ik = numeric_ik(robot.model, robot.tool.payload, robot.params,
                                          required_flange_pose(data, world, r), r.joints);
    if (ik.status != NumericIkStatus::Converged || !ik.within_limits) {
      out.failed.push_back({r.config, ik.status != NumericIkStatus::Converged
                                          ? to_string(ik.status)
                                          : "outside joint limits"});
      continue;
    }
    SessionConfiguration config;
    config.id = static_cast<int>(session.configurations.size()) + 1;
    config.pose = r.pose;
    config.mode = r.mode;
    config.labels = r.labels;
    config.legs = r.legs;
    std::vector<double> planned;
    for (int i = 0; i < kJointCount; ++i) {
      config.joints_deg.push_back(rad2deg(ik.joints[i]));
      planned.push_back(rad2deg(r.joints[i]));
    }
    session.configurations.push_back(config);
    out.plan.replanned->planned_joints_deg.push_back(planned);
  }
  return out;
}

nlohmann::json replan_json(const Replan& replan, const std::string& plan_file) {
  nlohmann::json failed = nlohmann::json::array();
  for (const ReplanFailure& f : replan.failed)
    failed.push_back({{"config", f.config}, {"why", f.why}});
  return {{"sessions", replan.plan.replanned->sessions},
          {"model", replan.plan.replanned->model},
          {"retry", replan.retry},
          {"replanned", replan.plan.session.configurations.size()},
          {"failed", failed},
          {"plan", plan_file}};
}

}  // namespace robcal::hexapod
