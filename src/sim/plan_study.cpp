#include "robcal/sim/plan_study.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "robcal/campaign/cell_planning.hpp"
#include "robcal/campaign/feasibility.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/design/observability.hpp"
#include "robcal/design/predicted_accuracy.hpp"
#include "robcal/identify/accuracy_prediction.hpp"
#include "robcal/identify/cross_validation.hpp"
#include "robcal/identify/identification.hpp"

namespace robcal {

namespace {

RegionError region_error(const std::vector<double>& errors) {
  RegionError out;
  for (double e : errors) {
    out.mean_mm += e / static_cast<double>(errors.size());
    out.rms_mm += e * e / static_cast<double>(errors.size());
    out.max_mm = std::max(out.max_mm, e);
  }
  out.rms_mm = std::sqrt(out.rms_mm);
  return out;
}

/// TCP error against the truth at every task configuration of the model the user holds: the
/// robot file's masses and the tool file's payload with `params` (the truth's own masses differ
/// under a mass error, and the user's compensation does not know them).
RegionError error_against_truth(const TrueRobot& truth, const RobotModel& model, const Tool& tool,
                                const ParameterVector& params, const std::vector<Vector6d>& task) {
  const Eigen::Vector3d tcp = tool.flange_T_tcp.translation();
  std::vector<double> errors;
  errors.reserve(task.size());
  for (const Vector6d& q : task)
    errors.push_back(
        (flange_pose(model, tool.payload, params, q) * tcp - true_flange_pose(truth, q) * tcp)
            .norm());
  return region_error(errors);
}

/// The study's cell around a true robot: the truth placed at the cell's base (plus its random
/// base error), the cell's instrument, and candidates by the cell's feasibility checks.
std::array<double, 6> base_placement_deg(const PlanStudyOptions& options) {
  if (!options.cell) return default_base_placement();
  std::array<double, 6> out = options.cell->robot_base;
  for (size_t i = 3; i < 6; ++i) out[i] = rad2deg(out[i]);
  return out;
}

VirtualInstrument study_instrument(const PlanStudyOptions& options, const TrueRobot& truth) {
  if (!options.cell) return standard_instrument(options.instrument, truth, options.noise_mm);
  VirtualInstrument out = campaign::virtual_instrument(*options.cell, truth.robot.tool);
  if (options.noise_mm > 0) {
    out.tracker.sigma_mm.setConstant(options.noise_mm);
    out.cmm.sigma_mm = options.noise_mm;
  }
  return out;
}

}  // namespace

SelectionCriterion study_criterion(const PlanStudyOptions& options) {
  if (options.criterion != SelectionCriterion::Default) return options.criterion;
  return options.task_box || !options.task_poses.empty() ? SelectionCriterion::IOptimal
                                                         : SelectionCriterion::DOptimal;
}

StudySummary summarize(const std::vector<StudyOutcome>& outcomes) {
  StudySummary s;
  if (outcomes.empty()) return s;
  const double n = static_cast<double>(outcomes.size());
  for (const StudyOutcome& o : outcomes) {
    s.achieved_mean_mm += o.achieved.mean_mm / n;
    s.achieved_rms_mm += o.achieved.rms_mm * o.achieved.rms_mm / n;
    s.achieved_max_mm += o.achieved.max_mm / n;
    s.predicted_mean_mm += o.predicted.mean_mm / n;
    s.predicted_rms_mm += o.predicted.rms_mm * o.predicted.rms_mm / n;
    s.predicted_rms_with_misfit_mm +=
        o.predicted_rms_with_misfit_mm * o.predicted_rms_with_misfit_mm / n;
    s.O1 += o.O1 / n;
  }
  s.achieved_rms_mm = std::sqrt(s.achieved_rms_mm);
  s.predicted_rms_mm = std::sqrt(s.predicted_rms_mm);
  s.predicted_rms_with_misfit_mm = std::sqrt(s.predicted_rms_with_misfit_mm);
  return s;
}

PlanStudyResult run_plan_study(const RobotModel& model, const Tool& tool,
                               const PlanStudyOptions& options,
                               const std::function<void(int done, int total)>& progress) {
  PlanStudyResult result;
  for (int count : options.counts) result.rows.push_back({count, {}, {}});
  const int largest = *std::max_element(options.counts.begin(), options.counts.end());
  for (int k = 0; k < options.seeds; ++k) {
    const uint64_t s = options.seed + 10 * static_cast<uint64_t>(k);
    result.seeds.push_back(s);
    std::mt19937_64 truth_rng(s), candidate_rng(s + 1), subset_rng(s + 2), task_rng(s + 3),
        noise_rng(s + 4);
    TrueRobot truth =
        random_truth(model, tool, options.bounds, truth_rng, base_placement_deg(options));
    if (!options.effects.empty()) enable_effects(truth, options.effects, truth_rng);
    const VirtualInstrument instrument = study_instrument(options, truth);
    const double sigma = instrument_sigma(instrument);
    result.sigma_mm = sigma;
    // What the planner knows: the nominal robot placed like the truth.
    const TrueRobot cell = planning_cell(model, tool, truth.robot.params.head<kBaseParamCount>());
    const std::array<JointLimit, kJointCount> box =
        constrained_joint_box(model, options.plan.constraints);
    CandidateSet pool;
    if (options.cell) {
      campaign::CellCandidateOptions cell_options;
      cell_options.box = box;
      cell_options.count = options.plan.candidates;
      pool = campaign::candidate_set(
          campaign::feasible_candidates(*options.cell, model, tool, cell_options, candidate_rng));
    } else {
      pool = instrument_candidates(cell, instrument, options.plan, candidate_rng);
    }
    const int drawn = static_cast<int>(pool.candidates.size());
    if (largest > drawn)
      throw InputError({"", 0, 0, "--counts"},
                       fmt::format("a count of {} needs more than the {} feasible candidates; "
                                   "raise --candidates",
                                   largest, drawn));
    result.candidates = k == 0 ? drawn : std::min(result.candidates, drawn);

    std::vector<Vector6d> task;
    if (!options.task_poses.empty()) {
      task = task_pose_configurations(model, tool, cell.robot.params, options.plan.constraints,
                                      options.task_poses, options.task_poses_file);
    } else if (options.task_box) {
      task = task_box_configurations(model, tool, cell.robot.params, options.plan.constraints,
                                     *options.task_box, options.task_count, task_rng);
    } else {
      CandidateOptions region;
      region.constraints = options.plan.constraints;
      region.floor_z_mm = options.plan.floor_mm;
      region.count = options.task_count;
      for (const Candidate& c : generate_candidates(model, tool, region, task_rng).candidates)
        task.push_back(c.joints);
    }
    result.task_configurations = static_cast<int>(task.size());
    result.nominal.push_back(error_against_truth(truth, model, tool, cell.robot.params, task));

    // The guard's task share: candidates whose TCP lies in the task region's TCP box.
    const SelectionCriterion criterion = study_criterion(options);
    const std::vector<char> in_task =
        criterion == SelectionCriterion::IOptimal && options.guard.enabled
            ? near_task_region(model, tool, cell.robot.params, task, pool.candidates,
                               options.guard.task_margin_mm)
            : std::vector<char>{};
    const DesignMatrix design = build_design_matrix(
        model, tool, pool.candidates, plan_design_settings(cell, instrument, options.plan.level));
    std::vector<int> shuffled(static_cast<size_t>(drawn));
    std::iota(shuffled.begin(), shuffled.end(), 0);
    std::shuffle(shuffled.begin(), shuffled.end(), subset_rng);
    const std::vector<Eigen::Vector3d> tcp{tool.flange_T_tcp.translation()};
    IdentifyOptions identify;
    identify.level = options.plan.level;
    identify.seed = s;
    // The prior calibration: random candidates measured and cross-validated, as the user would
    // before planning; its misfit is what no design of this model removes.
    MisfitAllowance misfit;
    if (options.prior_count > 0) {
      std::mt19937_64 prior_rng(s + 5);
      std::vector<int> prior(static_cast<size_t>(drawn));
      std::iota(prior.begin(), prior.end(), 0);
      std::shuffle(prior.begin(), prior.end(), prior_rng);
      prior.resize(static_cast<size_t>(std::min(options.prior_count, drawn)));
      const MeasurementSet measured =
          simulate_measurements(truth, instrument, planned_configurations(pool.candidates, prior),
                                prior_rng)
              .measurements;
      const IdentificationResult fit = calibrate(model, tool, measured, identify);
      const CrossValidation cv =
          cross_validate(model, tool, measured, identify, options.prior_folds, s);
      PriorCrossValidation p;
      p.mean_mm = cv.mean_mm;
      p.std_mm = cv.std_mm;
      p.folds = cv.folds;
      p.row_dimension = measured.kind == MeasurementKind::Distances ? 1 : 3;
      p.instrument_sigma_mm = sigma;
      p.predicted_rms_mm = fit.predicted.rms_mm;
      p.sigma_posterior_mm = fit.sigma_mm;
      misfit = misfit_from_cross_validation(p);
      misfit.source = fmt::format(
          "prior calibration from {} random configurations, {}-fold "
          "cross-validated",
          prior.size(), cv.folds);
      result.misfit.push_back(misfit);
    }
    const auto outcome = [&](const std::vector<int>& subset) {
      StudyOutcome out;
      const std::vector<PlannedConfiguration> configs =
          planned_configurations(pool.candidates, subset);
      const SimulationResult measured =
          simulate_measurements(truth, instrument, configs, noise_rng);
      out.measured = static_cast<int>(measured.measurements.size());
      const IdentificationResult fit = calibrate(model, tool, measured.measurements, identify);
      out.converged = fit.status.converged;
      out.achieved = error_against_truth(truth, model, tool, fit.robot.params, task);
      const PredictedAccuracy predicted = predict_position_error(
          model, tool.payload, cell.robot.params, design.parameters,
          design_parameter_covariance(design, subset, sigma), task, tcp, sigma);
      out.predicted = {predicted.mean_mm, predicted.rms_mm, predicted.max_mm};
      out.predicted_rms_with_misfit_mm = rms_with_misfit(predicted, misfit);
      out.O1 = observability_indices(design, subset).O1;
      return out;
    };
    Eigen::MatrixXd task_info;
    std::vector<Vector6d> pool_joints;
    SelectionGuard guard = options.guard;
    guard.box = box;
    if (criterion == SelectionCriterion::IOptimal) {
      task_info = task_information(design, position_jacobian(model, tool.payload, cell.robot.params,
                                                             design.parameters, task, tcp));
      for (const Candidate& c : pool.candidates) pool_joints.push_back(c.joints);
    }
    const auto planned = [&](int count) {
      if (criterion == SelectionCriterion::IOptimal)
        return select_i_optimal(design, task_info, count, pool_joints, guard, in_task).chosen;
      return select_d_optimal(design, count).chosen;
    };
    for (StudyRow& row : result.rows) {
      row.optimal.push_back(outcome(planned(row.count)));
      row.random.push_back(
          outcome(std::vector<int>(shuffled.begin(), shuffled.begin() + row.count)));
    }
    if (progress) progress(k + 1, options.seeds);
  }
  return result;
}

}  // namespace robcal
