#include "robcal/identify/calibration_run.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "robcal/core/error.hpp"

#include <cmath>
#include <set>

namespace robcal {

std::vector<std::string> implausible_parameters(const IdentificationResult& result) {
  std::vector<std::string> out;
  for (int i = kLinkParamOffset; i < kParameterCount; ++i) {
    const UnknownEstimate& u = result.unknowns[static_cast<size_t>(i)];
    if (u.status != ParameterStatus::Identified) continue;
    const ParamKind kind = parameter_table()[static_cast<size_t>(i)].kind;
    const double change = u.value - u.nominal;
    if (kind == ParamKind::Length && std::abs(change) > 20)
      out.push_back(
          fmt::format("{} moved {:+.3f} mm from nominal (more than 20 mm)", u.name, change));
    if (kind == ParamKind::Angle && std::abs(change) > 5)
      out.push_back(fmt::format("{} moved {:+.3f}° from nominal (more than 5°)", u.name, change));
    if (kind == ParamKind::Scale && std::abs(u.value - 1) > 0.01)
      out.push_back(fmt::format("{} is {:.5f} (more than 1 % from 1)", u.name, u.value));
    if (kind == ParamKind::Compliance && std::abs(u.value) > kImplausibleComplianceRadPerNmm)
      out.push_back(fmt::format(
          "{} is {:.3g} {}: more than {:g} in magnitude, a joint that would turn 1 rad under "
          "{:.3g} N·m",
          u.name, u.value, u.unit, kImplausibleComplianceRadPerNmm, 1e-3 / std::abs(u.value)));
    else if (kind == ParamKind::Compliance && u.value + 3 * u.std_dev < 0)
      out.push_back(fmt::format("{} is {:.3g} ± {:.2g} {}: a negative compliance", u.name, u.value,
                                u.std_dev, u.unit));
    if (kind == ParamKind::Expansion && std::abs(u.value) > 100)
      out.push_back(fmt::format("{} is {:.1f} ppm/K (metals expand 10–25 ppm/K)", u.name, u.value));
  }
  return out;
}

CalibrationRun run_calibration(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const CalibrationRequest& request) {
  CalibrationRun run;
  run.options = request.options;
  run.kind = data.kind;
  run.rows = data.size();
  run.file = data.file;
  run.result = calibrate(model, tool, data, request.options);
  const IdentificationResult& r = run.result;
  run.warnings = r.warnings;
  std::set<std::string> configs;
  for (size_t row = 0; row < data.size(); ++row)
    configs.insert(data.kind == MeasurementKind::Points  ? data.points[row].config
                   : data.kind == MeasurementKind::Poses ? data.poses[row].config
                                                         : data.distances[row].config);
  if (!request.folds.empty()) {
    run.cross_validation = cross_validate(model, tool, data, request.options, request.folds);
    if (request.kfold != 0 && request.kfold != run.cross_validation->folds)
      throw InputError({"", 0, 0, "--kfold"},
                       fmt::format("--kfold {} but the folds file has {} folds", request.kfold,
                                   run.cross_validation->folds));
  }
  int folds = request.folds.empty() ? request.kfold : 0;
  if (folds == 0 && !r.noise_test.consistent &&
      static_cast<int>(configs.size()) >= 2 * kMisfitFolds) {
    folds = kMisfitFolds;
    run.cross_validation_for_misfit = true;
  }
  if (folds != 0)
    run.cross_validation =
        cross_validate(model, tool, data, request.options, folds, request.options.seed);

  const std::string check =
      "check the robot (--robot: is it this arm's model?), the units of the measurement file "
      "('# units:' header), the tool's target coordinates and the joint columns";
  if (!r.status.converged)
    run.problems.push_back(
        fmt::format("the solver did not converge ({}): {}", r.status.message, check));
  if (r.rms_mm > kImplausibleResidualMm)
    run.problems.push_back(fmt::format(
        "the residuals stay at rms {:.3f} mm (mean {:.3f}, max {:.3f} mm) after the fit, more "
        "than the {:g} mm a calibrated arm leaves: {}",
        r.rms_mm, r.mean_mm, r.max_mm, kImplausibleResidualMm, check));
  else if (r.noise_test.tested &&
           r.sigma_mm > kImplausibleNoiseRatio * r.noise_test.instrument_sigma_mm)
    run.problems.push_back(fmt::format(
        "the residual σ {:.4f} mm is more than {:g} times the instrument's σ {:.4f} mm: {}",
        r.sigma_mm, kImplausibleNoiseRatio, r.noise_test.instrument_sigma_mm, check));
  for (const std::string& p : implausible_parameters(r))
    run.problems.push_back(
        fmt::format("{}: no real arm is that far from its data sheet; {}", p, check));
  return run;
}

namespace {

/// The new tool of level tool with every target (points) or its TCP frame (poses) free, after
/// checking that the data measure each of them often enough.
Tool tool_to_identify(Tool tool, const MeasurementSet& data) {
  if (data.kind == MeasurementKind::Distances)
    throw InputError({data.file, 0, 0, "--level"},
                     "--level tool identifies tool points from a points file or a TCP frame from "
                     "a poses file, not from ballbar distances");
  const std::string why = fmt::format(
      "a new tool {} needs at least {} measured configurations ({} unknowns, and enough "
      "redundancy for their σ): measure it in more configurations",
      data.kind == MeasurementKind::Points ? "point" : "frame", kMinToolConfigurations,
      data.kind == MeasurementKind::Points ? 3 : 6);
  if (data.kind == MeasurementKind::Poses) {
    if (static_cast<int>(data.size()) < kMinToolConfigurations)
      throw InputError({data.file, 0, 0, "--level"},
                       fmt::format("level tool: the TCP frame is measured in {} pose{}; {}",
                                   data.size(), data.size() == 1 ? "" : "s", why));
    tool.tcp_given = true;
    tool.tcp_position_known = tool.tcp_orientation_known = false;
    return tool;
  }
  std::vector<int> rows(tool.targets.size(), 0);
  for (const PointMeasurement& p : data.points)
    if (p.target >= 0 && p.target < static_cast<int>(rows.size()))
      ++rows[static_cast<size_t>(p.target)];
  for (size_t t = 0; t < tool.targets.size(); ++t) {
    if (rows[t] < kMinToolConfigurations)
      throw InputError({data.file, 0, 0, "--level"},
                       fmt::format("level tool: target '{}' is measured in {} configuration{}; {}",
                                   tool.targets[t].name, rows[t], rows[t] == 1 ? "" : "s", why));
    tool.targets[t].known = false;
  }
  return tool;
}

std::string what_was_asked(const IdentifyOptions& options) {
  std::string patterns = fmt::format("{}", fmt::join(options.identify, " "));
  if (options.level == CalibrationLevel::Patterns) return patterns;
  return patterns.empty() ? level_name(options.level)
                          : fmt::format("{} {}", level_name(options.level), patterns);
}

}  // namespace

CalibrationRun reidentify(const CalibratedRobot& start, const std::optional<Tool>& tool,
                          const MeasurementSet& data, const CalibrationRequest& request) {
  const CalibrationLevel level = request.options.level;
  if (level == CalibrationLevel::Patterns && request.options.identify.empty())
    throw InputError({"", 0, 0, "--model"},
                     "say what to re-identify on the calibrated model: --level tool (a new tool), "
                     "--level base (a moved robot base) or --identify PATTERN (e.g. 'link6.*')");
  if (level == CalibrationLevel::Tool && !tool)
    throw InputError({"", 0, 0, "--tool"},
                     "--level tool identifies a new tool: give its tool file (--tool), its "
                     "targets with their drawing's coordinates or without any");
  // Other levels keep the model's tool, whose targets the calibration refined: a tool given
  // beside it must be that tool (as for validate), never silently another one.
  if (tool && level != CalibrationLevel::Tool) check_tool_against_model(start, *tool, "--tool");
  const Tool used = level == CalibrationLevel::Tool ? tool_to_identify(*tool, data) : start.tool;
  CalibrationRequest inner = request;
  inner.options.start_parameters = start.params;
  CalibrationRun run = run_calibration(start.model, used, data, inner);
  IdentificationResult& r = run.result;

  // The calibrated robot with only the re-identified values replaced.
  CalibratedRobot robot = start;
  robot.tool = r.robot.tool;
  if (robot.covariance.rows() != kParameterCount)
    robot.covariance = Eigen::MatrixXd::Zero(kParameterCount, kParameterCount);
  Reidentification record{what_was_asked(request.options), {}};
  for (size_t a = 0; a < r.free.size(); ++a) {
    const int i = r.free[a];
    const UnknownEstimate& u = r.unknowns[static_cast<size_t>(i)];
    ReidentifiedValue value{u.name, u.unit, u.nominal, u.value, u.std_dev};
    if (i >= kParameterCount) {
      // Target coordinates and the TCP start from a least-squares guess: `before` is the tool
      // file's (TCP rotations are relative to the tool file's orientation: before 0).
      value.before = 0;
      if (tool && u.name.size() == 5 && u.name.rfind("tcp.", 0) == 0)
        value.before = tool->flange_T_tcp.translation()[u.name.back() - 'x'];
      const auto dot = u.name.rfind('.');
      if (u.name.rfind("target.", 0) == 0 && dot != std::string::npos) {
        const int t = tool ? tool->target_index(u.name.substr(7, dot - 7)) : -1;
        if (t >= 0 && tool->targets[static_cast<size_t>(t)].known)
          value.before = tool->targets[static_cast<size_t>(t)].position_mm[u.name.back() - 'x'];
      }
      record.values.push_back(value);
      continue;
    }
    record.values.push_back(value);
    const auto s = static_cast<size_t>(i);
    robot.params[i] = r.robot.params[i];
    robot.status[s] = ParameterStatus::Identified;
    robot.reason[s] = fmt::format("re-identified ({})", record.what);
    // The new σ is conditional on the rest, held at its calibrated values: no cross terms.
    robot.covariance.row(i).setZero();
    robot.covariance.col(i).setZero();
    for (size_t b = 0; b < r.free.size(); ++b)
      if (r.free[b] < kParameterCount)
        robot.covariance(i, r.free[b]) =
            r.covariance(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
  }
  robot.base_fitted = start.base_fitted || r.robot.base_fitted;
  r.robot = robot;
  r.reidentification = record;
  return run;
}

}  // namespace robcal
