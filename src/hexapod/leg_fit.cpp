#include "robcal/hexapod/leg_fit.hpp"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/identify/accuracy_prediction.hpp"

namespace robcal::hexapod {
namespace {

/// |B − H(q)·T| − (reading + offset) for one leg.
struct LegResidual {
  const RobotModel* model;
  PointMass payload;
  Vector6d joints;
  double reading;

  template <typename T>
  bool operator()(const T* params, const T* base_cup, const T* tool_cup, const T* offset,
                  T* residual) const {
    std::array<T, kJointCount> q;
    for (int i = 0; i < kJointCount; ++i) q[i] = T(joints[i]);
    const Pose<T> f = flange_pose(*model, payload, params, q.data());
    const Vector3<T> t = f * Vector3<T>(tool_cup[0], tool_cup[1], tool_cup[2]);
    const Vector3<T> b(base_cup[0], base_cup[1], base_cup[2]);
    residual[0] = (b - t).norm() - (T(reading) + offset[0]);
    return true;
  }
};

/// |a − b| − (reading + offset) for a fixture side.
struct SideResidual {
  double reading;
  template <typename T>
  bool operator()(const T* a, const T* b, const T* offset, T* residual) const {
    const Vector3<T> d(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    residual[0] = d.norm() - (T(reading) + offset[0]);
    return true;
  }
};

/// The six base parameters that carry the world frame the cups define, seen from the fit's robot
/// frame, to where `robot_T_world` puts it: T = robot_T_world · frame(cups)⁻¹ written exactly as
/// world_A_1 = Trans(x, y, d1 + z) · Rx Ry Rz(γ + θ1) (docs/method/02-frames.md §4).
template <typename T>
std::array<T, kBaseParamCount> base_parameters(const Cups<T>& cups,
                                               const Pose<double>& robot_T_world, double d1) {
  Pose<T> world;
  world.R = robot_T_world.R.cast<T>();
  world.p = robot_T_world.p.cast<T>();
  const Pose<T> t = world * frame_from_cups(cups).inverse();
  const Vector3<T> origin = t.p + t.R.col(2) * T(d1);
  using std::asin;
  using std::atan2;
  // T.R = Rx(α) Ry(β) Rz(γ); |R(0, 2)| ≤ 1 up to rounding.
  const T sin_beta = t.R(0, 2) > T(1) ? T(1) : (t.R(0, 2) < T(-1) ? T(-1) : t.R(0, 2));
  return {origin.x(),         origin.y(),
          origin.z() - T(d1), atan2(-t.R(1, 2), t.R(2, 2)),
          asin(sin_beta),     atan2(-t.R(0, 1), t.R(0, 0))};
}

}  // namespace

LegFitResult fit_from_legs(const RobotModel& model, const PointMass& payload,
                           const FixtureDistances& base, const FixtureDistances& tool,
                           const std::vector<LegReadings>& readings,
                           const ParameterVector& start_params, const Pose<double>& robot_T_world,
                           const Pose<double>& flange_T_tool, const LegFitOptions& options) {
  return fit_from_legs(model, payload, tool, {{base, readings, robot_T_world}}, start_params,
                       flange_T_tool, options);
}

LegFitResult fit_from_legs(const RobotModel& model, const PointMass& payload,
                           const FixtureDistances& tool,
                           const std::vector<LegPlacement>& placements,
                           const ParameterVector& start_params, const Pose<double>& flange_T_tool,
                           const LegFitOptions& options) {
  for (int i : options.free_parameters)
    if (i < kBaseParamCount || i >= kParameterCount)
      throw InputError({"", 0, 0, "free parameters"},
                       "the leg fit uses the relative model: base parameters stay fixed");
  if (placements.empty())
    throw InputError({"", 0, 0, "placements"}, "expected the readings of at least one placement");
  const int n_placements = static_cast<int>(placements.size());
  LegFitResult result;
  result.params = start_params;
  result.base_cups_robot.resize(placements.size());
  result.base_cup4_robot.resize(placements.size());
  if (const std::string problem = fixture_problem(tool, "tool fixture"); !problem.empty())
    throw InputError({"", 0, 0, "tool fixture"}, problem);
  const std::vector<Eigen::Vector3d> tool_local = fixture_cup_positions(tool);
  for (int p = 0; p < n_placements; ++p) {
    fixture_cups(placements[p].base.sides, "base fixture sides");
    if (const std::string problem = fixture_problem(placements[p].base, "base fixture");
        !problem.empty())
      throw InputError({"", 0, 0, "base fixture"}, problem);
    const std::vector<Eigen::Vector3d> base_local = fixture_cup_positions(placements[p].base);
    for (int i = 0; i < 3; ++i)
      result.base_cups_robot[p][i] = placements[p].robot_T_world * base_local[i];
    if (placements[p].base.fourth)
      result.base_cup4_robot[p] = placements[p].robot_T_world * base_local[3];
  }
  for (int i = 0; i < 3; ++i) result.tool_cups_flange[i] = flange_T_tool * tool_local[i];
  if (tool.fourth) result.tool_cup4_flange = flange_T_tool * tool_local[3];
  // The 3-vector blocks in extras order, named: base cups of each placement, then the tool cups.
  std::vector<double*> cup_blocks;
  std::vector<std::string> block_names;
  for (int p = 0; p < n_placements; ++p) {
    const auto add_base = [&](Eigen::Vector3d& c, int cup) {
      cup_blocks.push_back(c.data());
      const std::string name = fmt::format("base_cup.B{}", cup);
      block_names.push_back(n_placements == 1 ? name : fmt::format("placement{}.{}", p + 1, name));
    };
    for (int i = 0; i < 3; ++i) add_base(result.base_cups_robot[p][i], i + 1);
    if (result.base_cup4_robot[p]) add_base(*result.base_cup4_robot[p], 4);
  }
  for (int j = 0; j < 3; ++j) {
    cup_blocks.push_back(result.tool_cups_flange[j].data());
    block_names.push_back(fmt::format("tool_cup.T{}", j + 1));
  }
  if (result.tool_cup4_flange) {
    cup_blocks.push_back(result.tool_cup4_flange->data());
    block_names.push_back("tool_cup.T4");
  }
  const int extras = 3 * static_cast<int>(cup_blocks.size()) + 1;
  const int offset_index = kParameterCount + extras - 1;
  const auto extra_name = [&](int k) {
    return k + 1 == extras ? std::string("ballbar.length_offset")
                           : fmt::format("{}.{}", block_names[k / 3], "xyz"[k % 3]);
  };
  // Which unknowns are candidates: the requested parameters except those the free tool cups
  // absorb, every cup coordinate, the offset if asked.
  std::vector<bool> candidate(kParameterCount + extras, false);
  for (int i : options.free_parameters) candidate[i] = true;
  for (int link6 : {link_param(6, 3), link_param(6, 2)})
    if (candidate[link6]) {
      candidate[link6] = false;
      result.held.push_back(parameter_table()[link6].name +
                            ": a shift along / turn about the flange axis moves only the tool "
                            "cups, which are identified");
    }
  for (int k = 0; k < extras - 1; ++k) candidate[kParameterCount + k] = true;
  candidate[offset_index] = options.fit_length_offset;
  const auto base_cup = [&](int p, int b) {
    return b < 3 ? result.base_cups_robot[p][b].data() : result.base_cup4_robot[p]->data();
  };
  const auto tool_cup = [&](int t) {
    return t < 3 ? result.tool_cups_flange[t].data() : result.tool_cup4_flange->data();
  };
  const auto add_leg = [&](ceres::Problem& problem, const LegReadings& r, int p, int b, int t,
                           double reading) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<LegResidual, 1, kParameterCount, 3, 3, 1>(
            new LegResidual{&model, payload, r.joints, reading}),
        nullptr, result.params.data(), base_cup(p, b), tool_cup(t), &result.length_offset_mm);
  };

  double zero_offset = 0;  // the tool sides' set-up offset, held
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
  const auto build = [&](ceres::Problem& problem) {
    double* params = result.params.data();
    problem.AddParameterBlock(params, kParameterCount);
    for (double* block : cup_blocks) problem.AddParameterBlock(block, 3);
    problem.AddParameterBlock(&result.length_offset_mm, 1);
    for (int p = 0; p < n_placements; ++p)
      for (const LegReadings& r : placements[p].readings) {
        for (size_t i = 0; i < kDesignLegs.size(); ++i)
          add_leg(problem, r, p, r.design.base[kDesignLegs[i].base],
                  r.design.tool[kDesignLegs[i].tool], r.legs[i]);
        for (const MeasuredLeg& leg : r.extra_legs)
          add_leg(problem, r, p, leg.base, leg.tool, leg.length_mm);
      }
    // Base sides at the leg set-up share its offset; the tool sides (150 mm set-up) get their own,
    // held at zero: that set-up is calibrated separately.
    problem.AddParameterBlock(&zero_offset, 1);
    problem.SetParameterBlockConstant(&zero_offset);
    const auto side = [&](double reading, double* a, double* b, double* offset) {
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<SideResidual, 1, 3, 3, 1>(new SideResidual{reading}),
          nullptr, a, b, offset);
    };
    // A fourth base cup's distances, each at its own set-up, get no offset either.
    for (int p = 0; p < n_placements; ++p) {
      const std::vector<double> bs = placements[p].base.values();
      for (size_t i = 0; i < bs.size(); ++i)
        side(bs[i], base_cup(p, kFixtureDistancePairs[i][0]),
             base_cup(p, kFixtureDistancePairs[i][1]),
             i < 3 ? &result.length_offset_mm : &zero_offset);
    }
    // The tool sides, and a fourth cup's distances (each at its own set-up: no offset either).
    const std::vector<double> ts = tool.values();
    for (size_t i = 0; i < ts.size(); ++i)
      side(ts[i], tool_cup(kFixtureDistancePairs[i][0]), tool_cup(kFixtureDistancePairs[i][1]),
           &zero_offset);
  };

  // The Jacobian of every residual over the unknowns `columns` (indices into parameters + extras)
  // at the current values, and the residual sum of squares.
  const auto jacobian = [&](const std::vector<int>& columns, double* rss) {
    ceres::Problem probe(problem_options);
    build(probe);
    ceres::CRSMatrix crs;
    ceres::Problem::EvaluateOptions eval;
    eval.parameter_blocks = {result.params.data()};
    eval.parameter_blocks.insert(eval.parameter_blocks.end(), cup_blocks.begin(), cup_blocks.end());
    eval.parameter_blocks.push_back(&result.length_offset_mm);
    double cost = 0;
    probe.Evaluate(eval, &cost, nullptr, nullptr, &crs);
    *rss = 2 * cost;
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, static_cast<int>(columns.size()));
    std::vector<int> where(kParameterCount + extras, -1);
    for (size_t c = 0; c < columns.size(); ++c) where[columns[c]] = static_cast<int>(c);
    for (int row = 0; row < crs.num_rows; ++row)
      for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k)
        if (where[crs.cols[k]] >= 0) J(row, where[crs.cols[k]]) = crs.values[k];
    return J;
  };

  // Rank-revealing QR of the column-scaled Jacobian over the candidates, at the start point.
  std::vector<int> columns;
  for (int k = 0; k < kParameterCount + extras; ++k)
    if (candidate[k]) columns.push_back(k);
  {
    double rss = 0;
    Eigen::MatrixXd J = jacobian(columns, &rss);
    result.residuals = static_cast<int>(J.rows());
    result.initial_rms_mm = std::sqrt(rss / J.rows());
    for (int c = 0; c < J.cols(); ++c)
      if (J.col(c).norm() > 0) J.col(c) /= J.col(c).norm();
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(J);
    qr.setThreshold(1e-9);
    const int rank = static_cast<int>(qr.rank());
    for (int c = rank; c < J.cols(); ++c) {
      const int k = columns[qr.colsPermutation().indices()[c]];
      candidate[k] = false;
      result.held.push_back(
          (k < kParameterCount ? parameter_table()[k].name : extra_name(k - kParameterCount)) +
          ": not identifiable from these readings (rank test)");
    }
  }

  ceres::Problem problem(problem_options);
  build(problem);
  std::vector<int> fixed;
  for (int i = 0; i < kParameterCount; ++i)
    if (!candidate[i])
      fixed.push_back(i);
    else
      result.identified.push_back(i);
  if (fixed.size() == static_cast<size_t>(kParameterCount))
    problem.SetParameterBlockConstant(result.params.data());
  else if (!fixed.empty())
    problem.SetManifold(result.params.data(), new ceres::SubsetManifold(kParameterCount, fixed));
  for (size_t block = 0; block < cup_blocks.size(); ++block) {
    double* data = cup_blocks[block];
    std::vector<int> held;
    for (int a = 0; a < 3; ++a)
      if (!candidate[kParameterCount + 3 * static_cast<int>(block) + a]) held.push_back(a);
    if (held.size() == 3)
      problem.SetParameterBlockConstant(data);
    else if (!held.empty())
      problem.SetManifold(data, new ceres::SubsetManifold(3, held));
  }
  if (!candidate[offset_index]) problem.SetParameterBlockConstant(&result.length_offset_mm);

  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = 1e-15;
  solver.gradient_tolerance = 1e-15;
  solver.parameter_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.iterations = static_cast<int>(summary.iterations.size()) - 1;
  result.message = summary.message;
  result.rms_mm = std::sqrt(2 * summary.final_cost / result.residuals);
  // The fitted unknowns' covariance σ̂²(JᵀJ)⁻¹ at the solution (docs/method/04-identification.md
  // §4).
  result.unknowns.clear();
  for (int k = 0; k < kParameterCount + extras; ++k)
    if (candidate[k]) result.unknowns.push_back(k);
  double rss = 0;
  const Eigen::MatrixXd J = jacobian(result.unknowns, &rss);
  const auto dof = std::max<Eigen::Index>(1, J.rows() - J.cols());
  result.sigma_mm = std::sqrt(rss / static_cast<double>(dof));
  result.covariance = design_covariance(J, result.sigma_mm);
  return result;
}

CalibratedRobot leg_fit_robot(const RobotModel& model, const PointMass& payload,
                              const LegFitResult& fit, const Pose<double>& robot_T_world) {
  CalibratedRobot robot;
  robot.model = model;
  robot.params = fit.params;
  robot.level = "full";
  robot.base_fitted = true;
  robot.status.fill(ParameterStatus::Fixed);
  for (int i : fit.identified) robot.status[i] = ParameterStatus::Identified;
  for (const std::string& held : fit.held) {
    const std::string name = held.substr(0, held.find(':'));
    for (int i = 0; i < kParameterCount; ++i)
      if (parameter_table()[i].name == name) {
        robot.status[i] = ParameterStatus::Dropped;
        robot.reason[i] = held.substr(held.find(':') + 2);
      }
  }
  // The fit's robot frame in the pose fit's one, as the six base parameters, with their
  // derivatives by the first placement's nine base-cup coordinates (the fit's first extras).
  using Jet = ceres::Jet<double, 9>;
  Cups<Jet> cups;
  for (int c = 0; c < 3; ++c)
    for (int a = 0; a < 3; ++a) cups[c][a] = Jet(fit.base_cups_robot.front()[c][a], 3 * c + a);
  const std::array<Jet, kBaseParamCount> base =
      base_parameters(cups, robot_T_world, model.mdh[0].d);
  for (int i = 0; i < kBaseParamCount; ++i) {
    robot.params[i] = base[i].a;
    robot.status[i] = ParameterStatus::Identified;
  }
  const Pose<double> T = robot_T_world * frame_from_cups(fit.base_cups_robot.front()).inverse();
  // Covariance: C_model = G · C_fit · Gᵀ with G the derivatives of the model's parameters by the
  // fitted unknowns (1 for an identified parameter, the Jet's for the base parameters).
  if (fit.covariance.rows() == static_cast<Eigen::Index>(fit.unknowns.size()) &&
      !fit.unknowns.empty()) {
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(kParameterCount, fit.covariance.rows());
    for (Eigen::Index c = 0; c < G.cols(); ++c) {
      const int k = fit.unknowns[static_cast<size_t>(c)];
      if (k < kParameterCount)
        G(k, c) = 1;
      else if (k < kParameterCount + 9)
        for (int i = 0; i < kBaseParamCount; ++i) G(i, c) = base[i].v[k - kParameterCount];
    }
    robot.covariance = G * fit.covariance * G.transpose();
  }
  // Gravity given in the world was along the fit's robot z: seen from the new world it is
  // tilted by T. Gravity given in the base frame turns with the base placement already
  // (docs/method/03-error-model.md §7), so it stays as it is.
  if (!model.gravity_in_base) robot.model.gravity_m_s2 = T.R * model.gravity_m_s2;
  robot.tool.payload = payload;
  const Pose<double> flange_T_tool = frame_from_cups(fit.tool_cups_flange);
  robot.tool.flange_T_tcp.linear() = flange_T_tool.R;
  robot.tool.flange_T_tcp.translation() = flange_T_tool.p;
  for (int j = 0; j < 3; ++j)
    robot.tool.targets.push_back({"T" + std::to_string(j + 1), fit.tool_cups_flange[j], true});
  if (fit.tool_cup4_flange) robot.tool.targets.push_back({"T4", *fit.tool_cup4_flange, true});
  return robot;
}

}  // namespace robcal::hexapod
