#include "robcal/sim/monte_carlo.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <thread>
#include <utility>

#include "robcal/core/error.hpp"
#include "robcal/core/progress.hpp"
#include "robcal/sim/campaign.hpp"

namespace robcal {

namespace {

/// The generator of run `run`: independent of the thread that executes it.
std::mt19937_64 run_generator(uint64_t seed, int run) {
  std::seed_seq sequence{static_cast<uint32_t>(seed), static_cast<uint32_t>(seed >> 32),
                         static_cast<uint32_t>(run), 0x6d63u};
  return std::mt19937_64(sequence);
}

std::vector<int> all_parameters() {
  std::vector<int> all(kParameterCount);
  std::iota(all.begin(), all.end(), 0);
  return all;
}

}  // namespace

const char* validation_model_name(ValidationModel model) {
  return model == ValidationModel::Exact ? "exact" : "first-order";
}

ValidationModel parse_validation_model(const std::string& text) {
  if (text == "first-order") return ValidationModel::FirstOrder;
  if (text == "exact") return ValidationModel::Exact;
  throw InputError(
      {"", 0, 0, "--validation-model"},
      fmt::format("unknown validation model '{}': expected first-order or exact", text));
}

MonteCarloSetup prepare_monte_carlo(const TrueRobot& truth, const VirtualInstrument& instrument,
                                    const RobotModel& model, const Tool& tool,
                                    const MonteCarloOptions& options) {
  if (instrument.kind != InstrumentKind::LaserTracker)
    throw InputError({"", 0, 0, "--instrument"}, "the Monte Carlo simulates a laser tracker");
  const Eigen::Vector3d& s = instrument.tracker.sigma_mm;
  if (s.x() != s.y() || s.y() != s.z() || !(s.x() > 0))
    throw InputError({"", 0, 0, "--noise-mm"},
                     "the Monte Carlo needs one positive σ for every axis");
  for (const auto& [flag, count] : {std::pair{"--runs", options.runs},
                                    {"--poses", options.poses},
                                    {"--validation", options.validation},
                                    {"--threads", options.threads}})
    if (count < 1)
      throw InputError({"", 0, 0, flag}, fmt::format("expected at least 1, found {}", count));
  MonteCarloSetup setup;
  setup.truth = truth;
  setup.instrument = instrument;
  setup.sigma_mm = s.x();
  std::mt19937_64 plan_rng(options.seed), validation_rng(options.seed + 2);
  RandomConfigurationOptions random_options;
  random_options.box = published_joint_box(model);
  random_options.name_prefix = "C";
  setup.plan =
      options.optimal_plan
          ? plan_calibration(truth, instrument, model, tool, options.level, options.poses,
                             options.candidates, plan_rng)
          : random_configurations(truth, instrument, options.poses, plan_rng, random_options);
  VirtualInstrument exact = instrument;
  exact.tracker.sigma_mm.setZero();
  std::mt19937_64 unused(0);
  setup.template_set = simulate_measurements(truth, exact, setup.plan, unused).measurements;
  for (const PointMeasurement& m : setup.template_set.points)
    setup.true_positions.push_back(m.position_mm);

  IdentifyOptions identify;
  identify.level = options.level;
  identify.seed = options.seed;
  setup.identification = prepare_identification(model, tool, setup.template_set, identify);

  // Validation: Jacobian at the truth, plus the model-error bias p(q; x_true, model's masses)
  // − p_true(q), zero for a model-complete truth; kept in the Jacobian's last column block.
  random_options.name_prefix = "V";
  const std::vector<PlannedConfiguration> validation =
      random_configurations(truth, instrument, options.validation, validation_rng, random_options);
  std::vector<Vector6d> joints;
  std::vector<Eigen::Vector3d> targets;
  for (const PlannedConfiguration& c : validation) {
    joints.push_back(c.joints);
    targets.push_back(tool.targets[static_cast<size_t>(c.target)].position_mm);
  }
  const ParameterVector& x_true = truth.robot.params;
  setup.validation_jacobian = Eigen::MatrixXd(3 * joints.size(), kParameterCount + 1);
  setup.validation_jacobian.leftCols(kParameterCount) =
      position_jacobian(model, tool.payload, x_true, all_parameters(), joints, targets);
  for (size_t v = 0; v < joints.size(); ++v) {
    const Eigen::Vector3d modelled =
        flange_pose(model, tool.payload, x_true, joints[v]) * targets[v];
    const Eigen::Vector3d real = true_flange_pose(truth, joints[v]) * targets[v];
    setup.validation_jacobian.block<3, 1>(static_cast<Eigen::Index>(3 * v), kParameterCount) =
        modelled - real;
    setup.validation_configurations.push_back(prepare_configuration(model, x_true, joints[v]));
    setup.validation_true_positions.push_back(real);
  }
  setup.validation_targets = targets;

  // Cramér–Rao: the covariance of the fitted parameters from the design at the truth.
  std::vector<int> free_parameters;
  for (const int u : setup.identification.free)
    if (u < kParameterCount) free_parameters.push_back(u);
  std::vector<Vector6d> cal_joints;
  std::vector<Eigen::Vector3d> cal_targets;
  for (const PointMeasurement& m : setup.template_set.points) {
    cal_joints.push_back(m.joints);
    cal_targets.push_back(tool.targets[static_cast<size_t>(m.target)].position_mm);
  }
  const Eigen::MatrixXd J =
      position_jacobian(model, tool.payload, x_true, free_parameters, cal_joints, cal_targets);
  setup.predicted =
      predict_position_error(model, tool.payload, x_true, free_parameters,
                             design_covariance(J, setup.sigma_mm), joints, targets, setup.sigma_mm);
  return setup;
}

ParameterVector monte_carlo_fit(const MonteCarloSetup& setup, uint64_t seed, int run) {
  std::mt19937_64 rng = run_generator(seed, run);
  std::normal_distribution<double> noise(0.0, setup.sigma_mm);
  MeasurementSet data = setup.template_set;
  for (size_t i = 0; i < data.points.size(); ++i)
    for (int k = 0; k < 3; ++k)
      data.points[i].position_mm[k] = setup.true_positions[i][k] + noise(rng);
  const FitResult fit = fit_unknowns(setup.identification, data);
  return fit.status.converged ? ParameterVector(fit.unknowns.head<kParameterCount>())
                              : ParameterVector::Constant(std::numeric_limits<double>::quiet_NaN());
}

MonteCarloRun validate_monte_carlo_run(const MonteCarloSetup& setup, const ParameterVector& fitted,
                                       ValidationModel model) {
  MonteCarloRun run;
  run.converged = true;
  const size_t count = setup.validation_true_positions.size();
  Eigen::Matrix3Xd errors(3, static_cast<Eigen::Index>(count));
  if (model == ValidationModel::FirstOrder) {
    Eigen::VectorXd delta(kParameterCount + 1);
    delta.head<kParameterCount>() = fitted - setup.truth.robot.params;
    delta[kParameterCount] = 1.0;  // the model-error bias column
    Eigen::Map<Eigen::VectorXd>(errors.data(), errors.size()).noalias() =
        setup.validation_jacobian * delta;
  } else {
    const RobotModel& robot = setup.identification.model;
    const PointMass& payload = setup.identification.tool.payload;
    const ParameterTrig trig = parameter_trig(fitted);
    for (size_t v = 0; v < count; ++v) {
      const FlangeRegressor chain(robot, payload, fitted, trig, setup.validation_configurations[v]);
      errors.col(static_cast<Eigen::Index>(v)) =
          chain.flange() * setup.validation_targets[v] - setup.validation_true_positions[v];
    }
  }
  double sum_sq = 0, sum = 0;
  for (Eigen::Index v = 0; v < errors.cols(); ++v) {
    const double n = errors.col(v).norm();
    sum_sq += n * n;
    sum += n;
    run.max_mm = std::max(run.max_mm, n);
  }
  run.rms_mm = std::sqrt(sum_sq / static_cast<double>(count));
  run.mean_mm = sum / static_cast<double>(count);
  return run;
}

MonteCarloResult run_monte_carlo(const MonteCarloSetup& setup, const MonteCarloOptions& options) {
  MonteCarloResult result;
  result.runs.resize(static_cast<size_t>(options.runs));
  Progress progress("Monte Carlo runs", options.runs);
  auto work = [&](int first, int stride) {
    for (int r = first; r < options.runs; r += stride) {
      const ParameterVector fitted = monte_carlo_fit(setup, options.seed, r);
      if (fitted.allFinite())
        result.runs[static_cast<size_t>(r)] =
            validate_monte_carlo_run(setup, fitted, options.validation_model);
      progress.advance();
    }
  };
  const int threads = std::min(options.threads, options.runs);
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t, threads);
  work(0, threads);
  for (std::thread& thread : pool) thread.join();

  // Aggregated in run order: the same sums whatever the threads.
  double sum_sq = 0, sum = 0;
  int good = 0;
  for (const MonteCarloRun& run : result.runs) {
    if (!run.converged) {
      ++result.failed;
      continue;
    }
    sum_sq += run.rms_mm * run.rms_mm;
    sum += run.mean_mm;
    ++good;
  }
  if (good > 0) {
    result.observed_rms_mm = std::sqrt(sum_sq / good);
    result.observed_mean_mm = sum / good;
    result.ratio = result.observed_rms_mm / setup.predicted.rms_mm;
  }
  return result;
}

}  // namespace robcal
