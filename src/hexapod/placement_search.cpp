#include "robcal/hexapod/placement_search.hpp"

#include <fmt/format.h>

#include <Eigen/SVD>
#include <algorithm>
#include <limits>
#include <nlohmann/json.hpp>
#include <numeric>
#include <random>
#include <tuple>

#include "robcal/core/error.hpp"
#include "robcal/core/rounding.hpp"
#include "robcal/core/units.hpp"
#include "robcal/design/design_matrix.hpp"
#include "robcal/design/observability.hpp"
#include "robcal/design/predicted_accuracy.hpp"
#include "robcal/design/task_selection.hpp"
#include "robcal/hexapod/four_cup_kinematics.hpp"
#include "robcal/identify/accuracy_prediction.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/parameter_jacobian.hpp"

namespace robcal::hexapod {
namespace {

/// What a set of configurations (indices into the design) predicts.
struct Prediction {
  int undetermined = 0;
  double o1 = 0, mean_mm = 0, max_mm = 0;
};

struct Context {
  const RobotModel& model;
  DesignMatrix design;
  int asked = 0;
  double sigma_mm = 0;
  std::vector<Vector6d> validation;
  Eigen::Vector3d tcp_flange;
  double lever_mm = 100;                ///< the design's orientation rows × this
  std::vector<Eigen::Vector3d> tcp_mm;  ///< per candidate, nominal TCP in the robot frame
};

/// Rows of one pose candidate for the six world-frame unknowns of its placement
/// (docs/method/08-world-frame.md §4): the measured pose is exp(ξ)·robot_T_fixture·fixture_T_tool
/// with ξ = (v, ω) in the robot frame, so the residual r = model − measured moves by
/// ∂r_p/∂(v, ω) = (−I, [p]×) and ∂r_R/∂ω = −w·I (position p, orientation weight w).
Eigen::Matrix<double, 6, 6> frame_rows(const Eigen::Vector3d& p, double lever_mm) {
  Eigen::Matrix<double, 6, 6> rows = Eigen::Matrix<double, 6, 6>::Zero();
  rows.topLeftCorner<3, 3>() = -Eigen::Matrix3d::Identity();
  rows.topRightCorner<3, 3>() << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0;
  rows.bottomRightCorner<3, 3>() = -lever_mm * Eigen::Matrix3d::Identity();
  return rows;
}

/// The unscaled pose Jacobian of candidates grouped by placement: the model's columns, then six
/// world-frame columns for every placement after the first (whose frame the base parameters
/// carry).
Eigen::MatrixXd placements_jacobian(const Context& c, const std::vector<std::vector<int>>& groups) {
  std::vector<int> all;
  for (const std::vector<int>& g : groups) all.insert(all.end(), g.begin(), g.end());
  const int m = c.design.columns();
  const Eigen::Index frames = 6 * static_cast<Eigen::Index>(groups.size() - 1);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(all.size()) * 6, m + frames);
  J.leftCols(m) = c.design.stacked(all) * c.design.column_scale.cwiseInverse().asDiagonal();
  Eigen::Index row = 0;
  for (size_t g = 0; g < groups.size(); ++g)
    for (int k : groups[g]) {
      if (g > 0)
        J.block<6, 6>(row, m + 6 * static_cast<Eigen::Index>(g - 1)) =
            frame_rows(c.tcp_mm[k], c.lever_mm);
      row += 6;
    }
  return J;
}

/// Column scales of a placements Jacobian: the design's for the model's columns (RMS over every
/// candidate, so O1 compares across subsets), 1/RMS per configuration for the frames' (over the
/// configurations of their placement in J).
Eigen::VectorXd column_scales(const Context& c, const Eigen::MatrixXd& J,
                              const std::vector<std::vector<int>>& groups) {
  Eigen::VectorXd scale(J.cols());
  const int m = c.design.columns();
  scale.head(m) = c.design.column_scale;
  for (Eigen::Index k = m; k < J.cols(); ++k) {
    const double n = static_cast<double>(groups[1 + (k - m) / 6].size());
    scale[k] = std::sqrt(n) / std::max(J.col(k).norm(), 1e-300);
  }
  return scale;
}

Prediction predict(const Context& c, const std::vector<std::vector<int>>& groups) {
  Prediction p;
  std::vector<std::vector<int>> used;
  for (const std::vector<int>& g : groups)
    if (!g.empty()) used.push_back(g);
  if (used.empty()) {
    p.undetermined = c.asked;
    return p;
  }
  const Eigen::MatrixXd J = placements_jacobian(c, used);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J * column_scales(c, J, used).asDiagonal());
  const Eigen::VectorXd& s = svd.singularValues();
  int rank = 0;
  for (Eigen::Index i = 0; i < s.size(); ++i) rank += s[i] > 1e-9 * s[0];
  p.undetermined = static_cast<int>(J.cols()) - rank;
  if (p.undetermined > 0) return p;
  p.o1 = observability_from_singular_values(s, static_cast<int>(J.rows() / 6)).O1;
  // The model block of the covariance of all unknowns: the frames' uncertainty is marginalised.
  const Eigen::MatrixXd cov = design_covariance(J, c.sigma_mm).topLeftCorner(c.asked, c.asked);
  const PredictedAccuracy a =
      predict_position_error(c.model, PointMass{}, c.model.nominal(), c.design.parameters, cov,
                             c.validation, {c.tcp_flange}, c.sigma_mm);
  p.mean_mm = a.mean_mm;
  p.max_mm = a.max_mm;
  return p;
}

/// The model parameters every prediction is made for: the level's and the opt-in groups'.
std::vector<int> searched_parameters(const RobotModel& model,
                                     const PlacementSearchRequest& request) {
  return identified_model_parameters(model, Tool{}, MeasurementKind::Poses, request.level,
                                     request.identify);
}

/// σ of one pose row: the request's multiple of the gauge σ (§4's worst case of three tool
/// cups); with a fourth cup on either fixture, scaled by how much its legs lower the worst tool-cup
/// GUM uncertainty over the poses planned with it (docs/method/07-hexapod.md §7).
double pose_sigma_mm(const PlacementSearchRequest& request) {
  const HexapodPlanRequest& plan = request.plan;
  double multiple = request.pose_sigma_multiple;
  if (plan.geometry.tool_cup4_mm || plan.geometry.base_cup4_mm) {
    const WorstToolCupUncertainty worst =
        worst_tool_cup_uncertainty(plannable_poses(plan.geometry, plan.gauge.range_mm,
                                                   plan.angle_deg, plan.distance_mm, plan.cups)
                                       .kept,
                                   plan.geometry);
    multiple *= worst.all_legs / worst.design_legs;
  }
  return multiple * plan.gauge.sigma_mm;
}

/// The design over `candidates` (pose rows of the tool fixture mounted at `flange_T_tool`) and the
/// validation configurations of the request.
Context make_context(const RobotModel& model, const Pose<double>& flange_T_tool,
                     const std::vector<Candidate>& candidates,
                     const PlacementSearchRequest& request, double sigma_mm) {
  Tool tool;
  tool.flange_T_tcp.linear() = flange_T_tool.R;
  tool.flange_T_tcp.translation() = flange_T_tool.p;
  tool.tcp_given = true;
  DesignSettings settings;
  settings.kind = MeasurementKind::Poses;
  settings.parameters = searched_parameters(model, request);
  Context c{model,
            build_design_matrix(model, tool, candidates, settings),
            0,
            sigma_mm,
            {},
            flange_T_tool.p,
            settings.orientation_lever_mm,
            {}};
  c.asked = c.design.columns();
  for (const Candidate& k : candidates)
    c.tcp_mm.push_back(flange_pose(model, PointMass{}, model.nominal(), k.joints) *
                       flange_T_tool.p);
  std::mt19937_64 rng(request.seed);
  if (request.task_box) {
    c.validation = task_box_configurations(model, tool, model.nominal(), unconstrained_joints(),
                                           *request.task_box, request.validation_configurations,
                                           rng, "--task-box");
    return c;
  }
  Vector6d lower, upper;
  for (int j = 0; j < kJointCount; ++j) {
    lower[j] = model.limits[j].lower;
    upper[j] = model.limits[j].upper;
  }
  c.validation = sample_configurations(lower, upper, request.validation_configurations, rng);
  return c;
}

/// The setting points of a plan's base cups: B1..B3, then B4 if any.
std::vector<Eigen::Vector3d> plan_setting_points(const HexapodPlan& plan) {
  std::vector<Eigen::Vector3d> points(plan.session.setting_points->begin(),
                                      plan.session.setting_points->end());
  if (plan.session.setting_point4) points.push_back(*plan.session.setting_point4);
  return points;
}

/// The smallest distance between a cup of one placement and a cup of another, and which cups.

double closest_cups(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                    int* cup_a, int* cup_b) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < static_cast<int>(a.size()); ++i)
    for (int j = 0; j < static_cast<int>(b.size()); ++j)
      if ((a[i] - b[j]).norm() < best) {
        best = (a[i] - b[j]).norm();
        *cup_a = i;
        *cup_b = j;
      }
  return best;
}

void check_axis(const std::vector<double>& axis, const char* name) {
  if (axis.empty())
    throw InputError({"", 0, 0, name}, "expected at least one value for the placement grid");
  for (double v : axis)
    if (!std::isfinite(v)) throw InputError({"", 0, 0, name}, "expected finite values");
}

/// The flags that span the placement grid: the key of a message about the grid as a whole.
constexpr const char* kGridFlags = "--x-mm, --y-mm, --z-mm, --yaw-deg, --tilt-deg";

/// Each placement once and apart: no base cup within `clearance` of another placement's.
void check_apart(const std::vector<MeasuredPlacement>& placements, double clearance,
                 const char* key) {
  for (size_t i = 0; i < placements.size(); ++i)
    for (size_t j = 0; j < i; ++j) {
      int a = 0, b = 0;
      const double gap =
          closest_cups(placements[i].setting_points, placements[j].setting_points, &a, &b);
      if (gap < clearance)
        throw InputError({placements[i].source, 0, 0, key},
                         fmt::format("this placement overlaps the one of {}: its base cup B{} is "
                                     "{:.1f} mm from their B{} (cups stand at least {} mm apart); "
                                     "give each placement once",
                                     placements[j].source, a + 1, gap, b + 1, clearance));
    }
}

/// The task box as [xmin, xmax, ymin, ymax, zmin, zmax] (mm), null for the whole workspace.
nlohmann::json task_box_json(const std::optional<TaskBox>& box) {
  if (!box) return nullptr;
  return {box->min_mm.x(), box->max_mm.x(), box->min_mm.y(),
          box->max_mm.y(), box->min_mm.z(), box->max_mm.z()};
}

}  // namespace

std::string task_region_text(const std::optional<TaskBox>& task_box) {
  if (!task_box) return "random configurations in the joint limits";
  return fmt::format(
      "configurations putting the tool fixture in the task box x {:g}..{:g}, y {:g}..{:g}, z "
      "{:g}..{:g} mm (tool axis down)",
      task_box->min_mm.x(), task_box->max_mm.x(), task_box->min_mm.y(), task_box->max_mm.y(),
      task_box->min_mm.z(), task_box->max_mm.z());
}

MeasuredPlacement measured_placement(const HexapodPlan& plan, const std::string& source) {
  if (!plan.cell || !plan.session.setting_points)
    throw InputError({source, 0, 0, "placement"},
                     "the plan does not say where its base fixture stood: write it with `robcal "
                     "hexapod plan --out`");
  MeasuredPlacement m;
  m.source = source;
  m.placement = plan.cell->placement;
  m.tilt_deg = plan.cell->tilt_deg;
  m.setting_points = plan_setting_points(plan);
  for (size_t c = 0; c < plan.session.configurations.size(); ++c) {
    const SessionConfiguration& config = plan.session.configurations[c];
    if (config.joints_deg.size() != kJointCount)
      throw InputError({source, 0, 0, fmt::format("configurations[{}].joints_deg", c)},
                       "expected the joint values of every configuration");
    Vector6d q;
    for (int j = 0; j < kJointCount; ++j) q[j] = deg2rad(config.joints_deg[j]);
    m.joints.push_back(q);
  }
  return m;
}

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
    throw InputError({"", 0, 0, kGridFlags},
                     fmt::format("{} placements: expected at most 2000", grid));
  if (request.best < 1) throw InputError({"", 0, 0, "--best"}, "expected at least 1");
  if (!(request.pose_sigma_multiple > 0) || request.validation_configurations < 2)
    throw InputError({"", 0, 0, "placement search"},
                     "expected a positive σ multiple and at least 2 validation configurations");
  check_geometry(base.geometry);
  check_gauge(base.gauge, "--gauge-range-mm", "--gauge-sigma-mm");
  check_fixture_range(base.geometry, base.gauge);  // out of range at every placement
  std::string why_not;
  if (!analyze_ortho_parallel(model, &why_not))
    throw InputError({"", 0, 0, "robot"},
                     model.name + " has no closed-form inverse kinematics: " + why_not);

  // The measured placements come first among the design candidates; each once, apart.
  const double clearance = base.cups.cup_diameter_mm;
  std::vector<Candidate> candidates;
  std::vector<std::vector<int>> measured_members;
  check_apart(request.measured, clearance, "--measured");
  for (const MeasuredPlacement& m : request.measured) {
    std::vector<int> mine;
    for (const Vector6d& q : m.joints) {
      mine.push_back(static_cast<int>(candidates.size()));
      candidates.push_back({q, -1});
    }
    measured_members.push_back(std::move(mine));
  }

  // Plan every placement; keep each one's configurations as design candidates.
  std::vector<PlacementScore> scores;
  std::vector<std::vector<int>> members;
  std::vector<std::vector<Eigen::Vector3d>> setting_points;
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
              const HexapodPlan plan = plan_hexapod(model, r);  // refuses unplaceable cups
              flange_T_tool = *plan.session.flange_T_tool;
              setting_points.resize(scores.size() + 1);
              setting_points.back() = plan_setting_points(plan);
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

  setting_points.resize(scores.size());
  PlacementSearchResult result;
  result.best = request.best;
  result.level = request.level;
  result.identify = request.identify;
  result.task_box = request.task_box;
  result.parameters = static_cast<int>(searched_parameters(model, request).size());
  result.pose_sigma_mm = pose_sigma_mm(request);
  if (std::none_of(scores.begin(), scores.end(),
                   [](const PlacementScore& s) { return s.usable(); }))
    throw InputError(
        {"", 0, 0, kGridFlags},
        fmt::format("none of the {} placements has a configuration to measure (every pose "
                    "unreachable, colliding, or its cups out of the gauge's ±{} mm about "
                    "{} mm){}: move the grid or change the fixtures",
                    scores.size(), base.gauge.range_mm, base.geometry.leg_mm,
                    scores.front().refused.empty() ? "" : "; first: " + scores.front().refused));
  const Context context =
      make_context(model, flange_T_tool, candidates, request, result.pose_sigma_mm);
  result.identified_parameters = context.design.parameters;

  for (size_t i = 0; i < scores.size(); ++i) {
    const Prediction p = predict(context, {members[i]});
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
  std::vector<std::vector<Eigen::Vector3d>> ranked_points;
  for (size_t i : order) {
    result.ranked.push_back(scores[i]);
    ranked_members.push_back(members[i]);
    ranked_points.push_back(setting_points[i]);
  }

  // The next placement after the measured ones: each usable grid placement apart from them.
  if (!request.measured.empty()) {
    const Prediction alone = predict(context, measured_members);
    result.measured_undetermined = alone.undetermined;
    result.measured_mean_mm = alone.mean_mm;
    result.measured_max_mm = alone.max_mm;
    for (const std::vector<int>& m : measured_members)
      result.measured_configurations += static_cast<int>(m.size());
    for (size_t i = 0; i < result.ranked.size(); ++i) {
      if (!result.ranked[i].usable()) continue;
      int a = 0, b = 0;
      const bool apart = std::all_of(
          request.measured.begin(), request.measured.end(), [&](const MeasuredPlacement& m) {
            return closest_cups(ranked_points[i], m.setting_points, &a, &b) >= clearance;
          });
      if (!apart) continue;
      std::vector<std::vector<int>> groups = measured_members;
      groups.push_back(ranked_members[i]);
      const Prediction p = predict(context, groups);
      NextPlacement next;
      next.rank = static_cast<int>(i);
      next.configurations = result.measured_configurations + result.ranked[i].configurations;
      next.undetermined = p.undetermined;
      next.predicted_mean_mm = p.mean_mm;
      next.predicted_max_mm = p.max_mm;
      result.next.push_back(next);
    }
    std::stable_sort(result.next.begin(), result.next.end(),
                     [](const NextPlacement& a, const NextPlacement& b) {
                       return std::tuple(a.undetermined, a.predicted_mean_mm) <
                              std::tuple(b.undetermined, b.predicted_mean_mm);
                     });
  }

  // Pairs of the best fully determined placements.
  const int pair_candidates = std::max(request.best, 2);
  int eligible = 0;
  while (eligible < static_cast<int>(result.ranked.size()) && eligible < pair_candidates &&
         result.ranked[eligible].usable() && result.ranked[eligible].undetermined == 0)
    ++eligible;
  for (int a = 0; a < eligible; ++a)
    for (int b = a + 1; b < eligible; ++b) {
      std::vector<std::vector<int>> half(2);
      for (int g = 0; g < 2; ++g) {
        const std::vector<int>& m = ranked_members[g == 0 ? a : b];
        for (size_t k = 0; k < m.size(); k += 2) half[g].push_back(m[k]);
      }
      const Prediction all = predict(context, {ranked_members[a], ranked_members[b]});
      const Prediction equal = predict(context, half);
      PlacementPair pair;
      pair.first = a;
      pair.second = b;
      pair.configurations = static_cast<int>(ranked_members[a].size() + ranked_members[b].size());
      pair.undetermined = all.undetermined;
      pair.observability_o1 = all.o1;
      pair.predicted_mean_mm = all.mean_mm;
      pair.predicted_max_mm = all.max_mm;
      pair.equal_count_configurations = static_cast<int>(half[0].size() + half[1].size());
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

/// `count` candidates spread over the groups as equally as their sizes allow, evenly spaced
/// within each group.
std::vector<int> equal_shares(const std::vector<std::vector<int>>& groups, int count) {
  std::vector<size_t> share(groups.size(), 0);
  for (int left = count; left > 0;) {
    const int before = left;
    for (size_t p = 0; p < groups.size() && left > 0; ++p)
      if (share[p] < groups[p].size()) {
        ++share[p];
        --left;
      }
    if (left == before) break;  // every group taken whole
  }
  std::vector<int> out;
  for (size_t p = 0; p < groups.size(); ++p)
    for (size_t k = 0; k < share[p]; ++k) out.push_back(groups[p][k * groups[p].size() / share[p]]);
  return out;
}

PlacementsDesign design_placements(const RobotModel& model, const std::vector<HexapodPlan>& plans,
                                   int count, const PlacementSearchRequest& request) {
  if (plans.empty()) throw InputError({"", 0, 0, "placements"}, "expected at least one plan");
  std::vector<Candidate> candidates;
  std::vector<std::vector<int>> groups;
  for (size_t p = 0; p < plans.size(); ++p) {
    const MeasuredPlacement m = measured_placement(plans[p], fmt::format("plan {}", p + 1));
    std::vector<int> mine;
    for (const Vector6d& q : m.joints) {
      mine.push_back(static_cast<int>(candidates.size()));
      candidates.push_back({q, -1});
    }
    groups.push_back(std::move(mine));
  }
  if (count < 1 || count > static_cast<int>(candidates.size()))
    throw InputError({"", 0, 0, "count"},
                     fmt::format("expected 1 to {} configurations", candidates.size()));
  const Context c = make_context(model, *plans.front().session.flange_T_tool, candidates, request,
                                 pose_sigma_mm(request));
  // The I-optimal machinery (design/task_selection.hpp) on the scaled Jacobian of every candidate
  // with its placement's world-frame columns: the mean predicted squared error over the
  // validation configurations, to which the frames contribute nothing.
  DesignMatrix design = c.design;
  const Eigen::MatrixXd J = placements_jacobian(c, groups);
  const Eigen::VectorXd scale = column_scales(c, J, groups);
  design.rows = J * scale.asDiagonal();
  design.column_scale = scale;
  Eigen::MatrixXd task =
      Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(c.validation.size()), J.cols());
  PositionJacobian Jp;
  for (size_t t = 0; t < c.validation.size(); ++t) {
    target_position_jacobian(model, PointMass{}, model.nominal(), c.validation[t], c.tcp_flange,
                             nullptr, &Jp);
    for (int k = 0; k < c.asked; ++k)
      task.block<3, 1>(3 * static_cast<Eigen::Index>(t), k) = Jp.col(c.design.parameters[k]);
  }
  std::vector<Vector6d> joints;
  joints.reserve(candidates.size());
  for (const Candidate& k : candidates) joints.push_back(k.joints);
  SelectionGuard guard;
  guard.enabled = false;
  const Eigen::MatrixXd information = task_information(design, task);
  TaskSelection selection = select_i_optimal(design, information, count, joints, guard);
  // One configuration at a further placement only pays for its world frame, so one-at-a-time
  // steps from nothing never leave the first placement; the search started from equal shares of
  // every placement can (docs/method/07-hexapod.md §7). The better of the two is kept.
  if (groups.size() > 1) {
    TaskSelection shared = select_i_optimal(design, information, count, joints, guard, {},
                                            equal_shares(groups, count));
    if (shared.criterion < selection.criterion) selection = std::move(shared);
  }
  PlacementsDesign out;
  out.parameters = static_cast<int>(searched_parameters(model, request).size());
  out.identifiable = c.asked;
  out.chosen.resize(plans.size());
  std::vector<std::vector<int>> chosen(plans.size());
  for (int k : selection.chosen)
    for (size_t p = 0; p < groups.size(); ++p)
      if (k >= groups[p].front() && k <= groups[p].back()) {
        out.chosen[p].push_back(k - groups[p].front());
        chosen[p].push_back(k);
      }
  for (std::vector<int>& v : out.chosen) std::sort(v.begin(), v.end());
  const Prediction prediction = predict(c, chosen);
  out.undetermined = prediction.undetermined;
  out.predicted_mean_mm = prediction.mean_mm;
  out.predicted_max_mm = prediction.max_mm;
  return out;
}

HexapodPlan plan_with_configurations(const HexapodPlan& plan, const std::vector<int>& chosen) {
  HexapodPlan out = plan;
  out.session.configurations.clear();
  if (out.replanned) out.replanned->planned_joints_deg.clear();
  for (const int c : chosen) {
    out.session.configurations.push_back(plan.session.configurations.at(static_cast<size_t>(c)));
    out.session.configurations.back().id = static_cast<int>(out.session.configurations.size());
    if (plan.replanned) {
      const auto& planned = plan.replanned->planned_joints_deg;
      out.replanned->planned_joints_deg.push_back(static_cast<size_t>(c) < planned.size()
                                                      ? planned[static_cast<size_t>(c)]
                                                      : std::vector<double>{});
    }
  }
  return out;
}

PlacementsDesignResult design_placements(const PlacementsDesignRequest& request) {
  if (request.plan_files.empty())
    throw InputError({"", 0, 0, "--plan"}, "expected at least one plan file");
  if (!request.out_files.empty() && request.out_files.size() != request.plan_files.size())
    throw InputError({"", 0, 0, "--out"},
                     fmt::format("expected one --out per --plan ({}), got {}",
                                 request.plan_files.size(), request.out_files.size()));
  check_identify_patterns(request.level, request.identify);
  if (request.validation_configurations < 2)
    throw InputError({"", 0, 0, "--validation"},
                     fmt::format("expected at least 2 validation configurations, got {}",
                                 request.validation_configurations));
  if (request.count < 0)
    throw InputError({"", 0, 0, "--count"},
                     fmt::format("expected a positive count (0: as many as the first plan "
                                 "offers), got {}",
                                 request.count));
  PlacementsDesignResult result;
  std::vector<HexapodPlan> plans;
  std::vector<MeasuredPlacement> placements;
  for (const std::string& file : request.plan_files) {
    plans.push_back(read_hexapod_plan(file));
    placements.push_back(measured_placement(plans.back(), file));
    const HexapodPlan& first = plans.front();
    const HexapodPlan& plan = plans.back();
    if (plan.cell->robot != first.cell->robot)
      throw InputError(
          {file, 0, 0, "robot"},
          fmt::format("this plan is for {}, the first ({}) for {}: plans of one "
                      "robot only",
                      plan.cell->robot, request.plan_files.front(), first.cell->robot));
    if (!plan.session.flange_T_tool || !first.session.flange_T_tool ||
        !plan.session.flange_T_tool->p.isApprox(first.session.flange_T_tool->p, 1e-9) ||
        !plan.session.flange_T_tool->R.isApprox(first.session.flange_T_tool->R, 1e-12) ||
        plan.cell->geometry.tool_cup4_mm != first.cell->geometry.tool_cup4_mm)
      throw InputError({file, 0, 0, "tool"},
                       fmt::format("this plan's tool fixture is not the one of {}: one tool "
                                   "fixture for every placement",
                                   request.plan_files.front()));
    result.offered.push_back(static_cast<int>(plan.session.configurations.size()));
  }
  check_apart(placements, plans.front().cell->cups.cup_diameter_mm, "--plan");
  const int offered = std::accumulate(result.offered.begin(), result.offered.end(), 0);
  if (request.count > offered)
    throw InputError({"", 0, 0, "--count"},
                     fmt::format("expected at most {} configurations (what the plans offer), "
                                 "got {}",
                                 offered, request.count));
  const RobotModel model = load_robot(plans.front().cell->robot);
  PlacementSearchRequest search;
  search.plan = *plans.front().cell;
  search.level = request.level;
  search.identify = request.identify;
  search.validation_configurations = request.validation_configurations;
  search.task_box = request.task_box;
  search.seed = request.seed;
  result.robot = model.name;
  result.count = request.count > 0 ? request.count : result.offered.front();
  result.design = design_placements(model, plans, result.count, search);
  result.first_alone = design_placements(model, {plans.front()},
                                         std::min(result.count, result.offered.front()), search);
  for (size_t p = 0; p < plans.size(); ++p)
    result.plans.push_back(plan_with_configurations(plans[p], result.design.chosen[p]));
  // Every reduced plan or none (write_files_atomically).
  std::vector<std::string> texts;
  std::vector<std::pair<std::filesystem::path, std::string_view>> files;
  texts.reserve(request.out_files.size());
  for (size_t p = 0; p < request.out_files.size(); ++p) {
    result.written.push_back(!result.design.chosen[p].empty());
    if (!result.written.back()) continue;
    texts.push_back(hexapod_plan_text(result.plans[p]));
    files.emplace_back(request.out_files[p], texts.back());
  }
  write_files_atomically(files);
  return result;
}

nlohmann::json placements_design_json(const PlacementsDesignRequest& request,
                                      const PlacementsDesignResult& r) {
  using nlohmann::json;
  const auto prediction = [](const PlacementsDesign& d) {
    return json{{"parameters", d.parameters},
                {"identifiable", d.identifiable},
                {"undetermined", d.undetermined},
                {"predicted_mean_mm", rounded(d.predicted_mean_mm, 6)},
                {"predicted_max_mm", rounded(d.predicted_max_mm, 6)}};
  };
  json out{{"robot", r.robot},
           {"count", r.count},
           {"level", level_name(request.level)},
           {"identify", request.identify},
           {"validation_configurations", request.validation_configurations},
           {"task_box", task_box_json(request.task_box)},
           {"seed", request.seed},
           {"design", prediction(r.design)},
           {"first_alone", prediction(r.first_alone)}};
  out["first_alone"]["configurations"] = r.first_alone.chosen.front().size();
  out["placements"] = json::array();
  for (size_t p = 0; p < r.plans.size(); ++p)
    out["placements"].push_back({{"plan", request.plan_files[p]},
                                 {"placement", placement_text(r.plans[p].cell->placement)},
                                 {"tilt_deg", r.plans[p].cell->tilt_deg},
                                 {"offered", r.offered[p]},
                                 {"chosen", r.design.chosen[p].size()}});
  for (size_t p = 0; p < r.written.size(); ++p)
    out["placements"][p]["written"] = r.written[p] ? json(request.out_files[p]) : json(nullptr);
  return out;
}

nlohmann::json placement_search_json(const PlacementSearchResult& r) {
  using nlohmann::json;
  const int best = r.best;
  json out{{"level", level_name(r.level)},
           {"identify", r.identify},
           {"task_box", task_box_json(r.task_box)},
           {"parameters", r.parameters},
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
  if (!r.next.empty() || r.measured_configurations > 0) {
    out["measured"] = {{"configurations", r.measured_configurations},
                       {"undetermined", r.measured_undetermined},
                       {"predicted_mean_mm", rounded(r.measured_mean_mm, 9)},
                       {"predicted_max_mm", rounded(r.measured_max_mm, 9)}};
    out["next"] = json::array();
    for (int i = 0; i < best && i < static_cast<int>(r.next.size()); ++i) {
      const NextPlacement& n = r.next[i];
      const PlacementScore& s = r.ranked[n.rank];
      out["next"].push_back({{"rank", n.rank + 1},
                             {"placement", placement_text(s.placement)},
                             {"tilt_deg", s.tilt_deg},
                             {"configurations", n.configurations},
                             {"undetermined", n.undetermined},
                             {"predicted_mean_mm", rounded(n.predicted_mean_mm, 9)},
                             {"predicted_max_mm", rounded(n.predicted_max_mm, 9)}});
    }
  }
  return out;
}

}  // namespace robcal::hexapod
