#pragma once
/// \file
/// The calibration report (docs/method/09-validation.md §1–§3): one self-contained HTML page that
/// works offline and prints to PDF without a heading left alone at a page's foot (print CSS:
/// sections are kept whole, headings stay with what follows), and the same content as JSON. It
/// shows the provenance, the before/after errors on shared axes (cumulative distributions on one
/// logarithmic axis; histograms on bins of a round width), errors by configuration class, the
/// pair-distance histogram, orientation errors (poses), ISO 9283 and ballbar results when
/// given, and the parameters with σ and drop reasons. The page embeds its data and the
/// Chart.js library (Debian's libjs-chart.js, found at configure time) inline; its script
/// draws the charts, then marks the element `#render-status` with `data-status="rendered"`
/// (or `"error: …"` on a script error), which the browser test reads.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/report/provenance.hpp"
#include "robcal/validate/ballbar_error.hpp"
#include "robcal/validate/class_statistics.hpp"
#include "robcal/validate/iso9283.hpp"
#include "robcal/validate/pairwise_distance.hpp"

namespace robcal {

/// Absolute position errors of one model over the validation rows.
struct ModelErrors {
  std::string label;              ///< "nominal", "base", "kinematic", "full", "calibrated"…
  std::vector<double> errors_mm;  ///< per validation row, in row order
  std::vector<std::string> target_of_row;  ///< per row: the target's name ("tcp" for poses)
  std::vector<std::string> config_of_row;  ///< per row: its name in the file ("config")
  std::vector<std::string> class_of_row;   ///< per row: "front-up-noflip" (ArmConfig::label)
  std::vector<double> orientation_deg;     ///< per row of poses files; empty for points
  std::vector<ClassTable> classes;         ///< by configuration, target, region (when computed)
  std::optional<PairwiseDistanceErrors> pairs;  ///< distance errors over every pair of rows
};

/// A parameter's row of the report (external units: mm, deg, rad/N·mm, 1).
struct ReportParameter {
  std::string name, unit, status, reason;
  double nominal = 0, value = 0, std_dev = 0;
};

/// Everything the report shows, already computed.
struct ReportData {
  std::string title;
  std::string robot;
  std::vector<std::string> sources;  ///< input files or the demo's description
  std::vector<ModelErrors> models;   ///< the first is "before", the last "after"
  /// Per validation row: distance (mm) from its measured position to the nearest measured
  /// calibration position; empty when no calibration set was given.
  std::vector<double> distance_to_calibration_mm;
  std::vector<ReportParameter> parameters;
  /// Every opt-in parameter group (model/parameters.hpp) with its Wald test: enabled or not,
  /// significant or not (docs/method/03-error-model.md §5).
  std::vector<GroupSignificance> groups;
  nlohmann::json diagnostics = nlohmann::json::object();  ///< the fit's statistics
  std::vector<std::string> notes;
  Provenance provenance;  ///< empty fields are shown as "not recorded"
  std::optional<Iso9283Result> iso9283;
  /// Ballbar length errors per model (label, errors), e.g. nominal and calibrated.
  std::vector<std::pair<std::string, BallbarErrors>> ballbar;
  BallbarRange ballbar_range;  ///< what the ballbar readings were checked against
};

/// The parameter rows of a calibrated robot: every parameter that is not fixed, with its
/// nominal value, identified value, standard deviation (from the covariance) and status.
std::vector<ReportParameter> report_parameters(const CalibratedRobot& robot);

/// Errors of `robot` over the rows of points or poses sets (validate_model over the sets
/// joined: position and orientation errors, classes, pair distances); `calibration_mm`, the
/// calibration set's measured positions, adds the region classes.
/// \throws InputError when the sets are not all points or all poses
ModelErrors model_errors(const std::string& label, const CalibratedRobot& robot,
                         const std::vector<MeasurementSet>& validation,
                         const std::optional<Eigen::Matrix3Xd>& calibration_mm = {});

/// ISO 9283 figures as JSON (the report's and `robcal iso9283 analyse --json`'s).
nlohmann::json iso9283_json(const Iso9283Result& result);

/// Distance from each validation row's measured position to the nearest calibration row's.
std::vector<double> distance_to_calibration(const std::vector<MeasurementSet>& validation,
                                            const MeasurementSet& calibration);

/// A YAML text (the model file's statistics map) as JSON: numbers stay numbers.
nlohmann::json yaml_to_json(const std::string& yaml_text);

/// The report's content as JSON: summaries (mean, std, mean + 3 std, max) per model and per
/// target, histograms on common bins, classes (with pair distances for the configuration
/// classes), every row's residuals ("rows": config, target, class, one error per model),
/// parameters and diagnostics.
nlohmann::json report_json(const ReportData& data);

/// The Chart.js source to embed. Reads the file found at configure time (or $ROBCAL_CHARTJS);
/// throws InputError saying which package to install when it is missing.
std::string load_chartjs();

/// The HTML page for `report` (from report_json) with `chartjs` inline.
std::string report_html(const nlohmann::json& report, std::string_view chartjs);

/// Plain-text table of the models' summaries in the published tables' style.
std::string report_table_text(const nlohmann::json& report);

}  // namespace robcal
