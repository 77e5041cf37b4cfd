#include "robcal/hexapod/placement_search.hpp"

#include <fmt/format.h>

#include <Eigen/SVD>
#include <algorithm>
#include <nlohmann/json.hpp>
#include <numeric>
#include <random>

#include "robcal/core/error.hpp"
#include "robcal/core/rounding.hpp"
#include "robcal/core/units.hpp"
#include "robcal/design/design_matrix.hpp"
#include "robcal/design/observability.hpp"
#include "robcal/design/predicted_accuracy.hpp"
#include "robcal/identify/accuracy_prediction.hpp"

namespace robcal::hexapod {
namespace {

/// What a set of configurations (indices into the design) predicts.
struct Prediction {
  int undetermined = 0;
  double o1 = 0, mean_mm = 0, max_mm = 0;
};

struct Context {
  const RobotModel& model;
  const DesignMatrix& design;
  int asked = 0;
  double sigma_mm = 0;
  std::vector<Vector6d> validation;
  Eigen::Vector3d tcp_flange;
};

Prediction predict(const Context& c, const std::vector<int>& subset) {
  Prediction p;
  if (subset.empty()) {
    p.undetermined = c.asked;
    return p;
  }
  // Columns are RMS-scaled over all candidates (design_matrix.hpp): a relative rank threshold.
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(c.design.stacked(subset));
  const Eigen::VectorXd& s = svd.singularValues();
  int rank = 0;
  for (Eigen::Index i = 0; i < s.size(); ++i) rank += s[i] > 1e-9 * s[0];
  p.undetermined = c.asked - rank;
  if (p.undetermined > 0) return p;
  p.o1 = observability_from_singular_values(s, static_cast<int>(subset.size())).O1;
  const Eigen::MatrixXd cov = design_parameter_covariance(c.design, subset, c.sigma_mm);
  const PredictedAccuracy a =
      predict_position_error(c.model, PointMass{}, c.model.nominal(), c.design.parameters, cov,
                             c.validation, {c.tcp_flange}, c.sigma_mm);
  p.mean_mm = a.mean_mm;
  p.max_mm = a.max_mm;
  return p;
}

void check_axis(const std::vector<double>& axis, const char* name) {
  if (axis.empty())
    throw InputError({"", 0, 0, name}, "expected at least one value for the placement grid");
  for (double v : axis)
    if (!std::isfinite(v)) throw InputError({"", 0, 0, name}, "expected finite values");
}

}  // namespace

PlacementSearchResult search_placements(const RobotModel& model,
                                        const PlacementSearchRequest& request) {
  const HexapodPlanRequest& base = request.plan;
  check_axis(request.x_mm, "--x-mm");
  check_axis(request.y_mm, "--y-mm");
  check_axis(request.z_mm, "--z-mm");
  check_axis(request.yaw_deg, "--yaw-deg");
  check_axis(request.tilt_deg, "--tilt-deg");
  const size_t grid = request.x_mm.size() * request.y_mm.size() * request.z_mm.size() *
                      request.yaw_deg.size() * request.tilt_deg.size();
  if (grid > 2000)
    throw InputError({"", 0, 0, "placement grid"},
                     fmt::format("{} placements: expected at most 2000", grid));
  if (!(request.pose_sigma_multiple > 0) || request.validation_configurations < 2 ||
      request.pair_candidates < 0)
    throw InputError({"", 0, 0, "placement search"},
                     "expected a positive σ multiple, at least 2 validation configurations and a "
                     "non-negative number of pair candidates");
  fixture_cups(base.geometry.base, "--base-mm");
  fixture_cups(base.geometry.tool, "--tool-mm");
  check_gauge(base.gauge, "--gauge-range-mm", "--gauge-sigma-mm");
  std::string why_not;
  if (!analyze_ortho_parallel(model, &why_not))
    throw InputError({"", 0, 0, "robot"},
                     model.name + " has no closed-form inverse kinematics: " + why_not);

  // Plan every placement; keep each one's configurations as design candidates.
  std::vector<PlacementScore> scores;
  std::vector<std::vector<int>> members;
  std::vector<Candidate> candidates;
  Pose<double> flange_T_tool;
  for (double x : request.x_mm)
    for (double y : request.y_mm)
      for (double z : request.z_mm)
        for (double yaw : request.yaw_deg)
          for (double tilt : request.tilt_deg) {
            PlacementScore s;
            s.placement = {x, y, z, yaw};
            s.tilt_deg = tilt;
            HexapodPlanRequest r = base;
            r.placement = s.placement;
            r.tilt_deg = tilt;
            std::vector<int> mine;
            try {
              const HexapodPlan plan = plan_hexapod(model, r);
              flange_T_tool = *plan.session.flange_T_tool;
              s.poses_measurable = plan.outcome->poses_measurable;
              for (const SessionConfiguration& c : plan.session.configurations) {
                Candidate candidate;
                for (int j = 0; j < kJointCount; ++j)
                  candidate.joints[j] = deg2rad(c.joints_deg[j]);
                candidate.target = -1;
                mine.push_back(static_cast<int>(candidates.size()));
                candidates.push_back(candidate);
              }
            } catch (const InputError& e) {  // this placement only: a fixture in a keep-out box
              s.refused = e.what();
            }
            s.configurations = static_cast<int>(mine.size());
            scores.push_back(s);
            members.push_back(std::move(mine));
          }

  PlacementSearchResult result;
  result.parameters = static_cast<int>(level_parameters(request.level).size());
  result.pose_sigma_mm = request.pose_sigma_multiple * base.gauge.sigma_mm;
  if (candidates.empty()) {
    result.ranked = scores;
    for (PlacementScore& s : result.ranked) s.undetermined = result.parameters;
    return result;
  }
  Tool tool;
  tool.flange_T_tcp.linear() = flange_T_tool.R;
  tool.flange_T_tcp.translation() = flange_T_tool.p;
  tool.tcp_given = true;
  DesignSettings settings;
  settings.kind = MeasurementKind::Poses;
  settings.parameters = level_parameters(request.level);
  const DesignMatrix design = build_design_matrix(model, tool, candidates, settings);
  result.identified_parameters = design.parameters;
  Context context{model, design, design.columns(), result.pose_sigma_mm, {}, flange_T_tool.p};
  std::mt19937_64 rng(request.seed);
  Vector6d lower, upper;
  for (int j = 0; j < kJointCount; ++j) {
    lower[j] = model.limits[j].lower;
    upper[j] = model.limits[j].upper;
  }
  context.validation = sample_configurations(lower, upper, request.validation_configurations, rng);

  for (size_t i = 0; i < scores.size(); ++i) {
    const Prediction p = predict(context, members[i]);
    scores[i].undetermined = p.undetermined;
    scores[i].observability_o1 = p.o1;
    scores[i].predicted_mean_mm = p.mean_mm;
    scores[i].predicted_max_mm = p.max_mm;
  }
  std::vector<size_t> order(scores.size());
  std::iota(order.begin(), order.end(), 0);
  const auto key = [&](size_t i) {
    const PlacementScore& s = scores[i];
    return std::tuple(!s.usable(), s.undetermined, s.predicted_mean_mm);
  };
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return key(a) < key(b); });
  std::vector<std::vector<int>> ranked_members;
  for (size_t i : order) {
    result.ranked.push_back(scores[i]);
    ranked_members.push_back(members[i]);
  }

  // Pairs of the best fully determined placements.
  int eligible = 0;
  while (eligible < static_cast<int>(result.ranked.size()) && eligible < request.pair_candidates &&
         result.ranked[eligible].usable() && result.ranked[eligible].undetermined == 0)
    ++eligible;
  for (int a = 0; a < eligible; ++a)
    for (int b = a + 1; b < eligible; ++b) {
      std::vector<int> both = ranked_members[a];
      both.insert(both.end(), ranked_members[b].begin(), ranked_members[b].end());
      std::vector<int> half;
      for (const std::vector<int>* m : {&ranked_members[a], &ranked_members[b]})
        for (size_t k = 0; k < m->size(); k += 2) half.push_back((*m)[k]);
      const Prediction all = predict(context, both);
      const Prediction equal = predict(context, half);
      PlacementPair pair;
      pair.first = a;
      pair.second = b;
      pair.configurations = static_cast<int>(both.size());
      pair.undetermined = all.undetermined;
      pair.observability_o1 = all.o1;
      pair.predicted_mean_mm = all.mean_mm;
      pair.predicted_max_mm = all.max_mm;
      pair.equal_count_configurations = static_cast<int>(half.size());
      pair.equal_count_undetermined = equal.undetermined;
      pair.equal_count_mean_mm = equal.mean_mm;
      result.pairs.push_back(pair);
    }
  std::stable_sort(result.pairs.begin(), result.pairs.end(),
                   [](const PlacementPair& a, const PlacementPair& b) {
                     return a.predicted_mean_mm < b.predicted_mean_mm;
                   });
  return result;
}

nlohmann::json placement_search_json(const PlacementSearchResult& r, int best) {
  using nlohmann::json;
  json out{{"parameters", r.parameters},
           {"identified_parameters", r.identified_parameters.size()},
           {"pose_sigma_mm", rounded(r.pose_sigma_mm, 9)},
           {"placements_searched", r.ranked.size()}};
  out["ranked"] = json::array();
  for (int i = 0; i < best && i < static_cast<int>(r.ranked.size()); ++i) {
    const PlacementScore& s = r.ranked[i];
    json entry{{"rank", i + 1},
               {"placement", placement_text(s.placement)},
               {"tilt_deg", s.tilt_deg},
               {"poses_measurable", s.poses_measurable},
               {"configurations", s.configurations},
               {"undetermined", s.undetermined},
               {"observability_o1", rounded(s.observability_o1, 6)},
               {"predicted_mean_mm", rounded(s.predicted_mean_mm, 9)},
               {"predicted_max_mm", rounded(s.predicted_max_mm, 9)}};
    if (!s.refused.empty()) entry["refused"] = s.refused;
    out["ranked"].push_back(entry);
  }
  out["pairs"] = json::array();
  for (int i = 0; i < best && i < static_cast<int>(r.pairs.size()); ++i) {
    const PlacementPair& p = r.pairs[i];
    out["pairs"].push_back({{"ranks", {p.first + 1, p.second + 1}},
                            {"configurations", p.configurations},
                            {"undetermined", p.undetermined},
                            {"observability_o1", rounded(p.observability_o1, 6)},
                            {"predicted_mean_mm", rounded(p.predicted_mean_mm, 9)},
                            {"predicted_max_mm", rounded(p.predicted_max_mm, 9)},
                            {"equal_count_configurations", p.equal_count_configurations},
                            {"equal_count_undetermined", p.equal_count_undetermined},
                            {"equal_count_mean_mm", rounded(p.equal_count_mean_mm, 9)}});
  }
  return out;
}

}  // namespace robcal::hexapod
