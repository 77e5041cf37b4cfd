#include "robcal/design/calibration_planning.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <numeric>

#include "robcal/campaign/cell_planning.hpp"
#include "robcal/campaign/feasibility.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/progress.hpp"
#include "robcal/core/units.hpp"
#include "robcal/design/predicted_accuracy.hpp"
#include "robcal/identify/unknowns.hpp"

namespace robcal {

ConditionVariety parse_condition_variety(const std::string& text, const std::string& fixed_name,
                                         const std::string& flag) {
  if (text == "auto") return ConditionVariety::Auto;
  if (text == fixed_name) return ConditionVariety::Fixed;
  if (text == "varied") return ConditionVariety::Varied;
  throw InputError({"", 0, 0, flag},
                   fmt::format("'{}': expected auto, {} or varied", text, fixed_name));
}

SelectionCriterion parse_selection_criterion(const std::string& text, const std::string& flag) {
  if (text == "default") return SelectionCriterion::Default;
  if (text == "d") return SelectionCriterion::DOptimal;
  if (text == "i") return SelectionCriterion::IOptimal;
  if (text == "published") return SelectionCriterion::Published;
  throw InputError({"", 0, 0, flag},
                   fmt::format("unknown criterion '{}', expected 'default', 'd' (D-optimal), 'i' "
                               "(I-optimal over the task region) or 'published'",
                               text));
}

const char* criterion_name(SelectionCriterion criterion) {
  switch (criterion) {
    case SelectionCriterion::Default:
      return "default";
    case SelectionCriterion::DOptimal:
      return "D-optimal";
    case SelectionCriterion::IOptimal:
      return "I-optimal";
    case SelectionCriterion::Published:
      return "published exchange";
  }
  return "";
}

JointConstraints default_joint_constraints(const RobotModel& model) {
  // The published constraints (one-signed gearbox torques, docs/method/05-observability.md §2) were
  // chosen for the IRB 120's geometry and zero positions; on another robot the same numbers mean
  // other poses (on a UR θ2 ≥ 0 points the upper arm down), so only its own limits apply.
  return model.name == "ABB IRB 120" ? published_joint_constraints() : unconstrained_joints();
}

JointConstraints plan_joint_constraints(const RobotModel& model, const std::string& name,
                                        const std::string& flag) {
  if (name == "auto") return default_joint_constraints(model);
  if (name == "robot" || name == "none") return unconstrained_joints();
  if (name == "published") return published_joint_constraints();
  throw InputError({"", 0, 0, flag},
                   fmt::format("unknown constraint preset '{}', expected 'auto' (published for "
                               "the ABB IRB 120, else the robot file's limits), 'robot', "
                               "'published' or 'none'",
                               name));
}

std::vector<char> near_task_region(const RobotModel& model, const Tool& tool,
                                   const ParameterVector& params, const std::vector<Vector6d>& task,
                                   const std::vector<Candidate>& candidates, double margin_mm) {
  std::vector<char> out(candidates.size(), 0);
  if (task.empty()) return out;
  const Eigen::Vector3d tcp = tool.flange_T_tcp.translation();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const Vector6d& q : task) {
    const Eigen::Vector3d p = flange_pose(model, tool.payload, params, q) * tcp;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo.array() -= margin_mm;
  hi.array() += margin_mm;
  for (size_t i = 0; i < candidates.size(); ++i) {
    const Eigen::Vector3d p = flange_pose(model, tool.payload, params, candidates[i].joints) * tcp;
    out[i] = (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all() ? 1 : 0;
  }
  return out;
}

namespace {

// Gap of the continuous D-optimal design the efficiencies are certified against: the bound
// loosens by the factor e^(−gap) ≈ 0.99 (the reported efficiency stays a lower bound), and the
// multiplicative algorithm needs several times fewer iterations than at 1e-3.
constexpr double kContinuousTolerance = 1e-2;

/// The cell the plan is made for: the nominal robot placed at the cell's base, its instrument.
struct PlanningCell {
  TrueRobot robot;
  VirtualInstrument instrument;
  std::string name;
};

PlanningCell planning_cell_of(const PlanRequest& request) {
  PlanningCell out;
  if (request.cell) {
    out.robot =
        planning_cell(request.model, request.tool, campaign::base_parameters(*request.cell));
    out.instrument = campaign::virtual_instrument(*request.cell, request.tool);
    out.name = request.cell->name.empty() ? request.cell->file : request.cell->name;
    return out;
  }
  Eigen::Matrix<double, 6, 1> base;
  const std::array<double, 6> placement = default_base_placement();
  for (int i = 0; i < 6; ++i)
    base[i] =
        i < 3 ? placement[static_cast<size_t>(i)] : deg2rad(placement[static_cast<size_t>(i)]);
  out.robot = planning_cell(request.model, request.tool, base);
  out.instrument = standard_instrument(request.instrument, out.robot, request.noise_mm);
  out.name = "simulator standard cell";
  return out;
}

/// The candidates kept for the selection, with their scaled design rows.
struct Pool {
  std::vector<Candidate> candidates;
  Eigen::MatrixXd rows;  ///< as DesignMatrix::rows
};

/// Scaled design rows of `candidates` in the layout of `design` (its parameters and scale).
Eigen::MatrixXd design_rows(const TrueRobot& cell, const DesignSettings& settings,
                            const DesignMatrix& design, const std::vector<Candidate>& candidates) {
  const int r = design.rows_per_candidate;
  Eigen::MatrixXd out(static_cast<Eigen::Index>(candidates.size()) * r, design.columns());
  for (size_t i = 0; i < candidates.size(); ++i) {
    const Eigen::MatrixXd full = candidate_jacobian(
        cell.robot.model, cell.robot.tool, *settings.linearisation, candidates[i], settings);
    for (int j = 0; j < design.columns(); ++j)
      out.block(static_cast<Eigen::Index>(i) * r, j, r, 1) =
          full.col(design.parameters[static_cast<size_t>(j)]) * design.column_scale[j];
  }
  return out;
}

/// The request's listed configurations as candidates: inside the robot's joint limits, the
/// target the file names or (when it names none) the first the instrument sees.
CandidateSet listed_candidates(const PlanRequest& request, const PlanningCell& cell,
                               int& outside_limits) {
  CandidateSet out;
  const RobotModel& model = request.model;
  const MeasurementKind kind = measurement_kind(cell.instrument.kind);
  for (const PlannedConfiguration& c : request.candidate_configurations) {
    ++out.draws;
    bool inside = true;
    for (int k = 0; k < kJointCount; ++k)
      if (c.joints[k] < model.limits[k].lower || c.joints[k] > model.limits[k].upper)
        inside = false;
    if (!inside) {
      ++outside_limits;
      continue;
    }
    Candidate candidate{c.joints, c.target, c.approach, c.payload};
    if (kind == MeasurementKind::Poses) {
      candidate.target = -1;
    } else if (c.target < 0) {
      std::vector<int> seen;
      if (request.cell) {
        seen = campaign::check_configuration(*request.cell, model, request.tool, c.joints, -1)
                   .visible_targets;
      } else if (kind == MeasurementKind::Points) {
        seen = visible_targets(
            cell.instrument.tracker,
            flange_pose(model, request.tool.payload, cell.robot.robot.params, c.joints),
            request.tool);
      } else {
        seen = {0};
      }
      if (seen.empty()) {
        ++out.not_visible;
        continue;
      }
      candidate.target = seen.front();
    }
    out.candidates.push_back(candidate);
  }
  if (out.candidates.empty())
    throw InputError({request.candidates_file, 0, 0, "--candidates-file"},
                     fmt::format("none of the {} listed configurations can be used: {} outside the "
                                 "robot's joint limits, {} with no target the instrument sees",
                                 out.draws, outside_limits, out.not_visible));
  return out;
}

/// Leverage of every row block under the information `M` (scaled): D: tr(A_i M⁻¹ A_iᵀ);
/// with a task information B: tr(A_i M⁻¹ B M⁻¹ A_iᵀ). Both are a K aᵀ per row a with one m × m
/// matrix K formed once (M⁻¹, or M⁻¹ B M⁻¹), so the rows pass through a single product.
Eigen::VectorXd leverage(const Eigen::MatrixXd& rows, int r, const Eigen::MatrixXd& M,
                         const Eigen::MatrixXd* task_information) {
  const Eigen::LLT<Eigen::MatrixXd> llt(M);
  const Eigen::MatrixXd M_inverse = llt.solve(Eigen::MatrixXd::Identity(M.rows(), M.cols()));
  const Eigen::MatrixXd K =
      task_information ? Eigen::MatrixXd(M_inverse * *task_information * M_inverse) : M_inverse;
  const Eigen::VectorXd per_row = (rows * K).cwiseProduct(rows).rowwise().sum();
  Eigen::VectorXd out(rows.rows() / r);
  for (Eigen::Index i = 0; i < out.size(); ++i) out[i] = per_row.segment(i * r, r).sum();
  return out;
}

/// Keeps the `keep` most informative of the pool (see plan_calibration), in draw order.
void reduce_pool(Pool& pool, int r, int keep, const Eigen::MatrixXd& M,
                 const Eigen::MatrixXd* task_information, const SelectionGuard* guard) {
  const int n = static_cast<int>(pool.candidates.size());
  if (n <= keep) return;
  const Eigen::VectorXd score = leverage(pool.rows, r, M, task_information);
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return score[a] > score[b]; });
  std::vector<char> kept(static_cast<size_t>(n), 0);
  int taken = 0;
  if (guard) {
    // Half the pool away from the edges, so that the guard finds admissible candidates.
    for (int i : order)
      if (taken < keep / 2 &&
          !near_joint_edge(*guard, pool.candidates[static_cast<size_t>(i)].joints))
        kept[static_cast<size_t>(i)] = 1, ++taken;
  }
  for (int i : order)
    if (taken < keep && !kept[static_cast<size_t>(i)]) kept[static_cast<size_t>(i)] = 1, ++taken;
  Pool out;
  out.rows.resize(static_cast<Eigen::Index>(keep) * r, pool.rows.cols());
  for (int i = 0; i < n; ++i) {
    if (!kept[static_cast<size_t>(i)]) continue;
    out.rows.middleRows(static_cast<Eigen::Index>(out.candidates.size()) * r, r) =
        pool.rows.middleRows(static_cast<Eigen::Index>(i) * r, r);
    out.candidates.push_back(pool.candidates[static_cast<size_t>(i)]);
  }
  pool = std::move(out);
}

/// A DesignMatrix over given rows in `layout`'s columns.
DesignMatrix with_rows(const DesignMatrix& layout, Eigen::MatrixXd rows) {
  DesignMatrix out;
  out.rows_per_candidate = layout.rows_per_candidate;
  out.parameters = layout.parameters;
  out.dropped = layout.dropped;
  out.column_scale = layout.column_scale;
  out.rows = std::move(rows);
  return out;
}

bool plans_any(const std::vector<int>& parameters, const std::vector<int>& group) {
  return std::any_of(parameters.begin(), parameters.end(), [&](int i) {
    return std::find(group.begin(), group.end(), i) != group.end();
  });
}

/// Which conditions the drawn candidates vary (docs/method/05-observability.md §7): the approach
/// sides when a backlash parameter is planned for (its column is the joint's column times the
/// side: one side alone makes it the joint offset's), the payloads when a compliance is planned
/// for and the tool lists payloads (several payloads separate compliance from geometry).
struct CandidateConditions {
  bool approach_varied = false;
  bool payloads_varied = false;
};

CandidateConditions candidate_conditions(const PlanRequest& request,
                                         const std::vector<int>& parameters) {
  std::vector<int> compliances;
  for (int i : parameters)
    if (parameter_table()[static_cast<size_t>(i)].name.ends_with(".compliance"))
      compliances.push_back(i);
  if (request.payloads == ConditionVariety::Varied && request.tool.payloads.empty())
    throw InputError({"", 0, 0, "--payloads"},
                     "the tool file lists no payloads to vary: add them under 'payloads:' "
                     "(docs/method/03-error-model.md §7) or leave --payloads at auto");
  CandidateConditions out;
  out.approach_varied = request.approach == ConditionVariety::Varied ||
                        (request.approach == ConditionVariety::Auto &&
                         plans_any(parameters, opt_in_group_parameters("backlash")));
  out.payloads_varied = request.payloads == ConditionVariety::Varied ||
                        (request.payloads == ConditionVariety::Auto &&
                         !request.tool.payloads.empty() && !compliances.empty());
  return out;
}

/// Draws each candidate's sides (each joint from below or above, even odds, but only a side whose
/// approach move, 5° away, stays inside the joint's limits) and payload (the tool's own or one
/// of its `payloads`, even odds) as `conditions` asks.
void draw_conditions(const CandidateConditions& conditions, const RobotModel& model,
                     const Tool& tool, std::mt19937_64& rng, std::vector<Candidate>& candidates) {
  const double approach_rad = deg2rad(5.0);  // the measurement programs' default approach
  std::uniform_int_distribution<int> payload(-1, static_cast<int>(tool.payloads.size()) - 1);
  for (Candidate& c : candidates) {
    if (conditions.approach_varied)
      for (int j = 0; j < kJointCount; ++j) {
        const JointLimit& l = model.limits[static_cast<size_t>(j)];
        const bool below = c.joints[j] - approach_rad >= l.lower;
        const bool above = c.joints[j] + approach_rad <= l.upper;
        const bool drawn_below = (rng() & 1U) != 0;
        c.approach[j] = below && (drawn_below || !above) ? 1.0 : above ? -1.0 : 1.0;
      }
    if (conditions.payloads_varied) c.payload = payload(rng);
  }
}

/// What the user should know of the conditions: which are varied (the configurations file's
/// columns, followed by `program` and `session`), and the groups a plan cannot serve.
void add_condition_notes(const std::vector<int>& parameters, const CandidateConditions& conditions,
                         uint64_t seed, std::vector<std::string>& notes) {
  if (conditions.approach_varied)
    notes.push_back(fmt::format(
        "each joint of each candidate is approached from below or above (drawn with seed {}), "
        "so that the backlash is identifiable: the configurations file's approach column, which "
        "`robcal program` and `robcal session` follow",
        seed));
  else if (plans_any(parameters, opt_in_group_parameters("backlash")))
    notes.push_back(
        "every configuration is approached from below (--approach below): the backlash cannot "
        "be told from the joint offsets; use --approach varied");
  if (conditions.payloads_varied)
    notes.push_back(
        "each candidate carries the tool's own payload or one of its 'payloads' (drawn), "
        "grouped so that each is mounted once: the configurations file's payload column");
  if (plans_any(parameters, opt_in_group_parameters("thermal")) ||
      plans_any(parameters, opt_in_group_parameters("warmup")))
    notes.push_back(
        "the thermal and warm-up groups need rows at several arm temperatures or times, which a "
        "plan cannot choose: measure the plan through a warm-up, recording the temperature or "
        "time of each row (docs/method/03-error-model.md §8, §10)");
}

std::vector<Vector6d> task_region(const PlanRequest& request, const PlanningCell& cell,
                                  const JointConstraints& constraints, double floor_mm,
                                  std::mt19937_64& rng, std::string& region) {
  const RobotModel& model = request.model;
  const Tool& tool = request.tool;
  if (!request.task_configurations.empty()) {
    region = request.task_configurations_file.empty() ? "given configurations"
                                                      : request.task_configurations_file;
    return request.task_configurations;
  }
  if (!request.task_poses.empty()) {
    region = fmt::format("TCP poses of {}", request.task_poses_file);
    return task_pose_configurations(model, tool, cell.robot.robot.params, constraints,
                                    request.task_poses, request.task_poses_file);
  }
  if (request.task_box) {
    const TaskBox& b = *request.task_box;
    region =
        fmt::format("TCP box {},{},{},{},{},{} mm (world frame), tool pointing down", b.min_mm.x(),
                    b.max_mm.x(), b.min_mm.y(), b.max_mm.y(), b.min_mm.z(), b.max_mm.z());
    return task_box_configurations(model, tool, cell.robot.robot.params, constraints, b,
                                   request.task_count, rng);
  }
  region = "random configurations in the constrained joint box";
  CandidateOptions options;
  options.constraints = constraints;
  options.floor_z_mm = floor_mm;
  options.count = request.task_count;
  std::vector<Vector6d> out;
  for (const Candidate& c : generate_candidates(model, tool, options, rng).candidates)
    out.push_back(c.joints);
  return out;
}

}  // namespace

PlanResult plan_calibration(const PlanRequest& request) {
  if (request.count <= 0)
    throw InputError({"", 0, 0, "--count"},
                     fmt::format("expected a positive count, got {}", request.count));
  if (request.noise_mm < 0)
    throw InputError({"", 0, 0, "--noise-mm"}, "expected a non-negative noise");
  if (request.task_count <= 0)
    throw InputError({"", 0, 0, "--task-count"},
                     fmt::format("expected a positive number of task configurations, got {}",
                                 request.task_count));
  // Streamed in batches, candidates no longer bound memory, only time (about 20 µs each).
  constexpr int kMaxStreamedCandidates = 1000000;
  if (request.candidate_configurations.empty() &&
      (request.candidates <= 0 || request.candidates > kMaxStreamedCandidates))
    throw InputError({"", 0, 0, "--candidates"},
                     fmt::format("expected 1 to {} candidates (drawn and scored in batches, about "
                                 "20 µs each), got {}",
                                 kMaxStreamedCandidates, request.candidates));
  if (request.pool < 2 * request.count)
    throw InputError({"", 0, 0, "--pool"},
                     fmt::format("expected a pool of at least twice the count ({}), got {}",
                                 2 * request.count, request.pool));
  // The floor is a height in the cell: beyond ±20 m it is a typo or a unit slip, not a floor.
  if (!(std::abs(request.floor_mm) <= 20000))
    throw InputError({"", 0, 0, "--floor-mm"},
                     fmt::format("{:g} mm is outside the plausible range [-20000, 20000] mm of a "
                                 "floor height over the robot's base plane",
                                 request.floor_mm));
  if (request.prior_model && request.misfit_mm)
    throw InputError({"", 0, 0, "--misfit-mm"},
                     "give the misfit either from a prior model (--prior-model) or directly "
                     "(--misfit-mm), not both");
  const RobotModel& model = request.model;
  const Tool& tool = request.tool;
  const PlanningCell cell = planning_cell_of(request);
  const JointConstraints constraints =
      request.constraints.value_or(default_joint_constraints(model));
  const double floor_mm = request.cell ? request.cell->floor_z_mm : request.floor_mm;
  SelectionGuard guard = request.guard;
  guard.box = constrained_joint_box(model, constraints);

  PlanResult result;
  result.cell = cell.name;
  result.instrument = instrument_name(cell.instrument.kind);
  result.sigma_mm = request.noise_mm > 0 ? request.noise_mm : instrument_sigma(cell.instrument);
  // Resolved before the candidates are drawn, so that a prior model without a cross-validation
  // stops the run at once.
  if (request.prior_model)
    result.misfit =
        misfit_from_prior_model(*request.prior_model, request.prior_model_file, result.sigma_mm);
  else if (request.misfit_mm)
    result.misfit = misfit_given(*request.misfit_mm);
  result.task_region_given = !request.task_configurations.empty() || !request.task_poses.empty() ||
                             request.task_box.has_value();
  result.criterion = request.criterion != SelectionCriterion::Default ? request.criterion
                     : result.task_region_given                       ? SelectionCriterion::IOptimal
                                                : SelectionCriterion::DOptimal;
  std::mt19937_64 rng(request.seed), task_rng(request.seed + 1), sample_rng(request.seed + 2);
  // Listed task poses are solved first so that a pose out of reach stops the run early.
  const std::vector<Vector6d> task =
      task_region(request, cell, constraints, floor_mm, task_rng, result.region);
  result.task_configurations = static_cast<int>(task.size());

  PlanSettings settings;
  settings.level = request.level;
  settings.constraints = constraints;
  settings.floor_mm = floor_mm;
  DesignSettings design_settings = plan_design_settings(cell.robot, cell.instrument, request.level);
  design_settings.parameters = identified_model_parameters(
      request.model, request.tool, design_settings.kind, request.level, request.identify);
  const CandidateConditions conditions = candidate_conditions(request, design_settings.parameters);
  result.approach_varied = conditions.approach_varied;
  result.payloads_varied = conditions.payloads_varied;
  std::mt19937_64 condition_rng(request.seed + 4);
  add_condition_notes(design_settings.parameters, conditions, request.seed + 4, result.notes);
  const int r = measurement_kind(cell.instrument.kind) == MeasurementKind::Points  ? 3
                : measurement_kind(cell.instrument.kind) == MeasurementKind::Poses ? 6
                                                                                   : 1;
  // The candidate stream: the listed configurations in batches, or random draws in the cell.
  const bool listed = !request.candidate_configurations.empty();
  const CandidateSet listed_set =
      listed ? listed_candidates(request, cell, result.outside_limits) : CandidateSet{};
  const int wanted = listed ? static_cast<int>(listed_set.candidates.size()) : request.candidates;
  const auto next_batch = [&](int done, int n) {
    if (listed) {
      CandidateSet batch;
      batch.candidates.assign(listed_set.candidates.begin() + done,
                              listed_set.candidates.begin() + done + n);
      return batch;
    }
    if (request.cell) {
      campaign::CellCandidateOptions options;
      options.box = constrained_joint_box(model, constraints);
      options.count = n;
      return campaign::candidate_set(
          campaign::feasible_candidates(*request.cell, model, tool, options, rng));
    }
    settings.candidates = n;
    return instrument_candidates(cell.robot, cell.instrument, settings, rng);
  };

  DesignMatrix layout;
  Eigen::MatrixXd task_info, M_seen;
  Pool pool;
  std::vector<Candidate> sample;  // uniform sample of every candidate (reservoir)
  Eigen::MatrixXd sample_rows;
  const std::vector<Eigen::Vector3d> tcp{tool.flange_T_tcp.translation()};
  const bool task_aware = result.criterion == SelectionCriterion::IOptimal;
  Progress progress("drawing and scoring candidate batches",
                    (static_cast<std::int64_t>(wanted) + request.pool - 1) / request.pool);
  // The next batch is drawn on a second thread while this one is scored. One thread draws every
  // batch, in order, and stops after a short batch as this loop does, so the draws (and the
  // generator's state afterwards) are those of drawing one batch after the other.
  const auto draw_from = [&](int done) {
    return std::async(std::launch::async,
                      [&next_batch, done, asked = std::min(request.pool, wanted - done)] {
                        return next_batch(done, asked);
                      });
  };
  std::future<CandidateSet> drawing = draw_from(0);
  int seen = 0;
  while (seen < wanted) {
    const int asked = std::min(request.pool, wanted - seen);
    CandidateSet batch = drawing.get();
    if (!listed) draw_conditions(conditions, model, tool, condition_rng, batch.candidates);
    const int drawn = seen + static_cast<int>(batch.candidates.size());
    if (static_cast<int>(batch.candidates.size()) == asked && drawn < wanted)
      drawing = draw_from(drawn);
    result.draws += batch.draws;
    result.below_floor += batch.below_floor;
    result.not_visible += batch.not_visible;
    if (batch.candidates.empty()) break;
    Eigen::MatrixXd rows;
    if (seen == 0) {
      // The first batch fixes the identifiable parameters and the column scaling.
      layout = build_design_matrix(model, tool, batch.candidates, design_settings);
      rows = std::move(layout.rows);
      layout.rows.resize(0, rows.cols());
      task_info =
          task_information(layout, position_jacobian(model, tool.payload, cell.robot.robot.params,
                                                     layout.parameters, task, tcp));
      M_seen = Eigen::MatrixXd::Zero(rows.cols(), rows.cols());
      sample_rows.resize(static_cast<Eigen::Index>(request.count) * r, rows.cols());
    } else {
      rows = design_rows(cell.robot, design_settings, layout, batch.candidates);
    }
    M_seen.noalias() += rows.transpose() * rows;
    for (size_t i = 0; i < batch.candidates.size(); ++i) {
      const int index = seen + static_cast<int>(i);
      int slot = index;
      if (index >= request.count) slot = std::uniform_int_distribution<int>(0, index)(sample_rng);
      if (slot < request.count) {
        if (index < request.count)
          sample.push_back(batch.candidates[i]);
        else
          sample[static_cast<size_t>(slot)] = batch.candidates[i];
        sample_rows.middleRows(static_cast<Eigen::Index>(slot) * r, r) =
            rows.middleRows(static_cast<Eigen::Index>(i) * r, r);
      }
    }
    seen += static_cast<int>(batch.candidates.size());
    const Eigen::Index old_rows = pool.rows.rows();
    pool.rows.conservativeResize(old_rows + rows.rows(), rows.cols());
    pool.rows.bottomRows(rows.rows()) = rows;
    pool.candidates.insert(pool.candidates.end(), batch.candidates.begin(), batch.candidates.end());
    if (static_cast<int>(pool.candidates.size()) > request.pool) {
      const Eigen::MatrixXd M =
          M_seen / seen +
          1e-9 * Eigen::MatrixXd::Identity(M_seen.rows(), M_seen.cols());  // mean information
      reduce_pool(pool, r, request.pool, M, task_aware ? &task_info : nullptr,
                  task_aware && guard.enabled ? &guard : nullptr);
    }
    progress.advance();
    if (static_cast<int>(batch.candidates.size()) < asked) break;  // the draw budget ran out
  }
  result.candidates = seen;
  result.pooled = static_cast<int>(pool.candidates.size());
  if (request.count > result.pooled)
    throw InputError(
        {"", 0, 0, "--count"},
        fmt::format("{} configurations asked for, only {} feasible candidates{}", request.count,
                    result.pooled, listed ? " listed" : "; raise --candidates"));
  const DesignMatrix design = with_rows(layout, std::move(pool.rows));
  const DesignMatrix random_design = with_rows(layout, sample_rows);
  result.parameters = design.parameters;
  result.dropped = design.dropped;
  // The continuous optimum the efficiencies are certified against does not depend on the
  // selection: computed on a second thread meanwhile.
  std::future<ContinuousDesign> continuous_optimum = std::async(
      std::launch::async, [&design] { return d_optimal_continuous(design, kContinuousTolerance); });

  std::vector<int> chosen;
  std::vector<Vector6d> pool_joints;
  for (const Candidate& c : pool.candidates) pool_joints.push_back(c.joints);
  switch (result.criterion) {
    case SelectionCriterion::IOptimal: {
      const std::vector<char> in_task =
          guard.enabled ? near_task_region(model, tool, cell.robot.robot.params, task,
                                           pool.candidates, guard.task_margin_mm)
                        : std::vector<char>{};
      const TaskSelection s =
          select_i_optimal(design, task_info, request.count, pool_joints, guard, in_task);
      chosen = s.chosen;
      result.exchanges = s.exchanges;
      break;
    }
    case SelectionCriterion::Published: {
      const Selection s = select_published_exchange(design, request.count, rng);
      chosen = s.chosen;
      result.exchanges = s.exchanges;
      break;
    }
    default: {
      const Selection s = select_d_optimal(design, request.count, {.seed = request.seed});
      chosen = s.chosen;
      result.exchanges = s.exchanges;
      result.restarts = s.restarts;
    }
  }
  std::vector<int> all_random(static_cast<size_t>(request.count));
  std::iota(all_random.begin(), all_random.end(), 0);
  result.selected = observability_indices(design, chosen);
  result.random = observability_indices(random_design, all_random);
  const ContinuousDesign optimum = continuous_optimum.get();
  result.d_efficiency_selected = d_efficiency(design, chosen, optimum);
  result.d_efficiency_random = d_efficiency(random_design, all_random, optimum);
  result.edge_limit = result.criterion == SelectionCriterion::IOptimal
                          ? guard_edge_limit(guard, request.count)
                          : request.count;
  for (int i : chosen)
    result.near_edge += near_joint_edge(guard, pool.candidates[static_cast<size_t>(i)].joints);
  for (const Candidate& c : sample) result.near_edge_random += near_joint_edge(guard, c.joints);
  // Without the guard (a criterion other than I) the design may rest on the edges, where the
  // effects outside the model are largest (docs/method/05-observability.md §5): say so.
  if (result.criterion != SelectionCriterion::IOptimal &&
      result.near_edge > guard_edge_limit(guard, request.count))
    result.notes.push_back(fmt::format(
        "{} of {} configurations are near a joint-range edge (the guard allows {}), where effects "
        "the model does not contain are largest; {}",
        result.near_edge, request.count, guard_edge_limit(guard, request.count),
        result.task_region_given
            ? "--criterion i (the default with a task region) applies the guard"
            : "with a task region (--task-box, --task-poses, --task-configs) or --criterion i "
              "the guard applies"));

  const auto predict = [&](const DesignMatrix& d, const std::vector<int>& subset) {
    return predict_position_error(model, tool.payload, cell.robot.robot.params, d.parameters,
                                  design_parameter_covariance(d, subset, result.sigma_mm), task,
                                  tcp, result.sigma_mm);
  };
  result.predicted_selected = predict(design, chosen);
  result.predicted_random = predict(random_design, all_random);
  if (result.misfit) {
    result.predicted_rms_with_misfit_selected =
        rms_with_misfit(result.predicted_selected, *result.misfit);
    result.predicted_rms_with_misfit_random =
        rms_with_misfit(result.predicted_random, *result.misfit);
  }
  result.configurations = planned_configurations(pool.candidates, chosen);
  return result;
}

}  // namespace robcal
