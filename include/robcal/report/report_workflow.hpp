#pragma once
/// \file
/// The workflow behind `robcal report`: a calibrated model validated on measurement files, beside
/// the nominal robot (or another model), as the report's data; and the report's two files.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robcal/report/report.hpp"

namespace robcal {

struct ReportRequest {
  std::string model;                      ///< calibrated model file (with a world frame)
  std::vector<std::string> measurements;  ///< validation files (points or poses), one or more
  std::string calibration;  ///< calibration measurements (error against distance), optional
  /// Model to compare with; empty: the nominal robot placed by a rigid base fit to the
  /// calibration measurements (to the first validation file without them).
  std::string before;
  /// Further calibrated models shown between `before` and `model`, in this order (e.g. the lower
  /// calibration levels), each labelled by its level.
  std::vector<std::string> between;
  std::string title = "robcal calibration report";
  std::string instrument;  ///< instrument.yaml (name and sigma_mm) for the provenance, optional
  std::optional<uint64_t> seed;  ///< seed of the plan or simulation, for the provenance
  std::string iso9283_poses;     ///< ISO 9283 commanded poses (with iso9283_measurements)
  std::string iso9283_measurements;
  int iso9283_min_cycles = 30;  ///< fewest cycles accepted per pose (the standard: 30)
  std::string ballbar;          ///< ballbar (distances) file: length errors of both models
  /// The bar's nominal length (empty: the median reading) and range (empty: ±1 mm); a reading
  /// outside is refused (check_ballbar_readings).
  std::optional<double> ballbar_length_mm, ballbar_range_mm;
};

struct ReportBuild {
  ReportData data;
  std::vector<std::string> warnings;  ///< ignored columns of the files read
};

/// Reads the files and computes every model's errors, ISO 9283 and ballbar results when asked,
/// and the provenance (SHA-256 of every input). Throws InputError naming the file when the model
/// has no world frame or a file is bad.
ReportBuild build_report(const ReportRequest& request);

/// Throws InputError (key "--out") unless `html_path` ends in .html.
void check_report_path(const std::filesystem::path& html_path);

/// Writes the self-contained page at `html_path` and the JSON beside it (.json), each whole or
/// not at all. Throws InputError when Chart.js is missing (load_chartjs).
void write_report(const nlohmann::json& report, const std::filesystem::path& html_path);

/// The whole `robcal report` (and Python's report): with an html_path, the path and Chart.js
/// checked before the work (a missing package is named before the computing, not after), the
/// report built (build_report), its JSON made and, with an html_path, the page and the JSON
/// written beside it. Returns the report's JSON; the build's warnings go to `warnings`.
nlohmann::json make_report(const ReportRequest& request, const std::filesystem::path& html_path,
                           std::vector<std::string>& warnings);

}  // namespace robcal
