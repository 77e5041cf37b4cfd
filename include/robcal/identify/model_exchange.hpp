#pragma once
/// \file
/// Robot models in and out of robcal (`robcal model import|export`): a URDF read as a robot
/// file (or, when it needs a base placement or a tip off the flange, as a nominal model file),
/// a Universal Robots calibration.conf read onto its nominal robot as a model file
/// (io/ur_calibration_file.hpp), and a robot or calibrated model written as URDF or as UR
/// calibration.conf deltas with what the format cannot hold named and its accuracy cost
/// computed, or as its parameter table with σ (identify/parameter_csv.hpp).

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robcal/io/ur_calibration_file.hpp"
#include "robcal/io/urdf_file.hpp"

namespace robcal {

struct ModelImportRequest {
  std::string urdf_path;
  std::string tip_link;          ///< empty: tool0 when it follows joint 6, else joint 6's child
  std::string format = "urdf";   ///< "urdf", or "ur-calibration": the next two
  std::string calibration_path;  ///< a UR calibration.conf
  std::string robot;             ///< its nominal robot (built-in name or robot file)
};

struct ModelImportResult {
  UrdfImport imported;           ///< format urdf
  UrCalibration ur_calibration;  ///< format ur-calibration
  /// False: `yaml` is a robot file (`--robot`); true: a nominal calibrated-model file (`--model`)
  /// whose base parameters hold the placement of axis 1 and whose tool tcp is the tip link.
  bool model_file = false;
  std::string yaml;
};

ModelImportResult import_model(const ModelImportRequest& request);

/// What `robcal model import` reports: {format, source (the file read), model_file (true: a
/// nominal model file for --model, false: a robot file for --robot), out: `written_to`} and,
/// for URDF, {joints, root_link, tip_link, base_placement, tip_offset} (axis 1 off the root's z
/// axis, the tip off the flange), for a UR calibration {robot, calibration_status (its number,
/// -1 when not given), calibration_status_name, calibrated (false when the file says not
/// initialized: its deltas may be zero)}.
nlohmann::json model_import_json(const ModelImportRequest& request, const ModelImportResult& result,
                                 const std::string& written_to);

struct ModelExportRequest {
  std::string robot;            ///< built-in robot or robot file (the nominal model), or
  std::string model;            ///< a calibrated model file (exactly one of the two)
  std::string format = "urdf";  ///< "urdf", "ur-calibration" or "mdh-csv"
  uint64_t seed = 1;            ///< configurations drawn to measure the cost of what is left out
  int configurations = 2000;
};

struct ModelExportResult {
  std::string text;  ///< the URDF, calibration.conf or CSV
  /// URDF: by name, see robot_to_urdf; calibration.conf: the base placement off axis 1, the
  /// tool, compliance, scales and periodic errors, by name with their values.
  std::vector<std::string> left_out;
  /// Position error of the exported rigid model against the full model at the tool centre point
  /// (flange without one), over `configurations` random joint values within the limits, mm.
  double left_out_rms_mm = 0, left_out_max_mm = 0;
};

ModelExportResult export_model(const ModelExportRequest& request);

/// What `robcal model export` reports: {format, left_out (what the format cannot hold),
/// left_out_rms_mm, left_out_max_mm (its cost at the TCP), configurations, seed, out}.
nlohmann::json model_export_json(const ModelExportRequest& request, const ModelExportResult& result,
                                 const std::string& written_to);

}  // namespace robcal
