#include "robcal/identify/calibration_run.hpp"

#include <fmt/format.h>

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
    if (kind == ParamKind::Compliance && u.value + 3 * u.std_dev < 0)
      out.push_back(fmt::format("{} is {:.3g} ± {:.2g} {}: a negative compliance", u.name, u.value,
                                u.std_dev, u.unit));
  }
  return out;
}

CalibrationRun run_calibration(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const CalibrationRequest& request) {
  CalibrationRun run;
  run.result = calibrate(model, tool, data, request.options);
  const IdentificationResult& r = run.result;
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
    run.problems.push_back(p + ": no real arm is that far from its data sheet; " + check);
  return run;
}

}  // namespace robcal
