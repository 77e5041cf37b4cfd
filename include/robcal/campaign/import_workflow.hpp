#pragma once
/// \file
/// The workflow behind `robcal import` and Python's import_measurements: the files named, a
/// mapping file and option overrides as text (the flags), joined by import_measurements
/// (campaign/instrument_import.hpp); with the result's JSON.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <utility>
#include <vector>

#include "robcal/campaign/instrument_import.hpp"

namespace robcal::campaign {

struct ImportFilesRequest {
  std::string export_path;  ///< the instrument's export
  std::string joints_path;  ///< the robot program's joint log
  std::string map_path;     ///< mapping file (YAML), optional
  /// Options over the mapping file, as set_export_option takes them ("delimiter", "decimal",
  /// "columns", "config-column", "unit"); an empty value is not set.
  std::vector<std::pair<std::string, std::string>> options;
  std::string join = "order";  ///< order, name or time
  double time_tolerance_s = 0.5;
  std::string target;  ///< target name when neither file names one
  bool allow_unmeasured = false;
  std::string world_frame;  ///< frame file of `robcal frames world`: positions in that frame
  /// The configurations file the program ran (`--configs`): each row's approach and payload.
  std::string configs_path;
};

/// Reads the files and joins them. InputError names the file (line, column) or the option
/// (`--delimiter` …) that is wrong.
ImportResult import_files(const ImportFilesRequest& request);

/// {rows, kind, warnings} and world_frame (the frame file) when the positions are in one.
nlohmann::json import_json(const ImportResult& result);

}  // namespace robcal::campaign
