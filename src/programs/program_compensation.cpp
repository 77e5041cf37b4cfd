#include "robcal/programs/program_compensation.hpp"

#include <nlohmann/json.hpp>

#include "robcal/compensate/corrected_targets.hpp"
#include "robcal/programs/frames_file.hpp"

namespace robcal {

namespace {

/// The robot file's pulses per degree unless the options give their own.
ProgramFilterOptions with_robot_pulses(ProgramFilterOptions options, const Compensation& c) {
  if (options.pulses_per_degree[0] <= 0) options.pulses_per_degree = c.pulses_per_degree;
  return options;
}

}  // namespace

ProgramCompensationResult compensate_program_text(const Compensation& compensation,
                                                  std::string_view text, ProgramLanguage language,
                                                  const std::string& file,
                                                  const ProgramFilterOptions& options) {
  ProgramCompensationResult result;
  result.in = file;
  result.language = language;
  result.filter =
      filter_program(text, language, file, with_robot_pulses(options, compensation),
                     make_program_corrector(compensation.comp, language, &compensation.robot));
  return result;
}

ProgramCompensationResult compensate_krl_module_text(const Compensation& compensation,
                                                     std::string_view src, std::string_view dat,
                                                     const std::string& src_file,
                                                     const std::string& dat_file,
                                                     const ProgramFilterOptions& options) {
  ProgramCompensationResult result;
  result.in = src_file;
  result.language = ProgramLanguage::Krl;
  result.filter = filter_krl_module(
      src, dat, src_file, dat_file, options,
      make_program_corrector(compensation.comp, ProgramLanguage::Krl, &compensation.robot));
  return result;
}

ProgramCompensationResult compensate_program(const ProgramCompensationRequest& request) {
  const Compensation compensation = prepare_compensation(request.setup);
  const ProgramLanguage language = program_language_from_path(request.in);
  ProgramFilterOptions options = with_robot_pulses(request.options, compensation);
  if (!request.frames_file.empty()) {
    FramesFile frames = read_frames_file(request.frames_file);
    options.tools.merge(frames.tools);
    options.frames.merge(frames.frames);
  }
  ProgramCompensationResult result;
  result.in = request.in;
  result.out = request.out;
  result.language = language;
  CompensatorsByCondition by_condition(compensation);
  ApproachCompensators by_approach;
  if (request.approach_from_motion)
    by_approach = [&](const Vector6d& approach) -> const Compensator& {
      ReachCondition condition = compensation.comp.condition;
      condition.approach = approach;
      return by_condition.at(condition);
    };
  result.filter = filter_program_file(
      request.in, request.out, options,
      make_program_corrector(compensation.comp, language, &compensation.robot, by_approach),
      request.confidence_out);
  if (result.filter.dat_text) result.out_companion = krl_companion_path(request.out);
  return result;
}

namespace {

nlohmann::json points_json(const std::vector<UncorrectedPoint>& points) {
  nlohmann::json out = nlohmann::json::array();
  for (const UncorrectedPoint& u : points)
    out.push_back({{"where", u.where}, {"reason", u.reason}});
  return out;
}

}  // namespace

void to_json(nlohmann::json& j, const ProgramCompensationResult& result) {
  j = {{"in", result.in},
       {"out", result.out},
       {"out_companion", result.out_companion},
       {"language", program_language_name(result.language)},
       {"cartesian_points", result.filter.cartesian_points},
       {"joint_points", result.filter.joint_points},
       {"uncorrected", points_json(result.filter.uncorrected)},
       {"assumed", points_json(result.filter.assumed)},
       {"assumed_default_tool_and_frame", result.filter.assumed.size()}};
}

}  // namespace robcal
