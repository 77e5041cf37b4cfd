/// `robcal model import|export`: robot models in from URDF or a UR calibration.conf, out to
/// URDF, calibration.conf deltas or an MDH table (identify/model_exchange.hpp).

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/identify/model_exchange.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal::cli {
namespace {

struct ModelImportOptions {
  ModelImportRequest request;
  std::string out;
  bool json = false;
};

struct ExportOptions {
  ModelExportRequest request;
  std::string out;
  bool json = false;
};

void run_model_import(const ModelImportOptions& o) {
  const ModelImportResult r = import_model(o.request);
  write_file_atomically(o.out, r.yaml);
  const nlohmann::json report = model_import_json(o.request, r, o.out);
  if (o.json) {
    print_json(report);
    return;
  }
  const std::string use = r.model_file ? "a nominal model file: use it with --model"
                                       : "a robot file: use it with --robot";
  if (o.request.format == "ur-calibration") {
    fmt::print("{}: the factory deltas on {} (calibration_status {})\n",
               report["source"].get<std::string>(), report["robot"].get<std::string>(),
               report["calibration_status_name"].get<std::string>());
    if (!report["calibrated"].get<bool>())
      fmt::print("warning: the file says the robot is not calibrated: the deltas may be zero\n");
    fmt::print("wrote {} ({})\n", o.out, use);
    return;
  }
  fmt::print("{}: joints {}, flange = link '{}'\n", report["source"].get<std::string>(),
             fmt::join(report["joints"].get<std::vector<std::string>>(), ", "),
             report["tip_link"].get<std::string>());
  if (report["base_placement"].get<bool>())
    fmt::print("axis 1 is not the z axis of link '{}': its placement is in the base parameters\n",
               report["root_link"].get<std::string>());
  if (report["tip_offset"].get<bool>())
    fmt::print("link '{}' is off axis 6 or turned from it: it is the tool's tcp\n",
               report["tip_link"].get<std::string>());
  fmt::print("wrote {} ({})\n", o.out, use);
}

void run_export(const ExportOptions& o) {
  const ModelExportResult r = export_model(o.request);
  write_file_atomically(o.out, r.text);
  if (o.json) {
    print_json(model_export_json(o.request, r, o.out));
    return;
  }
  const char* format = o.request.format == "ur-calibration" ? "calibration.conf" : "URDF";
  for (const std::string& what : r.left_out)
    fmt::print("warning: not in the {}: {}\n", format, what);
  if (r.left_out_max_mm > 0)
    fmt::print(
        "leaving them out moves the tool centre point by {:.4f} mm RMS, {:.4f} mm at most "
        "({} configurations within the limits, seed {})\n",
        r.left_out_rms_mm, r.left_out_max_mm, o.request.configurations, o.request.seed);
  fmt::print("wrote {}\n", o.out);
}

const bool model_io_registered = register_command(15, [](CLI::App& app) {
  auto* model = app.add_subcommand(
      "model", "Robot models in from URDF, out to URDF or an MDH table with σ (CSV)");
  model->require_subcommand(1);

  auto in = std::make_shared<ModelImportOptions>();
  auto* import = model->add_subcommand(
      "import",
      "Read a 6R serial chain from a URDF as a robot file (a nominal model file when "
      "axis 1 is off the root's z axis or the tip is off the flange), or a UR calibration.conf "
      "onto its nominal robot as a nominal model file");
  import
      ->add_option("--format", in->request.format,
                   "urdf, or ur-calibration (--calibration, --robot)")
      ->check(CLI::IsMember({"urdf", "ur-calibration"}))
      ->capture_default_str();
  import->add_option("--urdf", in->request.urdf_path, "URDF file (format urdf)");
  import->add_option("--calibration", in->request.calibration_path,
                     "UR calibration.conf ([mounting] delta_theta, delta_a, delta_d, delta_alpha; "
                     "metres and radians)");
  import->add_option("--robot", in->request.robot,
                     "The calibration's nominal robot (built-in name or robot file)");
  import->add_option("--tip", in->request.tip_link,
                     "Link taken as the flange (default: tool0 when it follows joint 6, else "
                     "joint 6's child link)");
  import->add_option("--out", in->out, "Output YAML")->required();
  import->add_flag("--json", in->json, "Machine-readable summary");
  import->callback([in] { run_model_import(*in);
});

auto ex = std::make_shared<ExportOptions>();
auto* exp = model->add_subcommand(
    "export",
    "Write a robot or a calibrated model as URDF (rigid geometry, limits, masses, "
    "the tool's tcp as link 'tcp'; says what URDF cannot hold and what that costs), as UR "
    "calibration.conf deltas (the same statement) or as its MDH parameter table with σ (CSV)");
exp->add_option("--robot", ex->request.robot, "Built-in robot name or robot file (nominal model)");
exp->add_option("--model", ex->request.model, "Calibrated model file (calibrate --out)");
exp->add_option("--format", ex->request.format,
                "urdf; ur-calibration: calibration.conf [mounting] deltas (identity joint map, "
                "metres and radians); or mdh-csv: the parameter table (name, unit, nominal, value, "
                "std, status; mm and deg)")
    ->check(CLI::IsMember({"urdf", "ur-calibration", "mdh-csv"}))
    ->capture_default_str();
exp->add_option("--seed", ex->request.seed, "Seed of the configurations that measure the cost")
    ->capture_default_str();
exp->add_option("--out", ex->out, "Output URDF, calibration.conf or CSV")->required();
exp->add_flag("--json", ex->json, "Machine-readable summary");
exp->callback([ex] { run_export(*ex); });
});

}  // namespace
}  // namespace robcal::cli
