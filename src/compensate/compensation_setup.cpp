#include "robcal/compensate/compensation_setup.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "robcal/core/error.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/pose_list_file.hpp"

namespace robcal {

namespace {

/// The payload `setup.payload_name` of the tool in use (--tool, else the model's).
PointMass named_payload(const CompensationSetup& setup, const Tool& model_tool) {
  if (setup.payload)
    throw InputError({"", 0, 0, "--payload"},
                     "give the payload either by name (--payload) or by --payload-mass-kg and "
                     "--payload-cog-mm, not both");
  const Tool& tool = setup.tool ? *setup.tool : model_tool;
  const int index = tool.payload_index(setup.payload_name);
  if (index < 0) {
    std::vector<std::string> names;
    for (const NamedPayload& p : tool.payloads) names.push_back("'" + p.name + "'");
    throw InputError(
        {"", 0, 0, "--payload"},
        fmt::format("the tool has no payload '{}': expected one of its 'payloads:' "
                    "({})",
                    setup.payload_name,
                    names.empty() ? "it lists none" : fmt::format("{}", fmt::join(names, ", "))));
  }
  return tool.payload_of(index);
}

}  // namespace

Compensation prepare_compensation(const CompensationSetup& setup) {
  CalibratedRobot robot = setup.robot;
  if (!setup.expected_robot.empty() && setup.expected_robot != robot.model.name)
    throw InputError({setup.model_file, 0, 0, "--robot"},
                     fmt::format("the model is a calibrated {}, not a {}", robot.model.name,
                                 setup.expected_robot));
  if (setup.tool) {
    robot.tool.flange_T_tcp = setup.tool->flange_T_tcp;
    robot.tool.payload = setup.tool->payload;
    robot.tool.payloads = setup.tool->payloads;  // the names targets may give (§7)
  }
  if (setup.payload) {
    // A payload beyond any industrial arm's rating is a unit mistake (g for kg), not a load.
    if (!(setup.payload->mass_kg >= 0 && setup.payload->mass_kg < 1e4))
      throw InputError({"", 0, 0, "--payload-mass-kg"}, "expected a mass in kg, 0 or more");
    if (!setup.payload->cog_mm.allFinite())
      throw InputError({"", 0, 0, "--payload-cog-mm"},
                       "expected a finite centre of gravity x,y,z in mm");
  }
  ReachCondition run;
  run.payload = setup.payload.value_or(robot.tool.payload);
  if (!setup.payload_name.empty()) {
    run.payload = named_payload(setup, robot.tool);
    run.payload_name = setup.payload_name;
  }
  if (setup.temperature_c && !plausible_temperature_c(*setup.temperature_c))
    throw InputError({"", 0, 0, "--temperature-c"}, "expected a temperature in °C in [-50, 150]");
  run.temperature_rise_k =
      setup.temperature_c ? *setup.temperature_c - robot.model.reference_temperature_c : 0.0;
  if (setup.warmup_time_s &&
      (!(*setup.warmup_time_s >= 0 && *setup.warmup_time_s <= 1e7) || setup.warm))
    throw InputError({"", 0, 0, "--warmup-time-s"},
                     setup.warm ? "give either the warm-up time or --warm, not both"
                                : "expected seconds in [0, 1e7] since the arm started working");
  run.warmup_time_s = setup.warm ? std::optional(kFullyWarmS) : setup.warmup_time_s;
  run.warmup_fraction = run.warmup_time_s ? warmup_fraction(robot.model, *run.warmup_time_s) : 0.0;
  run.approach = setup.approach;
  Compensation out{robot, make_compensator(robot, run), setup.pulses_per_degree};
  return out;
}

CompensatorsByCondition::CompensatorsByCondition(const Compensation& run) : run_(run) {}

CompensatorsByCondition::Key CompensatorsByCondition::key_of(const ReachCondition& c) {
  const Vector6d& a = c.approach;
  const Eigen::Vector3d& g = c.payload.cog_mm;
  return {{a[0], a[1], a[2], a[3], a[4], a[5]},
          c.temperature_rise_k,
          c.warmup_fraction,
          c.warmup_time_s.value_or(-1.0),  // none: cold (a time is never negative)
          c.payload.mass_kg,
          {g.x(), g.y(), g.z()},
          c.payload_name};
}

const Compensator& CompensatorsByCondition::at(const ReachCondition& condition) {
  if (condition == run_.comp.condition) return run_.comp;
  const Key key = key_of(condition);
  auto it = made_.find(key);
  if (it == made_.end()) it = made_.emplace(key, make_compensator(run_.robot, condition)).first;
  return it->second;
}

IkMethod ik_method_from_name(const std::string& name, const std::string& key) {
  if (name == "newton") return IkMethod::Newton;
  if (name == "pose-shift") return IkMethod::PoseShift;
  throw InputError({"", 0, 0, key}, "expected newton or pose-shift, found '" + name + "'");
}

const char* ik_method_name(IkMethod method) {
  return method == IkMethod::Newton ? "newton" : "pose-shift";
}

}  // namespace robcal
