/// `robcal model import|export`: robot models in from URDF or a UR calibration.conf, out to
/// URDF, calibration.conf deltas or an MDH table (identify/model_exchange.hpp).

#include <fmt/format.h>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/identify/model_exchange.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal::cli {
namespace {

struct ImportOptions {
  std::string urdf, tip, format = "urdf", calibration, robot, out;
};

struct ExportOptions {
  std::string robot, model, format = "urdf", out;
  uint64_t seed = 1;
};

void run_import(const ImportOptions& o) {
  const ModelImportResult r = import_model({o.urdf, o.tip, o.format, o.calibration, o.robot});
  write_file_atomically(o.out, r.yaml);
  if (o.format == "ur-calibration") {
    static constexpr const char* kStatus[] = {"not initialized", "not linearised", "linearised"};
    const int status = r.ur_calibration.calibration_status;
    fmt::print("{}: the factory deltas on {} (calibration_status {})\n", o.calibration, o.robot,
               status < 0 ? "not given" : kStatus[status]);
    if (status == 0)
      fmt::print("warning: the file says the robot is not calibrated: the deltas may be zero\n");
    fmt::print("wrote {} (a nominal model file: use it with --model)\n", o.out);
    return;
  }
  const UrdfImport& u = r.imported;
  fmt::print("{}: joints {}, flange = link '{}'\n", o.urdf, fmt::join(u.joint_names, ", "),
             u.tip_link);
  if (u.has_base_placement())
    fmt::print("axis 1 is not the z axis of link '{}': its placement is in the base parameters\n",
               u.root_link);
  if (u.has_tip_offset())
    fmt::print("link '{}' is off axis 6 or turned from it: it is the tool's tcp\n", u.tip_link);
  fmt::print("wrote {} ({})\n", o.out,
             r.model_file ? "a nominal model file: use it with --model"
                          : "a robot file: use it with --robot");
}

void run_export(const ExportOptions& o) {
  const ModelExportResult r = export_model({o.robot, o.model, o.format, o.seed});
  write_file_atomically(o.out, r.text);
  const char* format = o.format == "ur-calibration" ? "calibration.conf" : "URDF";
  for (const std::string& what : r.left_out)
    fmt::print("warning: not in the {}: {}\n", format, what);
  if (r.left_out_max_mm > 0)
    fmt::print(
        "leaving them out moves the tool centre point by {:.4f} mm RMS, {:.4f} mm at most "
        "(2000 configurations within the limits, seed {})\n",
        r.left_out_rms_mm, r.left_out_max_mm, o.seed);
  fmt::print("wrote {}\n", o.out);
}

const bool registered = register_command(15, [](CLI::App& app) {
  auto* model = app.add_subcommand(
      "model", "Robot models in from URDF, out to URDF or an MDH table with σ (CSV)");
  model->require_subcommand(1);

  auto in = std::make_shared<ImportOptions>();
  auto* import = model->add_subcommand(
      "import",
      "Read a 6R serial chain from a URDF as a robot file (a nominal model file when "
      "axis 1 is off the root's z axis or the tip is off the flange), or a UR calibration.conf "
      "onto its nominal robot as a nominal model file");
  import->add_option("--format", in->format, "urdf, or ur-calibration (--calibration, --robot)")
      ->check(CLI::IsMember({"urdf", "ur-calibration"}))
      ->capture_default_str();
  import->add_option("--urdf", in->urdf, "URDF file (format urdf)");
  import->add_option("--calibration", in->calibration,
                     "UR calibration.conf ([mounting] delta_theta, delta_a, delta_d, delta_alpha; "
                     "metres and radians)");
  import->add_option("--robot", in->robot,
                     "The calibration's nominal robot (built-in name or robot file)");
  import->add_option("--tip", in->tip,
                     "Link taken as the flange (default: tool0 when it follows joint 6, else "
                     "joint 6's child link)");
  import->add_option("--out", in->out, "Output YAML")->required();
  import->callback([in] { run_import(*in);
});

auto ex = std::make_shared<ExportOptions>();
auto* exp = model->add_subcommand(
    "export",
    "Write a robot or a calibrated model as URDF (rigid geometry, limits, masses, "
    "the tool's tcp as link 'tcp'; says what URDF cannot hold and what that costs), as UR "
    "calibration.conf deltas (the same statement) or as its MDH parameter table with σ (CSV)");
exp->add_option("--robot", ex->robot, "Built-in robot name or robot file (nominal model)");
exp->add_option("--model", ex->model, "Calibrated model file (calibrate --out)");
exp->add_option("--format", ex->format,
                "urdf; ur-calibration: calibration.conf [mounting] deltas (identity joint map, "
                "metres and radians); or mdh-csv: the parameter table (name, unit, nominal, value, "
                "std, status; mm and deg)")
    ->check(CLI::IsMember({"urdf", "ur-calibration", "mdh-csv"}))
    ->capture_default_str();
exp->add_option("--seed", ex->seed, "Seed of the configurations that measure the cost")
    ->capture_default_str();
exp->add_option("--out", ex->out, "Output URDF, calibration.conf or CSV")->required();
exp->callback([ex] { run_export(*ex); });
});

}  // namespace
}  // namespace robcal::cli
