#include "robcal/sim/plan_study.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "robcal/core/error.hpp"
#include "robcal/design/observability.hpp"
#include "robcal/design/predicted_accuracy.hpp"
#include "robcal/identify/accuracy_prediction.hpp"
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

/// TCP error of the robot with `params` against the truth at every task configuration.
RegionError error_against_truth(const TrueRobot& truth, const ParameterVector& params,
                                const std::vector<Vector6d>& task) {
  const RobotModel& model = truth.robot.model;
  const Eigen::Vector3d tcp = truth.robot.tool.flange_T_tcp.translation();
  std::vector<double> errors;
  errors.reserve(task.size());
  for (const Vector6d& q : task)
    errors.push_back((flange_pose(model, truth.robot.tool.payload, params, q) * tcp -
                      true_flange_pose(truth, q) * tcp)
                         .norm());
  return region_error(errors);
}

}  // namespace

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
    s.O1 += o.O1 / n;
  }
  s.achieved_rms_mm = std::sqrt(s.achieved_rms_mm);
  s.predicted_rms_mm = std::sqrt(s.predicted_rms_mm);
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
    const TrueRobot truth = random_truth(model, tool, options.bounds, truth_rng);
    const VirtualInstrument instrument =
        standard_instrument(options.instrument, truth, options.noise_mm);
    const double sigma = instrument_sigma(instrument);
    result.sigma_mm = sigma;
    // What the planner knows: the nominal robot placed like the truth.
    const TrueRobot cell = planning_cell(model, tool, truth.robot.params.head<kBaseParamCount>());
    const CandidateSet pool = instrument_candidates(cell, instrument, options.plan, candidate_rng);
    const DesignMatrix design = build_design_matrix(
        model, tool, pool.candidates, plan_design_settings(cell, instrument, options.plan.level));
    if (largest > design.candidates())
      throw InputError({"", 0, 0, "--counts"},
                       fmt::format("a count of {} needs more than the {} feasible candidates; "
                                   "raise --candidates",
                                   largest, design.candidates()));
    result.candidates =
        k == 0 ? design.candidates() : std::min(result.candidates, design.candidates());

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
    result.nominal.push_back(error_against_truth(truth, cell.robot.params, task));

    std::vector<int> shuffled(static_cast<size_t>(design.candidates()));
    std::iota(shuffled.begin(), shuffled.end(), 0);
    std::shuffle(shuffled.begin(), shuffled.end(), subset_rng);
    const std::vector<Eigen::Vector3d> tcp{tool.flange_T_tcp.translation()};
    IdentifyOptions identify;
    identify.level = options.plan.level;
    identify.seed = s;
    const auto outcome = [&](const std::vector<int>& subset) {
      StudyOutcome out;
      const std::vector<PlannedConfiguration> configs =
          planned_configurations(pool.candidates, subset);
      const SimulationResult measured =
          simulate_measurements(truth, instrument, configs, noise_rng);
      out.measured = static_cast<int>(measured.measurements.size());
      const IdentificationResult fit = calibrate(model, tool, measured.measurements, identify);
      out.converged = fit.status.converged;
      out.achieved = error_against_truth(truth, fit.robot.params, task);
      const PredictedAccuracy predicted = predict_position_error(
          model, tool.payload, cell.robot.params, design.parameters,
          design_parameter_covariance(design, subset, sigma), task, tcp, sigma);
      out.predicted = {predicted.mean_mm, predicted.rms_mm, predicted.max_mm};
      out.O1 = observability_indices(design, subset).O1;
      return out;
    };
    for (StudyRow& row : result.rows) {
      row.optimal.push_back(outcome(select_d_optimal(design, row.count).chosen));
      row.random.push_back(
          outcome(std::vector<int>(shuffled.begin(), shuffled.begin() + row.count)));
    }
    if (progress) progress(k + 1, options.seeds);
  }
  return result;
}

}  // namespace robcal
