#include "robcal/campaign/frames_workflow.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <utility>

#include "robcal/campaign/cell.hpp"
#include "robcal/campaign/frames_file.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal::campaign {
namespace {

/// The rows of a points file of the one target `target`. A row of another target names the flag
/// that chose `target`: the only "tool" here is that flag's value.
MeasurementSet read_target_rows(const std::string& path, const std::string& target) {
  Tool tool;
  tool.targets.push_back({target, Eigen::Vector3d::Zero(), false});
  try {
    return read_measurements_csv(path, tool, {MeasurementKind::Points}).measurements;
  } catch (const InputError& e) {
    if (e.where().key != "target") throw;
    throw InputError(
        fmt::format("{} (from --target {}: set --target to the target this file "
                    "measured)",
                    e.what(), target));
  }
}

/// The tool file to update (request.tool's, or a new tool), read with the other inputs before
/// any fit: a bad file is named first.
Tool tool_to_update(const TargetFrameRequest& request) {
  return request.tool.empty() ? Tool{} : load_tool(request.tool);
}

/// `tool` with the target at `point`, as a file with the estimate and `source` in a comment.
TargetFrameResult target_result(const TargetFrameRequest& request, const RobotModel& model,
                                Tool tool, const PointEstimate& point, const std::string& source) {
  int index = tool.target_index(request.target);
  if (index < 0) {
    tool.targets.push_back({request.target, Eigen::Vector3d::Zero(), true});
    index = static_cast<int>(tool.targets.size()) - 1;
  }
  tool.targets[static_cast<size_t>(index)] = {request.target, point.position_mm, true};
  const Eigen::Vector3d& p = point.position_mm;
  const std::string text = fmt::format(
      "# target {} from {}: [{:.4f}, {:.4f}, {:.4f}] ± [{:.4f}, {:.4f}, {:.4f}] mm (1σ), noise σ "
      "{:.4f} mm\n{}",
      request.target, source, p.x(), p.y(), p.z(), point.sigma.x(), point.sigma.y(),
      point.sigma.z(), point.sigma_mm, tool_to_yaml(tool));
  return {model.name, request.target, point, text};
}

/// --sigma-mm: 0 estimates the noise from the fit residuals; a tracker or CMM reads to
/// hundredths of a millimetre, so beyond 10 mm per axis it is a typo or a unit slip.
void check_sigma_mm(double sigma_mm) {
  if (!(sigma_mm >= 0 && sigma_mm <= 10))
    throw InputError({"", 0, 0, "--sigma-mm"},
                     fmt::format("expected 0 (estimated from the fit residuals) or an instrument "
                                 "noise per axis above 0 and at most 10 mm, found {:g}",
                                 sigma_mm));
}

}  // namespace

BaseFrameResult frames_base(const BaseFrameRequest& request) {
  check_sigma_mm(request.sigma_mm);
  const RobotModel model = load_robot(request.robot);
  // Every file read before the fits: a bad one is named before the fits can fail.
  const MeasurementSet rows1 = read_target_rows(request.joint1, request.target);
  const MeasurementSet rows2 = read_target_rows(request.joint2, request.target);
  const std::string cell = request.cell.empty() ? "" : read_text_file(request.cell);
  const JointSweep s1 = sweep_from_measurements(rows1, 1, model);
  const JointSweep s2 = sweep_from_measurements(rows2, 2, model);
  BaseFrameResult result{model.name, base_from_sweeps(model, s1, s2, request.sigma_mm), ""};
  const std::string comment = fmt::format(
      "robot base of {} from circle fits of the joint-1 sweep {} ({} readings) and the joint-2 "
      "sweep {} ({} readings) of target {} (robcal frames base)",
      model.name, request.joint1, s1.points_mm.size(), request.joint2, s2.points_mm.size(),
      request.target);
  result.text = request.cell.empty() ? "# " + comment + "\n" + robot_base_block(result.base)
                                     : cell_with_base(cell, request.cell, result.base, comment);
  return result;
}

TargetFrameResult frames_tool(const TargetFrameRequest& request) {
  check_sigma_mm(request.sigma_mm);
  const RobotModel model = load_robot(request.robot);
  const MeasurementSet rows5 = read_target_rows(request.first, request.target);
  const MeasurementSet rows6 = read_target_rows(request.second, request.target);
  Tool tool = tool_to_update(request);
  const JointSweep s5 = sweep_from_measurements(rows5, 5, model);
  const JointSweep s6 = sweep_from_measurements(rows6, 6, model);
  return target_result(request, model, std::move(tool),
                       tool_from_sweeps(model, s5, s6, request.sigma_mm),
                       fmt::format("circle fits of the joint-5 sweep {} and the joint-6 sweep {} "
                                   "(robcal frames tool)",
                                   request.first, request.second));
}

TargetFrameResult frames_point(const TargetFrameRequest& request) {
  check_sigma_mm(request.sigma_mm);
  const RobotModel model = load_robot(request.robot);
  const Cell cell = load_cell(request.cell);
  Tool tool = tool_to_update(request);
  const MeasurementSet set = read_target_rows(request.first, request.target);
  return target_result(
      request, model, std::move(tool),
      tool_point_from_measurements(model, cell.robot_params(model), set, request.sigma_mm),
      fmt::format("{} rows of {} with the nominal robot at the base of {} (robcal frames point)",
                  set.points.size(), request.first, request.cell));
}

NestFrameResult frames_world(const NestFrameRequest& request) {
  check_sigma_mm(request.sigma_mm);
  NestFrameResult result;
  result.frame =
      frame_from_named_nests({request.measured, read_text_file(request.measured)},
                             {request.nominal, read_text_file(request.nominal)}, request.sigma_mm);
  result.instrument_mm = result.frame.pose.inverse().p;
  const Eigen::Vector3d& i = result.instrument_mm;
  result.text =
      frame_yaml("frame", result.frame,
                 fmt::format("the frame of {} (nest coordinates) in the instrument's frame, "
                             "fitted to the nests measured in {} (robcal frames world)",
                             request.nominal, request.measured)) +
      fmt::format("instrument_position_mm: [{}, {}, {}]  # the instrument in that frame\n", i.x(),
                  i.y(), i.z());
  return result;
}

nlohmann::json frame_estimate_json(const FrameEstimate& f) {
  return {{"position_mm", {f.values[0], f.values[1], f.values[2]}},
          {"rotation_xyz_deg", {rad2deg(f.values[3]), rad2deg(f.values[4]), rad2deg(f.values[5])}},
          {"sigma_position_mm", {f.sigma[0], f.sigma[1], f.sigma[2]}},
          {"sigma_rotation_deg", {rad2deg(f.sigma[3]), rad2deg(f.sigma[4]), rad2deg(f.sigma[5])}},
          {"sigma_noise_mm", f.sigma_mm},
          {"rms_mm", f.rms_mm}};
}

nlohmann::json target_estimate_json(const std::string& target, const PointEstimate& t) {
  return {{"target", target},
          {"position_mm", {t.position_mm.x(), t.position_mm.y(), t.position_mm.z()}},
          {"sigma_mm", {t.sigma.x(), t.sigma.y(), t.sigma.z()}},
          {"sigma_noise_mm", t.sigma_mm},
          {"rms_mm", t.rms_mm}};
}

nlohmann::json nest_frame_json(const NestFrameResult& result) {
  const Eigen::Vector3d& i = result.instrument_mm;
  return {{"frame", frame_estimate_json(result.frame)},
          {"instrument_position_mm", {i.x(), i.y(), i.z()}}};
}

}  // namespace robcal::campaign
