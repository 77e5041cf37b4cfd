#include "robcal/identify/calibration_output.hpp"

#include <yaml-cpp/yaml.h>

#include "robcal/core/rounding.hpp"
#include "robcal/identify/calibrated_robot_file.hpp"
#include "robcal/identify/fit_error_json.hpp"
#include "robcal/io/json_yaml.hpp"

namespace robcal {

void emit_statistics_entries(YAML::Emitter& y, const IdentificationResult& result) {
  y.SetDoublePrecision(kStatisticsDigits);
  y << YAML::Key << "converged" << YAML::Value << result.status.converged;
  y << YAML::Key << "iterations" << YAML::Value << result.status.iterations;
  y << YAML::Key << "solver_message" << YAML::Value << result.status.message;
  y << YAML::Key << "residuals" << YAML::Value << result.residual_count;
  y << YAML::Key << "identified" << YAML::Value << result.identified_count;
  y << YAML::Key << "sigma_mm" << YAML::Value << result.sigma_mm;
  y << YAML::Key << "start_rms_mm" << YAML::Value << result.start_rms_mm;
  y << YAML::Key << "mean_mm" << YAML::Value << result.mean_mm;
  y << YAML::Key << "rms_mm" << YAML::Value << result.rms_mm;
  y << YAML::Key << "max_mm" << YAML::Value << result.max_mm;
  if (result.noise_test.tested)
    y << YAML::Key << "noise_test" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
      << "instrument_sigma_mm" << YAML::Value << result.noise_test.instrument_sigma_mm << YAML::Key
      << "chi_square" << YAML::Value << result.noise_test.chi_square << YAML::Key << "dof"
      << YAML::Value << result.noise_test.dof << YAML::Key << "p_value" << YAML::Value
      << result.noise_test.p_value << YAML::EndMap;
  if (!result.warnings.empty()) {
    y << YAML::Key << "warnings" << YAML::Value << YAML::BeginSeq;
    for (const std::string& w : result.warnings) y << w;
    y << YAML::EndSeq;
  }
  y << YAML::Key << "condition_number" << YAML::Value << result.condition_number;
  if (result.huber_scale_mm > 0)
    y << YAML::Key << "huber_scale_mm" << YAML::Value << result.huber_scale_mm;
  y << YAML::Key << "by_target" << YAML::Value << YAML::BeginSeq;
  for (const auto& t : result.by_target)
    y << YAML::Flow << YAML::BeginMap << YAML::Key << "target" << YAML::Value << t.target
      << YAML::Key << "rows" << YAML::Value << t.rows << YAML::Key << "rms_mm" << YAML::Value
      << t.rms_mm << YAML::Key << "max_mm" << YAML::Value << t.max_mm << YAML::EndMap;
  y << YAML::EndSeq;
  y << YAML::Key << "correlations" << YAML::Value << YAML::BeginSeq;
  for (const auto& c : result.correlations)
    y << YAML::Flow << YAML::BeginSeq << c.first << c.second << c.rho << YAML::EndSeq;
  y << YAML::EndSeq;
  y << YAML::Key << "suspected_outliers" << YAML::Value << YAML::BeginSeq;
  for (const auto& o : result.outliers)
    y << YAML::Flow << YAML::BeginMap << YAML::Key << "config" << YAML::Value << o.config
      << YAML::Key << "line" << YAML::Value << o.line << YAML::Key << "residual_mm" << YAML::Value
      << o.residual_mm << YAML::EndMap;
  y << YAML::EndSeq;
  y << YAML::Key << "predicted_position_error_mm" << YAML::Value;
  emit_json(y, predicted_accuracy_json(result.predicted), YAML::EmitterStyle::Block);
  y.SetDoublePrecision(kExactDigits);
}

YamlWriter statistics_writer(const IdentificationResult& result) {
  return [&result](YAML::Emitter& out) {
    out << YAML::BeginMap;
    emit_statistics_entries(out, result);
    out << YAML::EndMap;
  };
}

namespace {

/// Re-identified values' digits in the record (12: their σ is far above the last one).
constexpr int kReidentifiedDigits = 12;

/// The statistics map: the fit's, then the cross-validation, the provenance and the problems.
void emit_statistics(YAML::Emitter& out, const IdentificationResult& result,
                     const CrossValidation* cv, const std::vector<std::string>& problems,
                     const Provenance* provenance) {
  out << YAML::BeginMap;
  emit_statistics_entries(out, result);
  out.SetDoublePrecision(kExactDigits);
  if (cv)
    out << YAML::Key << "cross_validation" << YAML::Value << YAML::BeginMap << YAML::Key << "folds"
        << YAML::Value << cv->folds << YAML::Key << "seed" << YAML::Value << cv->seed << YAML::Key
        << "mean_mm" << YAML::Value << cv->mean_mm << YAML::Key << "std_mm" << YAML::Value
        << cv->std_mm << YAML::Key << "max_mm" << YAML::Value << cv->max_mm << YAML::EndMap;
  if (provenance) {
    out << YAML::Key << "provenance" << YAML::Value;
    emit_provenance(out, *provenance);
  }
  if (!problems.empty()) out << YAML::Key << "problems" << YAML::Value << problems;
  out << YAML::EndMap;
}

std::string model_file(const IdentificationResult& result, const CrossValidation* cv,
                       const std::vector<std::string>& problems, const Provenance* provenance) {
  const YamlWriter statistics = [&](YAML::Emitter& out) {
    emit_statistics(out, result, cv, problems, provenance);
  };
  if (!result.reidentification) return calibrated_robot_to_yaml(result.robot, statistics);
  // A re-identification keeps the model's statistics and records this fit in a new record.
  const YamlWriter record = [&](YAML::Emitter& out) {
    const Reidentification& what = *result.reidentification;
    out.SetDoublePrecision(kReidentifiedDigits);
    out << YAML::BeginMap << YAML::Key << "what" << YAML::Value << what.what;
    out << YAML::Key << "values" << YAML::Value << YAML::BeginSeq;
    for (const ReidentifiedValue& v : what.values)
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value << v.name
          << YAML::Key << "unit" << YAML::Value << v.unit << YAML::Key << "before" << YAML::Value
          << v.before << YAML::Key << "value" << YAML::Value << v.value << YAML::Key << "std"
          << YAML::Value << v.std_dev << YAML::EndMap;
    out << YAML::EndSeq << YAML::Key << "statistics" << YAML::Value;
    statistics(out);
    out << YAML::EndMap;
  };
  return calibrated_robot_to_yaml(result.robot, {}, record);
}

}  // namespace

std::string calibrated_model_file(const CalibrationRun& run, const Provenance* provenance) {
  return model_file(run.result, run.cross_validation ? &*run.cross_validation : nullptr,
                    run.problems, provenance);
}

std::string calibrated_model_file(const IdentificationResult& result,
                                  const Provenance* provenance) {
  return model_file(result, nullptr, {}, provenance);
}

nlohmann::json calibration_run_json(const CalibrationRun& run, const std::string& written_to) {
  const IdentificationResult& r = run.result;
  const CrossValidation* cv = run.cross_validation ? &*run.cross_validation : nullptr;
  nlohmann::json out;
  out["robot"] = r.robot.model.name;
  out["level"] = r.robot.level;
  if (r.reidentification) {
    nlohmann::json values = nlohmann::json::array();
    for (const ReidentifiedValue& v : r.reidentification->values)
      values.push_back({{"name", v.name},
                        {"unit", v.unit},
                        {"before", rounded(v.before, 12)},
                        {"value", rounded(v.value, 12)},
                        {"std", v.std_dev}});
    out["reidentified"] = {{"what", r.reidentification->what}, {"values", values}};
  }
  out["rows"] = run.rows;
  out["converged"] = r.status.converged;
  out["iterations"] = r.status.iterations;
  out["solver_message"] = r.status.message;
  out["residuals"] = r.residual_count;
  out["identified"] = r.identified_count;
  if (run.kind == MeasurementKind::Poses)
    out["orientation_weight_mm_per_rad"] = run.options.orientation_weight_mm;
  out["warnings"] = run.warnings;
  out.update(residual_per_row_json(r, 9));
  out["rms_mm"] = rounded(r.rms_mm);
  out["max_mm"] = rounded(r.max_mm);
  if (r.noise_test.tested)
    out["noise_test"] = {{"instrument_sigma_mm", r.noise_test.instrument_sigma_mm},
                         {"chi_square", rounded(r.noise_test.chi_square)},
                         {"dof", r.noise_test.dof},
                         {"p_value", r.noise_test.p_value},
                         {"consistent", r.noise_test.consistent}};
  out["sigma_mm"] = rounded(r.sigma_mm);
  out["condition_number"] = r.condition_number;
  if (r.huber_scale_mm > 0) out["huber_scale_mm"] = rounded(r.huber_scale_mm);
  out["by_target"] = nlohmann::json::array();
  for (const auto& t : r.by_target)
    out["by_target"].push_back({{"target", t.target},
                                {"rows", t.rows},
                                {"rms_mm", rounded(t.rms_mm)},
                                {"max_mm", rounded(t.max_mm)}});
  out["parameters"] = nlohmann::json::array();
  for (const auto& u : r.unknowns) {
    nlohmann::json p = {{"name", u.name},
                        {"unit", u.unit},
                        {"nominal", rounded(u.nominal, 12)},
                        {"value", rounded(u.value, 12)},
                        {"std", u.std_dev},
                        {"status", status_name(u.status)}};
    if (!u.reason.empty()) p["reason"] = u.reason;
    out["parameters"].push_back(p);
  }
  out["groups"] = nlohmann::json::array();
  for (const GroupSignificance& g : group_significance(r.robot))
    if (g.enabled)
      out["groups"].push_back({{"name", g.group},
                               {"identified", g.identified},
                               {"wald", rounded(g.wald)},
                               {"p_value", g.p_value},
                               {"significant", g.significant}});
  out["correlations"] = nlohmann::json::array();
  for (const auto& c : r.correlations)
    out["correlations"].push_back(
        {{"first", c.first}, {"second", c.second}, {"rho", rounded(c.rho, 6)}});
  out["suspected_outliers"] = nlohmann::json::array();
  for (const auto& o : r.outliers)
    out["suspected_outliers"].push_back(
        {{"config", o.config}, {"line", o.line}, {"residual_mm", rounded(o.residual_mm)}});
  out["predicted_position_error_mm"] = predicted_accuracy_json(r.predicted, 9);
  out["predicted_position_error_mm"]["seed"] = run.options.seed;
  if (cv) {
    nlohmann::json per_fold = nlohmann::json::array();
    for (const FoldErrors& f : cv->per_fold)
      per_fold.push_back(nlohmann::json(fold_errors_json(f, 9)));
    out["cross_validation"] = {{"folds", cv->folds},
                               {"run_because_of_misfit", run.cross_validation_for_misfit},
                               {"user_folds", cv->user_folds},
                               {"per_fold", per_fold},
                               {"seed", cv->seed},
                               {"rows", cv->errors_mm.size()},
                               {"error_mm", held_out_error_json(*cv, 9)}};
  }
  out["problems"] = run.problems;
  out["output"] = written_to.empty() ? nlohmann::json(nullptr) : nlohmann::json(written_to);
  return out;
}

Provenance calibration_provenance(const CalibrationRun& run, const CalibrationInputs& inputs) {
  Provenance provenance = start_provenance_of_process();
  provenance.robot = run.result.robot.model.name;
  provenance.level = level_name(run.options.level);
  provenance.seed = run.options.seed;
  if (!inputs.model.empty()) provenance.files.push_back(provenance_file("model", inputs.model));
  if (!inputs.tool.empty()) provenance.files.push_back(provenance_file("tool", inputs.tool));
  if (!inputs.measurements.empty())
    provenance.files.push_back(provenance_file("measurements", inputs.measurements));
  return provenance;
}

}  // namespace robcal
