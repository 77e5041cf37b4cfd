#include "robcal/campaign/import_workflow.hpp"

#include <nlohmann/json.hpp>

#include "robcal/campaign/frames_world.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"

namespace robcal::campaign {

ImportResult import_files(const ImportFilesRequest& request) {
  ImportRequest r;
  // Read first: a bad frame file is named before the export's own errors.
  if (!request.world_frame.empty()) {
    r.instrument_T_world = load_world_frame(request.world_frame);
    r.world_frame_file = request.world_frame;
  }
  r.export_file = {request.export_path, read_text_file(request.export_path)};
  r.joint_log = {request.joints_path, read_text_file(request.joints_path)};
  if (!request.map_path.empty())
    r.format = parse_export_format(read_text_file(request.map_path), request.map_path);
  // The options override the mapping file.
  for (const auto& [option, value] : request.options)
    if (!value.empty()) set_export_option(r.format, option, value, "--" + option);
  r.join = parse_join_by(request.join, "--join");
  r.time_tolerance_s = request.time_tolerance_s;
  r.default_target = request.target;
  r.allow_unmeasured = request.allow_unmeasured;
  if (!request.configs_path.empty())
    r.plan = NamedText{request.configs_path, read_text_file(request.configs_path)};
  return import_measurements(r);
}

nlohmann::json import_json(const ImportResult& result) {
  nlohmann::json j = {{"rows", result.measurements.size()},
                      {"kind", std::string(measurement_kind_name(result.measurements.kind))},
                      {"warnings", result.warnings}};
  if (!result.world_frame.empty()) j["world_frame"] = result.world_frame;
  return j;
}

}  // namespace robcal::campaign
