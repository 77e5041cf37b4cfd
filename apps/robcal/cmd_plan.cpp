/// `robcal plan`: choose the configurations to measure (docs/method/05-observability.md) and
/// predict the accuracy they give before measuring.

#include <fmt/format.h>

#include <memory>
#include <optional>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/campaign/cell.hpp"
#include "robcal/core/error.hpp"
#include "robcal/design/calibration_planning.hpp"
#include "robcal/design/plan_report.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/pose_list_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/calibration_plan.hpp"
#include "robcal/sim/true_robot.hpp"

namespace robcal::cli {
namespace {

struct PlanOptions {
  std::string robot = "abb-irb120";
  std::string tool;
  std::string instrument = "laser-tracker";
  std::string cell;
  std::string level = "full";
  std::vector<std::string> identify;
  std::string approach = "auto";
  std::string payloads = "auto";
  int count = 40;
  int candidates = 5000;
  std::string candidates_file;
  uint64_t seed = 1;
  std::string constraints = "auto";
  double floor_mm = 50;
  double noise_mm = 0;
  std::string method = "fast";
  std::string criterion = "default";
  bool no_guard = false;
  std::string task_configs;
  std::string task_box;
  std::string task_poses;
  int task_count = 1000;
  std::string prior_model;
  std::optional<double> misfit_mm;
  std::string out;
  bool json = false;
};

/// The world the task region is given in: the planning cell's, where the robot stands as in the
/// simulator's standard cell (and its instruments see it).
std::string planning_world_help() {
  const std::array<double, 6> b = default_base_placement();
  return fmt::format(
      "World frame: the cell's (without --cell the simulator's, robot base at x {} y {} z {} mm, "
      "α β γ {} {} {} deg, docs/method/02-frames.md §4)",
      b[0], b[1], b[2], b[3], b[4], b[5]);
}

PlanRequest plan_request(const PlanOptions& o) {
  if (o.out.empty()) throw InputError({"", 0, 0, "--out"}, "expected an output file");
  if (o.method != "fast" && o.method != "published")
    throw InputError({"", 0, 0, "--method"},
                     fmt::format("unknown method '{}', expected 'fast' or 'published'", o.method));
  PlanRequest request;
  request.model = load_robot(o.robot);
  request.tool = o.tool.empty() ? default_simulation_tool() : load_tool(o.tool);
  request.instrument = parse_instrument_kind(o.instrument, "--instrument");
  if (!o.cell.empty()) request.cell = campaign::load_cell(o.cell);
  request.level = parse_calibration_level(o.level);
  request.identify = o.identify;
  request.approach = parse_condition_variety(o.approach, "below", "--approach");
  request.payloads = parse_condition_variety(o.payloads, "own", "--payloads");
  request.count = o.count;
  request.candidates = o.candidates;
  request.seed = o.seed;
  request.constraints = plan_joint_constraints(request.model, o.constraints);
  request.floor_mm = o.floor_mm;
  request.noise_mm = o.noise_mm;
  request.criterion = o.method == "published" ? SelectionCriterion::Published
                                              : parse_selection_criterion(o.criterion);
  request.guard.enabled = !o.no_guard;
  if (!o.candidates_file.empty()) {
    request.candidate_configurations = read_configurations_csv(o.candidates_file, request.tool);
    request.candidates_file = o.candidates_file;
  }
  if (!o.task_configs.empty()) {
    for (const PlannedConfiguration& c : read_configurations_csv(o.task_configs, request.tool))
      request.task_configurations.push_back(c.joints);
    request.task_configurations_file = o.task_configs;
  }
  if (!o.task_box.empty()) request.task_box = parse_task_box(o.task_box, "--task-box");
  if (!o.task_poses.empty()) {
    request.task_poses = read_pose_list(o.task_poses);
    request.task_poses_file = o.task_poses;
  }
  request.task_count = o.task_count;
  if (!o.prior_model.empty()) {
    request.prior_model = load_calibrated_robot(o.prior_model);
    request.prior_model_file = o.prior_model;
  }
  request.misfit_mm = o.misfit_mm;
  return request;
}

void run_plan(const PlanOptions& o) {
  const PlanRequest request = plan_request(o);
  const PlanResult r = plan_calibration(request);
  write_file_atomically(o.out, write_configurations_csv(r.configurations, request.tool));

  std::vector<std::string> dropped;
  for (int p : r.dropped) dropped.push_back(parameter_table()[static_cast<size_t>(p)].name);
  const std::string level = level_name(request.level);
  if (o.json) {
    print_json(plan_json(request, r, o.out));
    return;
  }
  if (r.candidates < request.candidates && request.candidate_configurations.empty())
    fmt::print(
        "note: only {} of {} candidates found in {} draws ({} below the floor, {} not "
        "seen by the instrument)\n",
        r.candidates, request.candidates, r.draws, r.below_floor, r.not_visible);
  if (!request.candidate_configurations.empty() && r.candidates < static_cast<int>(r.draws))
    fmt::print(
        "note: {} of the {} listed configurations left out ({} outside the joint limits, "
        "{} with no target the instrument sees)\n",
        r.draws - r.candidates, r.draws, r.outside_limits, r.not_visible);
  fmt::print(
      "plan for {} with a {} in the {}, level {}{} ({} identifiable parameters{}), seed {}\n",
      request.model.name, r.instrument, r.cell, level,
      request.identify.empty() ? "" : fmt::format(" + {}", fmt::join(request.identify, " + ")),
      r.parameters.size(),
      dropped.empty() ? "" : fmt::format("; dropped as dependent: {}", fmt::join(dropped, ", ")),
      request.seed);
  fmt::print(
      "chose {} of {} feasible candidates{} ({}, {} exchanges{})\n", request.count, r.candidates,
      r.pooled < r.candidates ? fmt::format(" ({} most informative kept)", r.pooled) : "",
      criterion_name(r.criterion), r.exchanges,
      r.criterion == SelectionCriterion::DOptimal ? fmt::format(", {} restarts", r.restarts) : "");
  fmt::print("near a joint-range edge (within {:.0f} % of a range): {} selected{}, {} random\n\n",
             100 * request.guard.edge_margin, r.near_edge,
             r.criterion == SelectionCriterion::IOptimal && request.guard.enabled
                 ? fmt::format(" (guard: at most {})", r.edge_limit)
                 : "",
             r.near_edge_random);
  for (const std::string& note : r.notes) fmt::print("note: {}\n\n", note);
  fmt::print("index      selected        random\n");
  const auto row = [](const char* name, double a, double b) {
    fmt::print("{:<6} {:>12.6g}  {:>12.6g}\n", name, a, b);
  };
  row("O1", r.selected.O1, r.random.O1);
  row("O2", r.selected.O2, r.random.O2);
  row("O3", r.selected.O3, r.random.O3);
  row("O4", r.selected.O4, r.random.O4);
  row("O5", r.selected.O5, r.random.O5);
  row("D-eff", r.d_efficiency_selected, r.d_efficiency_random);
  fmt::print("\npredicted TCP error after calibration ({} task configurations: {})\n",
             r.task_configurations, r.region);
  fmt::print(
      "from instrument noise only (σ = {} mm, σ²(JᵀJ)⁻¹: as if the model held every effect of "
      "the robot):\n",
      r.sigma_mm);
  fmt::print("  selected: mean {:.4f}  rms {:.4f}  max {:.4f} mm\n", r.predicted_selected.mean_mm,
             r.predicted_selected.rms_mm, r.predicted_selected.max_mm);
  fmt::print("  random:   mean {:.4f}  rms {:.4f}  max {:.4f} mm\n", r.predicted_random.mean_mm,
             r.predicted_random.rms_mm, r.predicted_random.max_mm);
  if (r.misfit) {
    fmt::print("with the model misfit, {:.4f} mm rms ({}{}), the expected accuracy:\n",
               r.misfit->misfit_mm, r.misfit->source,
               r.misfit->held_out_rms_mm > 0
                   ? fmt::format(", less its noise {:.4f} and parameter noise {:.4f} mm",
                                 r.misfit->noise_mm, r.misfit->parameter_noise_mm)
                   : "");
    fmt::print("  selected: rms {:.4f} mm\n", r.predicted_rms_with_misfit_selected);
    fmt::print("  random:   rms {:.4f} mm\n", r.predicted_rms_with_misfit_random);
  } else {
    fmt::print(
        "note: a real robot adds the misfit its model leaves (effects the model does not "
        "contain), which this noise-only prediction does not show; for the expected accuracy "
        "give "
        "--prior-model (a calibration of this robot with --kfold) or --misfit-mm\n");
  }
  fmt::print("wrote {}\n", o.out);
}

const bool plan_registered = register_command(60, [](CLI::App& app) {
  auto o = std::make_shared<PlanOptions>();
  auto* cmd = app.add_subcommand(
      "plan", "Choose calibration configurations (observability) and predict their accuracy");
  cmd->add_option("--robot", o->robot, "Built-in robot name or robot file")->capture_default_str();
  cmd->add_option("--tool", o->tool, "Tool file (default: 3 SMRs, 2.6 kg payload)");
  cmd->add_option("--instrument", o->instrument, "laser-tracker, optical-cmm or ballbar")
      ->capture_default_str();
  cmd->add_option("--level", o->level, "base, joints, kinematic or full")->capture_default_str();
  cmd->add_option("--identify", o->identify,
                  "Also plan for the parameters matching this glob or opt-in group (repeatable), "
                  "as calibrate --identify takes them, e.g. backlash, periodic, groups");
  cmd->add_option("--approach", o->approach,
                  "auto (varied when backlash is planned for), below (every joint from q - 5 "
                  "deg) or varied (each joint's side drawn per candidate): the approach column")
      ->capture_default_str();
  cmd->add_option("--payloads", o->payloads,
                  "auto (varied when the tool file lists payloads and compliance is planned "
                  "for), own (the tool's payload) or varied: the payload column")
      ->capture_default_str();
  cmd->add_option("--count", o->count, "Configurations to choose")->capture_default_str();
  auto* candidates_option =
      cmd->add_option("--candidates", o->candidates,
                      "Random feasible candidates to choose from (drawn and scored in batches "
                      "of 5000; the 5000 most informative are kept)")
          ->capture_default_str();
  cmd->add_option("--candidates-file", o->candidates_file,
                  "Choose among these configurations instead (e.g. already measured ones): "
                  "config,target,j1..j6 CSV, degrees; an empty target: the first the "
                  "instrument sees")
      ->excludes(candidates_option);
  cmd->add_option("--cell", o->cell,
                  "Cell file (data/cells/default-tracker.yaml format): robot base, instrument, "
                  "floor and keep-out boxes; default: the simulator's cell");
  cmd->add_option("--seed", o->seed, "Seed of every random draw")->capture_default_str();
  cmd->add_option("--constraints", o->constraints,
                  "Joint constraints: auto (published for the ABB IRB 120, the robot file's "
                  "limits for any other robot), published (θ2≥0, θ3≥−80, |θ1|≤90, |θ4|≤150, "
                  "|θ5|≤90, |θ6|≤180 deg) or robot (= none: the robot file's limits)")
      ->capture_default_str();
  cmd->add_option("--floor-mm", o->floor_mm,
                  "Targets, flange and wrist above this height over the robot's base plane")
      ->capture_default_str();
  cmd->add_option("--noise-mm", o->noise_mm,
                  "Instrument σ for the predicted accuracy (default: the instrument's own)");
  cmd->add_option("--method", o->method,
                  "fast (D-optimal: greedy, exchanges and Fedorov's best swap with rank-r updates, "
                  "seeded restarts below 4000 candidates) or published (exchange on O1)")
      ->capture_default_str();
  cmd->add_option("--criterion", o->criterion,
                  "default (i with a task region, else d), d (D-optimal) or i (I-optimal: least "
                  "mean predicted TCP variance over the task region, with the robustness guard; "
                  "docs/method/05-observability.md)")
      ->capture_default_str();
  cmd->add_flag("--no-guard", o->no_guard,
                "I-optimal without the robustness guard (at most 25 % of the configurations "
                "within 5 % of a joint-range end, 5 % of a range apart)");
  auto* configs_option = cmd->add_option(
      "--task-configs", o->task_configs,
      "Task region for the predicted accuracy: config,target,j1..j6 CSV (default: random "
      "configurations in the constrained joint box)");
  auto* box_option =
      cmd->add_option("--task-box", o->task_box,
                      "Task region as a box of TCP positions in the world frame: "
                      "\"xmin,xmax,ymin,ymax,zmin,zmax\" (mm), sampled by inverse kinematics "
                      "with the tool pointing down. " +
                          planning_world_help());
  cmd->add_option("--task-poses", o->task_poses,
                  "Task region as TCP poses in the world frame: name,x,y,z,qw,qx,qy,qz[,config] "
                  "CSV (mm; the file `robcal compensate` reads), each solved by inverse "
                  "kinematics in its config branch if given, else the solution nearest the middle "
                  "of the constrained joint box. " +
                      planning_world_help())
      ->excludes(configs_option)
      ->excludes(box_option);
  configs_option->excludes(box_option);
  cmd->add_option("--task-count", o->task_count,
                  "Task configurations drawn (box or random) when no --task-configs or "
                  "--task-poses file")
      ->capture_default_str();
  auto* prior_option = cmd->add_option(
      "--prior-model", o->prior_model,
      "A calibrated model of this robot with its cross-validation (calibrate --kfold 5 --sigma "
      "S): its held-out error, less noise, is the model misfit added to the prediction");
  cmd->add_option("--misfit-mm", o->misfit_mm,
                  "The model misfit (RMS systematic TCP error a calibration leaves, mm) added to "
                  "the prediction, when known from elsewhere")
      ->excludes(prior_option);
  cmd->add_option("--out", o->out, "Output CSV: config,target,j1..j6 (deg)[,approach][,payload]")
      ->required();
  cmd->add_flag("--json", o->json, "Machine-readable output");
  cmd->callback([o] { run_plan(*o); });
});

}  // namespace
}  // namespace robcal::cli
