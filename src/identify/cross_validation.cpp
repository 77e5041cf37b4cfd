#include "robcal/identify/cross_validation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <random>

#include "robcal/core/error.hpp"
#include "robcal/core/progress.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal {
namespace {

const std::string& config_of(const MeasurementSet& data, size_t row) {
  return data.kind == MeasurementKind::Points  ? data.points[row].config
         : data.kind == MeasurementKind::Poses ? data.poses[row].config
                                               : data.distances[row].config;
}

/// Mean, sample standard deviation and maximum.
FoldErrors statistics(const std::vector<double>& errors) {
  FoldErrors out;
  out.rows = static_cast<int>(errors.size());
  const double n = static_cast<double>(errors.size());
  for (double e : errors) {
    out.mean_mm += e / n;
    out.max_mm = std::max(out.max_mm, e);
  }
  for (double e : errors) out.std_mm += (e - out.mean_mm) * (e - out.mean_mm);
  out.std_mm = std::sqrt(out.std_mm / std::max(1.0, n - 1));
  return out;
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

namespace {

/// Every configuration's fold (0-based, `folds` of them) → held-out errors and their statistics.
CrossValidation run_folds(const RobotModel& model, const Tool& tool, const MeasurementSet& data,
                          const IdentifyOptions& options, int folds,
                          const std::vector<int>& row_fold) {
  CrossValidation out;
  out.folds = folds;
  out.errors_mm.assign(data.size(), 0.0);
  const int k = data.residuals_per_row();
  Progress progress("cross-validation folds", folds);
  for (int fold = 0; fold < folds; ++fold) {
    std::vector<bool> train(data.size());
    for (size_t row = 0; row < data.size(); ++row) train[row] = row_fold[row] != fold;
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
    std::vector<double> errors;
    for (size_t row = 0; row < data.size(); ++row) {
      if (!train[row]) continue;
      row_residuals(context, fit.unknowns, h++, r.data(), nullptr);
      out.errors_mm[row] = k == 1 ? std::abs(r[0]) : r.head<3>().norm();
      errors.push_back(out.errors_mm[row]);
    }
    out.per_fold.push_back(statistics(errors));
    progress.advance();
  }
  const FoldErrors pooled = statistics(out.errors_mm);
  out.mean_mm = pooled.mean_mm;
  out.std_mm = pooled.std_mm;
  out.max_mm = pooled.max_mm;
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

  std::vector<int> row_fold(data.size());
  for (size_t row = 0; row < data.size(); ++row) row_fold[row] = config_fold[row_config[row]];
  CrossValidation out = run_folds(model, tool, data, options, folds, row_fold);
  out.seed = seed;
  return out;
}

CrossValidation cross_validate(const RobotModel& model, const Tool& tool,
                               const MeasurementSet& data, const IdentifyOptions& options,
                               const std::map<std::string, int>& config_fold) {
  std::vector<int> row_fold(data.size());
  int folds = 0;
  for (const auto& [config, fold] : config_fold) folds = std::max(folds, fold);
  std::vector<bool> used(static_cast<size_t>(folds), false);
  for (size_t row = 0; row < data.size(); ++row) {
    const auto it = config_fold.find(config_of(data, row));
    if (it == config_fold.end())
      throw InputError({"", 0, 0, "--folds"},
                       fmt::format("configuration '{}' of {} has no fold in the folds file",
                                   config_of(data, row), data.file));
    row_fold[row] = it->second - 1;
    used[static_cast<size_t>(it->second - 1)] = true;
  }
  for (int fold = 0; fold < folds; ++fold)
    if (!used[static_cast<size_t>(fold)])
      throw InputError({"", 0, 0, "--folds"},
                       fmt::format("fold {} has no configuration of {}: number the folds 1..K",
                                   fold + 1, data.file));
  if (folds < 2) throw InputError({"", 0, 0, "--folds"}, "the folds file gives fewer than 2 folds");
  CrossValidation out = run_folds(model, tool, data, options, folds, row_fold);
  out.user_folds = true;
  return out;
}

std::map<std::string, int> read_folds_csv(const std::string& path) {
  const std::string text = read_text_file(path);
  std::map<std::string, int> out;
  int line_number = 0;
  bool header = true;
  size_t start = 0;
  while (start < text.size()) {
    const size_t newline = std::min(text.find('\n', start), text.size());
    std::string line = text.substr(start, newline - start);
    start = newline + 1;
    ++line_number;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty() || line.front() == '#') continue;
    if (header) {
      if (line != "config,fold")
        throw InputError({path, line_number, 1, ""},
                         fmt::format("header '{}': expected 'config,fold'", line));
      header = false;
      continue;
    }
    const size_t comma = line.find(',');
    const std::string fold_text = comma == std::string::npos ? "" : line.substr(comma + 1);
    int fold = 0;
    const auto [end, ec] =
        std::from_chars(fold_text.data(), fold_text.data() + fold_text.size(), fold);
    if (comma == std::string::npos || ec != std::errc() ||
        end != fold_text.data() + fold_text.size() || fold < 1)
      throw InputError(
          {path, line_number, static_cast<int>(comma == std::string::npos ? 1 : comma + 2), "fold"},
          fmt::format("'{}': expected config,fold with fold an integer ≥ 1", line));
    out[line.substr(0, comma)] = fold;
  }
  if (out.empty()) throw InputError({path, 0, 0, ""}, "no folds: expected config,fold rows");
  return out;
}

}  // namespace robcal
