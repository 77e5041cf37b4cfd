/// `robcal plan-study`: does planning pay? Closed-loop simulation (docs/method/05-observability.md,
/// issue 5 items 5–6) of planned against random configurations at several counts, over several
/// random true robots, with the accuracy predicted before measuring (noise only, and with a prior
/// calibration's misfit) beside the one achieved.

#include <fmt/format.h>

#include <cmath>
#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/campaign/cell.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/pose_list_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/plan_study_report.hpp"

namespace robcal::cli {
namespace {

struct StudyOptions {
  std::string robot = "abb-irb120";
  std::string tool;
  std::string instrument = "laser-tracker";
  std::string level = "full";
  std::string counts = "15,20,30,40,60";
  int seeds = 4;
  uint64_t seed = 1;
  int candidates = 2000;
  std::string constraints = "auto";
  std::string criterion = "default";
  bool no_guard = false;
  std::vector<std::string> effects;
  std::string cell;
  double floor_mm = 50;
  double noise_mm = 0;
  std::string task_box;
  std::string task_poses;
  int task_count = 200;
  int prior_count = 60;
  bool json = false;
};

void run_study(const StudyOptions& o) {
  PlanStudyOptions options;
  options.counts.clear();
  for (double c : parse_numbers(o.counts, -1, "--counts")) {
    if (c != std::floor(c))
      throw InputError({"", 0, 0, "--counts"},
                       fmt::format("expected positive whole counts, found {}", c));
    options.counts.push_back(static_cast<int>(c));
  }
  options.seeds = o.seeds;
  options.seed = o.seed;
  options.plan.level = parse_calibration_level(o.level);
  options.plan.candidates = o.candidates;
  const RobotModel model = load_robot(o.robot);
  options.plan.constraints = plan_joint_constraints(model, o.constraints);
  options.criterion = parse_selection_criterion(o.criterion);
  options.guard.enabled = !o.no_guard;
  options.effects = o.effects;
  if (!o.cell.empty()) options.cell = campaign::load_cell(o.cell);
  options.plan.floor_mm = o.floor_mm;
  options.instrument = parse_instrument_kind(o.instrument, "--instrument");
  options.noise_mm = o.noise_mm;
  if (!o.task_box.empty()) options.task_box = parse_task_box(o.task_box, "--task-box");
  if (!o.task_poses.empty()) {
    options.task_poses = read_pose_list(o.task_poses);
    options.task_poses_file = o.task_poses;
  }
  options.task_count = o.task_count;
  options.prior_count = o.prior_count;
  check_plan_study_options(options);
  const Tool tool = o.tool.empty() ? default_simulation_tool() : load_tool(o.tool);

  const bool progress = !o.json && stdout_is_terminal();
  const PlanStudyResult r = run_plan_study(model, tool, options, [&](int done, int total) {
    if (progress) fmt::print("true robot {}/{} done\n", done, total);
  });
  if (o.json) {
    print_json(plan_study_json(r, options));
    return;
  }
  const std::string region = task_region_description(options);
  const double nominal = nominal_mean_mm(r);
  fmt::print(
      "plan study: {} with a {}, level {}, σ {} mm, {} random true robots (seeds {}), {} "
      "candidates each\n",
      model.name, o.instrument, o.level, r.sigma_mm, r.seeds.size(), fmt::join(r.seeds, ", "),
      r.candidates);
  fmt::print("task region: {} ({} configurations); nominal robot's mean TCP error {:.3f} mm\n",
             region, r.task_configurations, nominal);
  fmt::print(
      "planned design: {}{}; effects outside the model: {}\n\n",
      criterion_name(study_criterion(options)),
      study_criterion(options) == SelectionCriterion::IOptimal && options.guard.enabled
          ? " with the robustness guard"
          : "",
      options.effects.empty() ? "none" : fmt::format("{}", fmt::join(options.effects, ", ")));
  fmt::print("TCP error after calibration against the truth, over the true robots (mm)\n");
  if (!r.misfit.empty()) {
    double misfit = 0;
    for (const MisfitAllowance& m : r.misfit)
      misfit += m.misfit_mm * m.misfit_mm / static_cast<double>(r.misfit.size());
    fmt::print(
        "prior calibration of each true robot: {} random configurations, {}-fold "
        "cross-validated; misfit allowance {:.4f} mm rms over the robots\n",
        options.prior_count, options.prior_folds, std::sqrt(misfit));
  }
  fmt::print("\n");
  fmt::print("{:>5} | {:^49} | {:^49} | {:>5}\n", "", "planned", "random", "gain");
  fmt::print("{:>5} | {:>9} {:>9} {:>9} {:>9} {:>9} | {:>9} {:>9} {:>9} {:>9} {:>9} | {:>5}\n",
             "count", "mean", "rms", "pred.rms", "+misfit", "max", "mean", "rms", "pred.rms",
             "+misfit", "max", "");
  for (const StudyRow& row : r.rows) {
    const StudySummary opt = summarize(row.optimal), rnd = summarize(row.random);
    fmt::print(
        "{:>5} | {:>9.4f} {:>9.4f} {:>9.4f} {:>9.4f} {:>9.4f} | {:>9.4f} {:>9.4f} {:>9.4f} "
        "{:>9.4f} {:>9.4f} | {:>5.2f}\n",
        row.count, opt.achieved_mean_mm, opt.achieved_rms_mm, opt.predicted_rms_mm,
        opt.predicted_rms_with_misfit_mm, opt.achieved_max_mm, rnd.achieved_mean_mm,
        rnd.achieved_rms_mm, rnd.predicted_rms_mm, rnd.predicted_rms_with_misfit_mm,
        rnd.achieved_max_mm, rnd.achieved_mean_mm / opt.achieved_mean_mm);
  }
  for (const StudyRow& row : r.rows) {
    const StudySummary opt = summarize(row.optimal);
    int beaten = 0;
    for (size_t k = 0; k < row.optimal.size(); ++k)
      beaten += row.optimal[k].achieved.mean_mm < row.random[k].achieved.mean_mm ? 1 : 0;
    fmt::print(
        "count {}: planned better than random on {} of {} true robots; predicted rms {:.4f} mm "
        "(noise only) is {:+.0f} % of the achieved {:.4f} mm{}\n",
        row.count, beaten, row.optimal.size(), opt.predicted_rms_mm,
        100 * (opt.predicted_rms_mm / opt.achieved_rms_mm - 1), opt.achieved_rms_mm,
        r.misfit.empty()
            ? ""
            : fmt::format(", with the misfit {:.4f} mm {:+.0f} %", opt.predicted_rms_with_misfit_mm,
                          100 * (opt.predicted_rms_with_misfit_mm / opt.achieved_rms_mm - 1)));
  }
  fmt::print(
      "\nmean, max: achieved, averaged over the true robots; rms: achieved, quadratic mean over "
      "them; pred.rms: predicted before measuring from the design's parameter covariance "
      "σ²(JᵀJ)⁻¹ (instrument noise only); +misfit: √(pred.rms² + m²), m the prior calibration's "
      "cross-validated misfit (docs/method/05-observability.md §6); gain: random mean / planned "
      "mean\n");
}

const bool plan_study_registered = register_command(62, [](CLI::App& app) {
  auto o = std::make_shared<StudyOptions>();
  auto* cmd = app.add_subcommand(
      "plan-study",
      "Closed-loop simulation: planned against random configurations at several counts, "
      "predicted against achieved accuracy");
  cmd->add_option("--robot", o->robot, "Built-in robot name or robot file")->capture_default_str();
  cmd->add_option("--tool", o->tool, "Tool file (default: 3 SMRs, 2.6 kg payload)");
  cmd->add_option("--instrument", o->instrument, "laser-tracker, optical-cmm or ballbar")
      ->capture_default_str();
  cmd->add_option("--level", o->level, "base, joints, kinematic or full")->capture_default_str();
  cmd->add_option("--counts", o->counts, "Configuration counts to compare, comma-separated")
      ->capture_default_str();
  cmd->add_option("--seeds", o->seeds, "Random true robots (each with its own noise)")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "First seed; true robot k uses seed + 10k")
      ->capture_default_str();
  cmd->add_option("--candidates", o->candidates, "Feasible candidates per true robot")
      ->capture_default_str();
  cmd->add_option("--constraints", o->constraints,
                  "Joint constraints: auto (published for the ABB IRB 120, else the robot "
                  "file's limits), published, or robot (= none)")
      ->capture_default_str();
  cmd->add_option("--criterion", o->criterion,
                  "Planned design: default (as plan: i with a task region, else d), d or i")
      ->capture_default_str();
  cmd->add_flag("--no-guard", o->no_guard, "I-optimal without the robustness guard");
  cmd->add_option("--effects", o->effects,
                  "Effects outside the model in every true robot, comma-separated: backlash, "
                  "j6-periodic, mass-error, thermal")
      ->delimiter(',');
  cmd->add_option("--cell", o->cell, "Cell file (default: the simulator's cell)");
  cmd->add_option("--floor-mm", o->floor_mm,
                  "Targets, flange and wrist above this height over the robot's base plane")
      ->capture_default_str();
  cmd->add_option("--noise-mm", o->noise_mm, "Instrument σ (default: the instrument's own)");
  auto* box_option =
      cmd->add_option("--task-box", o->task_box,
                      "Task region: \"xmin,xmax,ymin,ymax,zmin,zmax\" of TCP positions (mm, "
                      "world frame); default: random configurations in the constrained joint box");
  cmd->add_option("--task-poses", o->task_poses,
                  "Task region: TCP poses in the world frame, name,x,y,z,qw,qx,qy,qz[,config] "
                  "CSV (mm), solved by inverse kinematics for each true robot's placement")
      ->excludes(box_option);
  cmd->add_option("--task-count", o->task_count, "Task configurations (box or random)")
      ->capture_default_str();
  cmd->add_option("--prior-count", o->prior_count,
                  "A prior calibration of each true robot from this many random configurations, "
                  "5-fold cross-validated, for the misfit-aware prediction (0: none)")
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Machine-readable output");
  cmd->callback([o] { run_study(*o); });
});

}  // namespace
}  // namespace robcal::cli
