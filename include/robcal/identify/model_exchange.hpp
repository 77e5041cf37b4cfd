#pragma once
/// \file
/// Robot models in and out of robcal (`robcal model import|export`): a URDF read as a robot
/// file (or, when it needs a base placement or a tip off the flange, as a nominal model file),
/// and a robot or calibrated model written as URDF with what URDF cannot hold named and its
/// accuracy cost computed, or as its parameter table with σ (identify/parameter_csv.hpp).

#include <cstdint>
#include <string>
#include <vector>

#include "robcal/io/urdf_file.hpp"

namespace robcal {

struct ModelImportRequest {
  std::string urdf_path;
  std::string tip_link;  ///< empty: tool0 when it follows joint 6, else joint 6's child
};

struct ModelImportResult {
  UrdfImport imported;
  /// False: `yaml` is a robot file (`--robot`); true: a nominal calibrated-model file (`--model`)
  /// whose base parameters hold the placement of axis 1 and whose tool tcp is the tip link.
  bool model_file = false;
  std::string yaml;
};

ModelImportResult import_model(const ModelImportRequest& request);

struct ModelExportRequest {
  std::string robot;            ///< built-in robot or robot file (the nominal model), or
  std::string model;            ///< a calibrated model file (exactly one of the two)
  std::string format = "urdf";  ///< "urdf" or "mdh-csv"
  uint64_t seed = 1;            ///< configurations drawn to measure the cost of what is left out
  int configurations = 2000;
};

struct ModelExportResult {
  std::string text;                   ///< the URDF or the CSV
  std::vector<std::string> left_out;  ///< URDF: by name, see robot_to_urdf
  /// Position error of the URDF's rigid model against the full model at the tool centre point
  /// (flange without one), over `configurations` random joint values within the limits, mm.
  double left_out_rms_mm = 0, left_out_max_mm = 0;
};

ModelExportResult export_model(const ModelExportRequest& request);

}  // namespace robcal
