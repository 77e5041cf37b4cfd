/// `robcal plan`: choose the configurations to measure (docs/method/05-observability.md) and
/// predict the accuracy they give before measuring.

#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <numeric>
#include <optional>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/design/candidates.hpp"
#include "robcal/design/design_matrix.hpp"
#include "robcal/design/observability.hpp"
#include "robcal/design/predicted_accuracy.hpp"
#include "robcal/design/selection.hpp"
#include "robcal/design/task_region.hpp"
#include "robcal/identify/accuracy_prediction.hpp"
#include "robcal/identify/unknowns.hpp"
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
  std::string level = "full";
  int count = 40;
  int candidates = 5000;
  uint64_t seed = 1;
  std::string constraints = "published";
  double floor_mm = 50;
  double noise_mm = 0;
  std::string method = "fast";
  std::string task_configs;
  std::string task_box;
  std::string task_poses;
  int task_count = 1000;
  std::string out;
  bool json = false;
};

nlohmann::json indices_json(const ObservabilityIndices& o) {
  return {{"O1", tidy(o.O1)},
          {"O2", tidy(o.O2)},
          {"O3", tidy(o.O3)},
          {"O4", tidy(o.O4)},
          {"O5", tidy(o.O5)}};
}

/// The world the task region is given in: the planning cell's, where the robot stands as in the
/// simulator's standard cell (and its instruments see it).
std::string planning_world_help() {
  const std::array<double, 6> b = default_base_placement();
  return fmt::format(
      "World frame: the planning cell's, as `robcal simulate` (robot base at x {} y {} z {} mm, "
      "α β γ {} {} {} deg, docs/method/02-frames.md)",
      b[0], b[1], b[2], b[3], b[4], b[5]);
}

void run_plan(const PlanOptions& o) {
  if (o.out.empty()) throw InputError({"", 0, 0, "--out"}, "expected an output file");
  if (o.count <= 0)
    throw InputError({"", 0, 0, "--count"},
                     fmt::format("expected a positive count, got {}", o.count));
  if (o.method != "fast" && o.method != "published")
    throw InputError({"", 0, 0, "--method"},
                     fmt::format("unknown method '{}', expected 'fast' or 'published'", o.method));
  if (o.noise_mm < 0) throw InputError({"", 0, 0, "--noise-mm"}, "expected a non-negative noise");
  const RobotModel model = load_robot(o.robot);
  const Tool tool = o.tool.empty() ? default_simulation_tool() : load_tool(o.tool);
  const InstrumentKind kind = parse_instrument_kind(o.instrument, "--instrument");
  PlanSettings settings;
  settings.level = parse_calibration_level(o.level);
  settings.count = o.count;
  settings.candidates = o.candidates;
  settings.constraints = joint_constraints_preset(o.constraints);
  settings.floor_mm = o.floor_mm;
  const std::optional<TaskBox> task_box =
      o.task_box.empty() ? std::nullopt : std::optional(parse_task_box(o.task_box, "--task-box"));
  const std::vector<ListedPose> task_poses =
      o.task_poses.empty() ? std::vector<ListedPose>{} : read_pose_list(o.task_poses);
  // The planning cell: the nominal robot placed as in the simulator's standard cell, so the
  // instrument's placement and visibility are those `robcal simulate` uses.
  Eigen::Matrix<double, 6, 1> base;
  const std::array<double, 6> placement = default_base_placement();
  for (int i = 0; i < 6; ++i)
    base[i] =
        i < 3 ? placement[static_cast<size_t>(i)] : deg2rad(placement[static_cast<size_t>(i)]);
  const TrueRobot cell = planning_cell(model, tool, base);
  const VirtualInstrument instrument = standard_instrument(kind, cell, o.noise_mm);
  // Listed task poses are solved before the selection so that a pose out of reach stops the
  // run early.
  std::vector<Vector6d> task;
  if (!task_poses.empty())
    task = task_pose_configurations(model, tool, cell.robot.params, settings.constraints,
                                    task_poses, o.task_poses);
  std::mt19937_64 rng(o.seed);

  const CandidateSet candidate_set = instrument_candidates(cell, instrument, settings, rng);
  const std::vector<Candidate>& candidates = candidate_set.candidates;
  if (static_cast<int>(candidates.size()) < o.candidates && !o.json)
    fmt::print(
        "note: only {} of {} candidates found in {} draws ({} below the floor, {} not "
        "seen by the instrument)\n",
        candidates.size(), o.candidates, candidate_set.draws, candidate_set.below_floor,
        candidate_set.not_visible);
  const DesignMatrix design = build_design_matrix(
      model, tool, candidates, plan_design_settings(cell, instrument, settings.level));

  const Selection chosen = o.method == "fast" ? select_d_optimal(design, o.count, {.seed = o.seed})
                                              : select_published_exchange(design, o.count, rng);
  std::vector<int> random(static_cast<size_t>(design.candidates()));
  std::iota(random.begin(), random.end(), 0);
  std::shuffle(random.begin(), random.end(), rng);
  random.resize(static_cast<size_t>(o.count));

  const ObservabilityIndices selected_o = observability_indices(design, chosen.chosen);
  const ObservabilityIndices random_o = observability_indices(design, random);
  const ContinuousDesign optimum = d_optimal_continuous(design);
  const double eff_selected = d_efficiency(design, chosen.chosen, optimum);
  const double eff_random = d_efficiency(design, random, optimum);

  // Predicted accuracy of the TCP over the task region: the given configurations or TCP poses,
  // a box of TCP positions, or random configurations in the constrained joint box above the
  // floor.
  std::string region = "random configurations in the constrained joint box";
  if (!task_poses.empty()) {
    region = fmt::format("TCP poses of {}", o.task_poses);
  } else if (!o.task_configs.empty()) {
    for (const PlannedConfiguration& c : read_configurations_csv(o.task_configs, tool))
      task.push_back(c.joints);
    region = o.task_configs;
  } else if (task_box) {
    task = task_box_configurations(model, tool, cell.robot.params, settings.constraints, *task_box,
                                   o.task_count, rng);
    region = fmt::format("TCP box {} mm (world frame), tool pointing down", o.task_box);
  } else {
    CandidateOptions options;
    options.constraints = settings.constraints;
    options.floor_z_mm = o.floor_mm;
    options.count = o.task_count;
    for (const Candidate& c : generate_candidates(model, tool, options, rng).candidates)
      task.push_back(c.joints);
  }
  const double sigma = o.noise_mm > 0 ? o.noise_mm : instrument_sigma(instrument);
  const std::vector<Eigen::Vector3d> tcp{tool.flange_T_tcp.translation()};
  const auto predict = [&](const std::vector<int>& subset) {
    return predict_position_error(model, tool.payload, cell.robot.params, design.parameters,
                                  design_parameter_covariance(design, subset, sigma), task, tcp,
                                  sigma);
  };
  const PredictedAccuracy acc_selected = predict(chosen.chosen);
  const PredictedAccuracy acc_random = predict(random);

  std::vector<PlannedConfiguration> configs;
  for (size_t k = 0; k < chosen.chosen.size(); ++k) {
    const Candidate& c = candidates[static_cast<size_t>(chosen.chosen[k])];
    configs.push_back({fmt::format("C{}", k + 1), c.joints, c.target});
  }
  write_file_atomically(o.out, write_configurations_csv(configs, tool));

  std::vector<std::string> dropped;
  for (int p : design.dropped) dropped.push_back(parameter_table()[static_cast<size_t>(p)].name);
  if (o.json) {
    nlohmann::json out;
    out["selected"] = indices_json(selected_o);
    out["random"] = indices_json(random_o);
    out["count"] = o.count;
    out["d_efficiency"] = tidy(eff_selected, 4);
    out["d_efficiency_random"] = tidy(eff_random, 4);
    out["candidates"] = design.candidates();
    out["parameters"] = design.columns();
    out["dropped"] = dropped;
    out["method"] = o.method;
    out["exchanges"] = chosen.exchanges;
    out["restarts"] = chosen.restarts;
    out["seed"] = o.seed;
    out["instrument"] = instrument_name(kind);
    out["level"] = o.level;
    out["sigma_mm"] = sigma;
    out["predicted_error_mm"] = {
        {"task_configurations", acc_selected.configurations},
        {"task_region", region},
        {"selected",
         {{"mean", tidy(acc_selected.mean_mm, 6)}, {"max", tidy(acc_selected.max_mm, 6)}}},
        {"random", {{"mean", tidy(acc_random.mean_mm, 6)}, {"max", tidy(acc_random.max_mm, 6)}}}};
    out["out"] = o.out;
    print_json(out);
    return;
  }
  fmt::print(
      "plan for {} with a {}, level {} ({} identifiable parameters{}), seed {}\n", model.name,
      instrument_name(kind), o.level, design.columns(),
      dropped.empty() ? "" : fmt::format("; dropped as dependent: {}", fmt::join(dropped, ", ")),
      o.seed);
  fmt::print("chose {} of {} feasible candidates ({} method, {} exchanges{})\n\n", o.count,
             design.candidates(), o.method, chosen.exchanges,
             o.method == "fast" ? fmt::format(", {} restarts", chosen.restarts) : "");
  fmt::print("index      selected        random\n");
  const auto row = [](const char* name, double a, double b) {
    fmt::print("{:<6} {:>12.6g}  {:>12.6g}\n", name, a, b);
  };
  row("O1", selected_o.O1, random_o.O1);
  row("O2", selected_o.O2, random_o.O2);
  row("O3", selected_o.O3, random_o.O3);
  row("O4", selected_o.O4, random_o.O4);
  row("O5", selected_o.O5, random_o.O5);
  row("D-eff", eff_selected, eff_random);
  fmt::print("\npredicted TCP error after calibration (σ = {} mm, {} task configurations: {}):\n",
             sigma, acc_selected.configurations, region);
  fmt::print("  selected: mean {:.4f} mm, max {:.4f} mm\n", acc_selected.mean_mm,
             acc_selected.max_mm);
  fmt::print("  random:   mean {:.4f} mm, max {:.4f} mm\n", acc_random.mean_mm, acc_random.max_mm);
  fmt::print("wrote {}\n", o.out);
}

const bool registered = register_command(60, [](CLI::App& app) {
  auto o = std::make_shared<PlanOptions>();
  auto* cmd = app.add_subcommand(
      "plan", "Choose calibration configurations (observability) and predict their accuracy");
  cmd->add_option("--robot", o->robot, "Built-in robot name or robot file")->capture_default_str();
  cmd->add_option("--tool", o->tool, "Tool file (default: 3 SMRs, 2.6 kg payload)");
  cmd->add_option("--instrument", o->instrument, "laser-tracker, optical-cmm or ballbar")
      ->capture_default_str();
  cmd->add_option("--level", o->level, "base, joints, kinematic or full")->capture_default_str();
  cmd->add_option("--count", o->count, "Configurations to choose")->capture_default_str();
  cmd->add_option("--candidates", o->candidates, "Random feasible candidates to choose from")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of every random draw")->capture_default_str();
  cmd->add_option("--constraints", o->constraints,
                  "Joint constraints: published (θ2≥0, θ3≥−80, |θ1|≤90, |θ4|≤150, |θ5|≤90, "
                  "|θ6|≤180 deg) or none")
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
  cmd->add_option("--out", o->out, "Output CSV: config,target,j1..j6 (deg)")->required();
  cmd->add_flag("--json", o->json, "Machine-readable output");
  cmd->callback([o] { run_plan(*o); });
});

}  // namespace
}  // namespace robcal::cli
