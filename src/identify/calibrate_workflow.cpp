#include "robcal/identify/calibrate_workflow.hpp"

#include <fmt/format.h>

#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/identify/calibration_output.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/format_options.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal {

IdentifyOptions checked_options(IdentifyOptions options, const std::string& loss) {
  check_orientation_weight(options.orientation_weight_mm);
  if (!std::isfinite(options.instrument_sigma_mm) || options.instrument_sigma_mm < 0)
    throw InputError({"", 0, 0, "--sigma"},
                     fmt::format("the instrument's σ must be a finite number of mm >= 0 (0: not "
                                 "stated), got {}",
                                 options.instrument_sigma_mm));
  if (loss != "none" && loss != "huber")
    throw InputError({"", 0, 0, "--loss"},
                     fmt::format("unknown loss '{}': expected none or huber", loss));
  options.huber = loss == "huber";
  return options;
}

CalibrationRun calibrate_files(const CalibrateFilesRequest& request) {
  IdentifyOptions options = checked_options(request.request.options, request.loss);
  const bool from_model = !request.model.empty();
  if (!from_model && request.robot.empty())
    throw InputError({"", 0, 0, "--robot"},
                     "give the robot (--robot) to calibrate, or a calibrated model (--model) to "
                     "re-identify a part of");
  if (from_model && !request.robot.empty())
    throw InputError({"", 0, 0, "--robot"},
                     "--model already holds the robot; give either --robot or --model");
  if (!from_model && request.tool.empty())
    throw InputError({"", 0, 0, "--tool"}, "give the tool file (--tool)");
  options.level = !from_model
                      ? parse_calibration_level(request.level.empty() ? "full" : request.level)
                  : request.level.empty() ? CalibrationLevel::Patterns
                                          : parse_reidentification_level(request.level);
  std::optional<CalibratedRobot> start;
  if (from_model) start = load_calibrated_robot(request.model);
  std::optional<Tool> tool;
  if (!request.tool.empty()) tool = load_tool(request.tool);
  const MeasurementFile file =
      read_measurements_csv(request.measurements, tool ? *tool : start->tool, {},
                            declared_format(request.units, request.euler));
  CalibrationRequest inner = request.request;
  inner.options = options;
  if (!request.folds.empty()) inner.folds = read_folds_csv(request.folds);
  CalibrationRun run =
      start ? reidentify(*start, tool, file.measurements, inner)
            : run_calibration(load_robot(request.robot), *tool, file.measurements, inner);
  run.warnings.insert(run.warnings.begin(), file.warnings.begin(), file.warnings.end());
  return run;
}

std::optional<std::string> write_calibration(const CalibrationRun& run, const std::string& path,
                                             bool force, const Provenance* provenance) {
  if (!run.problems.empty() && !force)
    return fmt::format(
        "{} not written: the fit is not trustworthy ({} problem{}: {}); fix the cause, or "
        "write it anyway with --force (Python: force=True)",
        path, run.problems.size(), run.problems.size() > 1 ? "s" : "", run.problems.front());
  write_file_atomically(path, calibrated_model_file(run, provenance));
  return std::nullopt;
}

}  // namespace robcal
