#include "robcal/identify/cross_validation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <random>

#include "robcal/core/error.hpp"
#include "robcal/core/progress.hpp"

namespace robcal {
namespace {

const std::string& config_of(const MeasurementSet& data, size_t row) {
  return data.kind == MeasurementKind::Points  ? data.points[row].config
         : data.kind == MeasurementKind::Poses ? data.poses[row].config
                                               : data.distances[row].config;
}

/// The rows whose `keep` flag is set.
MeasurementSet subset(const MeasurementSet& data, const std::vector<bool>& keep) {
  MeasurementSet out;
  out.kind = data.kind;
  out.file = data.file;
  for (size_t row = 0; row < data.size(); ++row) {
    if (!keep[row]) continue;
    if (data.kind == MeasurementKind::Points) out.points.push_back(data.points[row]);
    if (data.kind == MeasurementKind::Poses) out.poses.push_back(data.poses[row]);
    if (data.kind == MeasurementKind::Distances) out.distances.push_back(data.distances[row]);
  }
  return out;
}

}  // namespace

CrossValidation cross_validate(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const IdentifyOptions& options,
                               int folds, uint64_t seed) {
  std::vector<std::string> configs;
  std::map<std::string, size_t> config_index;
  std::vector<size_t> row_config(data.size());
  for (size_t row = 0; row < data.size(); ++row) {
    const auto [it, inserted] = config_index.emplace(config_of(data, row), configs.size());
    if (inserted) configs.push_back(it->first);
    row_config[row] = it->second;
  }
  if (folds < 2 || folds > static_cast<int>(configs.size()))
    throw InputError(
        {"", 0, 0, "--kfold"},
        fmt::format("K must be between 2 and the number of configurations ({}), got {}",
                    configs.size(), folds));
  std::vector<size_t> order(configs.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::mt19937_64 rng(seed);
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<int> config_fold(configs.size());
  for (size_t i = 0; i < order.size(); ++i) config_fold[order[i]] = static_cast<int>(i) % folds;

  CrossValidation out;
  out.folds = folds;
  out.seed = seed;
  out.errors_mm.assign(data.size(), 0.0);
  const int k = data.residuals_per_row();
  Progress progress("cross-validation folds", folds);
  for (int fold = 0; fold < folds; ++fold) {
    std::vector<bool> train(data.size());
    for (size_t row = 0; row < data.size(); ++row)
      train[row] = config_fold[row_config[row]] != fold;
    const MeasurementSet training = subset(data, train);
    for (auto&& t : train) t = !t;
    const MeasurementSet held_out = subset(data, train);
    FitResult fit;
    IdentificationSetup setup;
    try {
      setup = prepare_identification(model, tool, training, options);
      fit = fit_unknowns(setup, training);
    } catch (const InputError& e) {
      throw InputError(
          e.where(), fmt::format("cross-validation fold {} of {}: {}", fold + 1, folds, e.what()));
    }
    const ResidualContext context{&setup.model, &setup.tool, &held_out, &setup.layout,
                                  options.orientation_weight_mm};
    Eigen::VectorXd r(k);
    size_t h = 0;
    for (size_t row = 0; row < data.size(); ++row) {
      if (!train[row]) continue;
      row_residuals(context, fit.unknowns, h++, r.data(), nullptr);
      out.errors_mm[row] = k == 1 ? std::abs(r[0]) : r.head<3>().norm();
    }
    progress.advance();
  }
  const double n = static_cast<double>(out.errors_mm.size());
  for (double e : out.errors_mm) {
    out.mean_mm += e / n;
    out.max_mm = std::max(out.max_mm, e);
  }
  for (double e : out.errors_mm) out.std_mm += (e - out.mean_mm) * (e - out.mean_mm);
  out.std_mm = std::sqrt(out.std_mm / std::max(1.0, n - 1));
  return out;
}

}  // namespace robcal
