/// `robcal import`: an instrument's export joined with the robot's joint log into robcal's
/// measurement CSV (campaign/instrument_import.hpp).

#include <fmt/format.h>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/campaign/import_workflow.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"

namespace robcal::cli {
namespace {

struct ImportOptions {
  std::string export_path, log_path, map_path, out;
  std::string join = "order";
  double tolerance_s = 0.5;
  std::string target, delimiter, decimal, columns, unit, config_column, world_frame, configs;
  bool allow_unmeasured = false;
  bool json = false;
};

void run_import(const ImportOptions& o) {
  const campaign::ImportResult result = campaign::import_files({o.export_path,
                                                                o.log_path,
                                                                o.map_path,
                                                                {{"delimiter", o.delimiter},
                                                                 {"decimal", o.decimal},
                                                                 {"columns", o.columns},
                                                                 {"config-column", o.config_column},
                                                                 {"unit", o.unit}},
                                                                o.join,
                                                                o.tolerance_s,
                                                                o.target,
                                                                o.allow_unmeasured,
                                                                o.world_frame,
                                                                o.configs});
  write_file_atomically(o.out, result.csv);
  if (o.json) {
    nlohmann::json out = campaign::import_json(result);
    out["out"] = o.out;
    print_json(out);
    return;
  }
  for (const std::string& w : result.warnings) fmt::print(stderr, "warning: {}\n", w);
  fmt::print("imported {} {} rows from {} joined by {} with {}\nwrote {}\n",
             result.measurements.size(), measurement_kind_name(result.measurements.kind),
             o.export_path, o.join, o.log_path, o.out);
  if (!result.world_frame.empty())
    fmt::print("positions in the world frame of {}\n", result.world_frame);
  if (!o.configs.empty())
    fmt::print("each row's approach and payload from its configuration in {}\n", o.configs);
}

const bool import_registered = register_command(75, [](CLI::App& app) {
  auto o = std::make_shared<ImportOptions>();
  auto* cmd = app.add_subcommand(
      "import",
      "Join an instrument's export (points or poses, as the tracker/CMM software writes it) with "
      "the robot's joint log into robcal's measurement CSV");
  cmd->add_option("--export", o->export_path, "Instrument export file")->required();
  cmd->add_option("--joints", o->log_path,
                  "Joint log of the robot program: header with config, j1..j6 (deg), optional "
                  "time, target")
      ->required();
  cmd->add_option("--map", o->map_path,
                  "Mapping file (YAML): delimiter, decimal, header, columns, roles, unit, angles");
  cmd->add_option("--join", o->join, "How readings find their joints: order, name or time")
      ->capture_default_str();
  cmd->add_option("--time-tolerance", o->tolerance_s, "Largest clock gap for --join time, s")
      ->capture_default_str();
  cmd->add_option("--target", o->target, "Target name when neither file names it");
  cmd->add_option("--delimiter", o->delimiter,
                  "comma, semicolon, tab or space (default: detected)");
  cmd->add_option("--decimal", o->decimal, "point or comma (default: detected)");
  cmd->add_option("--columns", o->columns,
                  "Column names in file order for a file without a header, e.g. "
                  "collection,group,target,x,y,z");
  cmd->add_option("--config-column", o->config_column,
                  "Column holding the configuration name (e.g. group), for --join name");
  cmd->add_option("--unit", o->unit,
                  "Length unit of the export: mm or m (default: header, else mm)");
  cmd->add_flag("--allow-unmeasured", o->allow_unmeasured,
                "Import even when some joint-log rows have no reading (listed as warnings)");
  cmd->add_option("--world-frame", o->world_frame,
                  "Frame file of `robcal frames world`: write the positions (and orientations) "
                  "in that frame (the nests' world) instead of the instrument's");
  cmd->add_option("--configs", o->configs,
                  "The configurations file the program ran (robcal plan --out): each row takes "
                  "its configuration's approach and payload columns (backlash, several payloads), "
                  "joined by the joint log's configuration names");
  cmd->add_option("--out", o->out, "Measurement CSV to write")->required();
  cmd->add_flag("--json", o->json, "Machine-readable output");
  cmd->callback([o] { run_import(*o); });
});

}  // namespace
}  // namespace robcal::cli
