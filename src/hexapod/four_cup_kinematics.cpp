#include "robcal/hexapod/four_cup_kinematics.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "robcal/core/error.hpp"
#include "robcal/hexapod/poses.hpp"

namespace robcal::hexapod {
namespace {

/// One measured distance between two cups (global ids: base cups first, then tool cups).
struct Observation {
  int a = 0;
  int b = 0;
  double value = 0;
};

/// The least-squares problem: each cup's unknown coordinates (−1: fixed at zero by the gauge
/// b1 = 0, b2 on x, b3 in the xy plane) and the observations.
struct Problem {
  int base_count = 3;
  int tool_count = 3;
  int unknowns = 0;
  std::vector<std::array<int, 3>> index;
  std::vector<Observation> observations;
  std::vector<std::string> names;
};

Problem build_problem(const FourCupDkpRequest& request) {
  Problem p;
  p.base_count = request.base.cup_count();
  p.tool_count = request.tool.cup_count();
  p.index = {{-1, -1, -1}, {0, -1, -1}, {1, 2, -1}};
  p.unknowns = 3;
  for (int c = 3; c < p.base_count + p.tool_count; ++c) {
    p.index.push_back({p.unknowns, p.unknowns + 1, p.unknowns + 2});
    p.unknowns += 3;
  }
  const auto add_fixture = [&](const FixtureDistances& f, int offset, char letter) {
    const std::vector<double> values = f.values();
    for (size_t k = 0; k < values.size(); ++k) {
      p.observations.push_back(
          {offset + kFixtureDistancePairs[k][0], offset + kFixtureDistancePairs[k][1], values[k]});
      p.names.push_back(fmt::format("{}{}{}", letter, kFixtureDistancePairs[k][0] + 1,
                                    kFixtureDistancePairs[k][1] + 1));
    }
  };
  add_fixture(request.base, 0, 'b');
  add_fixture(request.tool, p.base_count, 't');
  for (const MeasuredLeg& leg : request.legs) {
    p.observations.push_back({leg.base, p.base_count + leg.tool, leg.length_mm});
    p.names.push_back(fmt::format("rho{}{}", leg.base + 1, leg.tool + 1));
  }
  return p;
}

Eigen::Vector3d cup(const Problem& p, const Eigen::VectorXd& x, int c) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a)
    if (p.index[c][a] >= 0) v[a] = x[p.index[c][a]];
  return v;
}

Eigen::VectorXd pack(const Problem& p, const std::vector<Eigen::Vector3d>& cups) {
  Eigen::VectorXd x(p.unknowns);
  for (size_t c = 0; c < cups.size(); ++c)
    for (int a = 0; a < 3; ++a)
      if (p.index[c][a] >= 0) x[p.index[c][a]] = cups[c][a];
  return x;
}

/// Residuals (model − measured) and their Jacobian: ∂|a − b|/∂a = (a − b)/|a − b|.
void residuals(const Problem& p, const Eigen::VectorXd& x, Eigen::VectorXd& r, Eigen::MatrixXd& J) {
  const int m = static_cast<int>(p.observations.size());
  r.resize(m);
  J.setZero(m, p.unknowns);
  for (int i = 0; i < m; ++i) {
    const Observation& o = p.observations[i];
    const Eigen::Vector3d diff = cup(p, x, o.a) - cup(p, x, o.b);
    const double length = diff.norm();
    r[i] = length - o.value;
    const Eigen::Vector3d u = diff / length;
    for (int a = 0; a < 3; ++a) {
      if (p.index[o.a][a] >= 0) J(i, p.index[o.a][a]) += u[a];
      if (p.index[o.b][a] >= 0) J(i, p.index[o.b][a]) -= u[a];
    }
  }
}

struct Fit {
  Eigen::VectorXd x;
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  int iterations = 0;
  bool converged = false;
};

/// Gauss–Newton; converged when a step is below 1e-12 mm (quadratic convergence at zero
/// residual, so the round trip is at rounding level).
Fit gauss_newton(const Problem& p, Eigen::VectorXd x) {
  Fit fit;
  for (fit.iterations = 1; fit.iterations <= 60; ++fit.iterations) {
    residuals(p, x, fit.r, fit.J);
    const Eigen::VectorXd step = fit.J.colPivHouseholderQr().solve(fit.r);
    if (!step.allFinite()) break;
    x -= step;
    if (step.norm() < 1e-12 * (1 + x.norm() / 1000)) {
      fit.converged = true;
      break;
    }
  }
  fit.x = x;
  residuals(p, x, fit.r, fit.J);
  return fit;
}

/// A problem of the request's input and where it lies; an empty message: none.
struct InputProblem {
  std::string message;
  FourCupInput culprit = FourCupInput::Legs;
};

InputProblem input_problem(const FourCupDkpRequest& request) {
  if (std::string problem = fixture_problem(request.base, "base fixture"); !problem.empty())
    return {std::move(problem), FourCupInput::BaseFixture};
  if (std::string problem = fixture_problem(request.tool, "tool fixture"); !problem.empty())
    return {std::move(problem), FourCupInput::ToolFixture};
  std::array<bool, 2> fourth_has_leg{false, false};
  for (const MeasuredLeg& leg : request.legs) {
    if (leg.base < 0 || leg.base >= request.base.cup_count() || leg.tool < 0 ||
        leg.tool >= request.tool.cup_count())
      return {fmt::format("leg B{}-T{}: the fixtures have cups B1..B{} and T1..T{}", leg.base + 1,
                          leg.tool + 1, request.base.cup_count(), request.tool.cup_count())};
    if (!std::isfinite(leg.length_mm) || leg.length_mm <= 0)
      return {fmt::format("leg B{}-T{} = {} mm is not a positive length", leg.base + 1,
                          leg.tool + 1, leg.length_mm)};
    fourth_has_leg[0] = fourth_has_leg[0] || leg.base == 3;
    fourth_has_leg[1] = fourth_has_leg[1] || leg.tool == 3;
  }
  // Without a leg, a fourth cup's distances to its own fixture fix it only up to a mirror
  // through the fixture plane, and not at all to first order across it.
  if (request.base.fourth && !fourth_has_leg[0])
    return {"base cup B4 has no leg: measure at least one leg from B4 or leave the cup out"};
  if (request.tool.fourth && !fourth_has_leg[1])
    return {"tool cup T4 has no leg: measure at least one leg to T4 or leave the cup out"};
  return {};
}

/// Per tool cup: σ per axis and as a norm from the variances of T1x, T1y, T1z, T2x, ….
std::vector<CupUncertainty> cup_uncertainties(const Eigen::VectorXd& variances) {
  std::vector<CupUncertainty> cups(variances.size() / 3);
  for (size_t j = 0; j < cups.size(); ++j) {
    const Eigen::Vector3d var = variances.segment<3>(3 * j);
    cups[j].cup = "T" + std::to_string(j + 1);
    cups[j].per_axis = var.cwiseSqrt();
    cups[j].norm = std::sqrt(var.sum());
  }
  return cups;
}

}  // namespace

FourCupDkpRequest four_cup_distances(const std::vector<Eigen::Vector3d>& base,
                                     const std::vector<Eigen::Vector3d>& tool,
                                     const std::vector<PhysicalLeg>& legs) {
  const auto distances = [](const std::vector<Eigen::Vector3d>& c) {
    FixtureDistances f;
    f.sides = {(c[0] - c[1]).norm(), (c[1] - c[2]).norm(), (c[2] - c[0]).norm()};
    if (c.size() > 3) f.fourth = {(c[0] - c[3]).norm(), (c[1] - c[3]).norm(), (c[2] - c[3]).norm()};
    return f;
  };
  FourCupDkpRequest request{distances(base), distances(tool), {}};
  for (const PhysicalLeg& leg : legs)
    request.legs.push_back({leg.base, leg.tool, (base[leg.base] - tool[leg.tool]).norm()});
  return request;
}

FourCupDkpResult solve_four_cup_dkp(const FourCupDkpRequest& request) {
  FourCupDkpResult result;
  if (InputProblem problem = input_problem(request); !problem.message.empty()) {
    result.status = FourCupDkpStatus::InvalidInput;
    result.message = std::move(problem.message);
    result.culprit = problem.culprit;
    return result;
  }
  const Problem problem = build_problem(request);
  result.distance_names = problem.names;
  // A 3-3 design on cups 1..3 among the legs gives the closed-form starting points.
  const auto leg_length = [&](int b, int t) -> std::optional<double> {
    for (const MeasuredLeg& leg : request.legs)
      if (leg.base == b && leg.tool == t) return leg.length_mm;
    return std::nullopt;
  };
  std::optional<LegLengths<double>> design_legs;
  for (const LegDesign& design : all_leg_designs()) {
    LegLengths<double> legs;
    bool complete = true;
    for (size_t i = 0; i < kDesignLegs.size() && complete; ++i) {
      const auto length =
          leg_length(design.base[kDesignLegs[i].base], design.tool[kDesignLegs[i].tool]);
      complete = length.has_value();
      if (complete) legs[i] = *length;
    }
    if (complete) {
      result.design = design;
      design_legs = legs;
      break;
    }
  }
  if (!design_legs) {
    result.status = FourCupDkpStatus::InvalidInput;
    result.message =
        "the legs do not include a 1^12 2^123 3^1 design on the cups 1..3 (one base cup to two "
        "tool cups, one to all three, one to the first): no closed-form starting point";
    return result;
  }
  const std::vector<Eigen::Vector3d> base = fixture_cup_positions(request.base);
  const std::vector<Eigen::Vector3d> tool_local = fixture_cup_positions(request.tool);
  const Cups<double> base3{base[0], base[1], base[2]};
  const Cups<double> tool3{tool_local[0], tool_local[1], tool_local[2]};
  const DkpResult dkp = solve_dkp(design_base_cups(result.design, base3), Eigen::Vector3d::UnitZ(),
                                  design_tool_sides(result.design, tool3), *design_legs);
  if (dkp.status != DkpStatus::Ok) {
    result.status = FourCupDkpStatus::NoRealSolution;
    result.message = "cups 1..3: " + dkp.message;
    return result;
  }
  std::string rank_problem;
  for (const AssemblyModeSolution& start : dkp.solutions) {
    const Cups<double> tool_cups = physical_tool_cups(result.design, start.tool);
    // The tool fixture frame of the cascade's cups carries the fourth tool cup along
    // (tool_local is in its own fixture frame, whose frame_from_cups is the identity).
    const Pose<double> base_T_tool = frame_from_cups(tool_cups);
    std::vector<Eigen::Vector3d> cups = base;
    for (const Eigen::Vector3d& t : tool_local) cups.push_back(base_T_tool.R * t + base_T_tool.p);
    const Fit fit = gauss_newton(problem, pack(problem, cups));
    if (!fit.converged || !fit.x.allFinite()) continue;
    // The whole configuration mirrored through the base plane fits every distance as well: keep
    // the side the cascade keeps (design T1 above the base plane).
    if (!(cup(problem, fit.x, problem.base_count + result.design.tool[0]).z() > 0)) continue;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(fit.J, Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::VectorXd& sv = svd.singularValues();
    if (!(sv[sv.size() - 1] > 1e-9 * sv[0])) {
      rank_problem = fmt::format(
          "the distances do not determine the cups (assembly mode {}: the fit's Jacobian has "
          "condition number {:.3g}); add legs to the fourth cups or change the geometry",
          start.mode, sv[0] / sv[sv.size() - 1]);
      continue;
    }
    FourCupSolution s;
    s.mode = start.mode;
    s.iterations = fit.iterations;
    for (int c = 0; c < problem.base_count + problem.tool_count; ++c)
      (c < problem.base_count ? s.base_cups : s.tool_cups).push_back(cup(problem, fit.x, c));
    if (std::any_of(result.solutions.begin(), result.solutions.end(),
                    [&](const FourCupSolution& o) {
                      for (size_t j = 0; j < s.tool_cups.size(); ++j)
                        if ((o.tool_cups[j] - s.tool_cups[j]).norm() > 1e-6) return false;
                      return true;
                    }))
      continue;
    s.rms_residual_mm = std::sqrt(fit.r.squaredNorm() / fit.r.size());
    s.max_residual_mm = fit.r.cwiseAbs().maxCoeff();
    // GUM (Guide 98-3 eq. 10): ∂x/∂d = J⁺ at the least-squares solution (r = f(x) − d).
    const Eigen::MatrixXd pinv =
        svd.matrixV() * sv.cwiseInverse().asDiagonal() * svd.matrixU().transpose();
    s.sensitivity.setZero(3 * problem.tool_count, pinv.cols());
    for (int j = 0; j < problem.tool_count; ++j)
      for (int a = 0; a < 3; ++a)
        s.sensitivity.row(3 * j + a) = pinv.row(problem.index[problem.base_count + j][a]);
    s.uncertainty = cup_uncertainties(s.sensitivity.rowwise().squaredNorm());
    result.solutions.push_back(std::move(s));
  }
  std::sort(result.solutions.begin(), result.solutions.end(),
            [](const auto& a, const auto& b) { return a.rms_residual_mm < b.rms_residual_mm; });
  if (result.solutions.empty()) {
    result.status =
        rank_problem.empty() ? FourCupDkpStatus::NoRealSolution : FourCupDkpStatus::NotDetermined;
    result.message = rank_problem.empty() ? "no least-squares solution converged from the cascade"
                                          : rank_problem;
  }
  return result;
}

std::vector<CupUncertainty> four_cup_uncertainty_monte_carlo(const FourCupDkpRequest& request,
                                                             const FourCupSolution& reference,
                                                             double sigma_mm, int samples,
                                                             std::mt19937_64& rng) {
  if (!(sigma_mm > 0) || !std::isfinite(sigma_mm) || samples < 2)
    throw InputError(
        fmt::format("Monte Carlo needs σ > 0 and at least 2 samples (σ = {} mm, {} samples)",
                    sigma_mm, samples));
  const Problem problem = build_problem(request);
  std::vector<Eigen::Vector3d> cups = reference.base_cups;
  cups.insert(cups.end(), reference.tool_cups.begin(), reference.tool_cups.end());
  const Eigen::VectorXd x0 = pack(problem, cups);
  std::normal_distribution<double> noise(0.0, sigma_mm);
  const int n = 3 * problem.tool_count;
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(n), sum2 = sum;
  int used = 0;
  Problem drawn = problem;
  for (int s = 0; s < samples; ++s) {
    for (size_t i = 0; i < drawn.observations.size(); ++i)
      drawn.observations[i].value = problem.observations[i].value + noise(rng);
    // Started from the reference: the draw stays in its basin (σ ≪ the distance to another mode).
    const Fit fit = gauss_newton(drawn, x0);
    if (!fit.converged) continue;
    Eigen::VectorXd dev(n);
    for (int j = 0; j < problem.tool_count; ++j)
      dev.segment<3>(3 * j) = cup(drawn, fit.x, problem.base_count + j) - reference.tool_cups[j];
    sum += dev;
    sum2 += dev.cwiseProduct(dev);
    ++used;
  }
  if (used < 2)
    throw InputError(fmt::format("Monte Carlo: only {} of {} draws converged", used, samples));
  const Eigen::VectorXd mean = sum / used;
  const Eigen::VectorXd var =
      (sum2 / used - mean.cwiseProduct(mean)) * (double(used) / (used - 1)) / (sigma_mm * sigma_mm);
  return cup_uncertainties(var);
}

WorstToolCupUncertainty worst_tool_cup_uncertainty(const std::vector<HexapodPose>& poses,
                                                   const HexapodGeometry& geometry) {
  fixture_cups(geometry.base, "--base-mm");
  const std::vector<Eigen::Vector3d> base_cups = base_cup_positions(geometry);
  // The worst cup of the solution nearest the planned tool cups.
  const auto worst_cup = [](const FourCupDkpRequest& request,
                            const std::vector<Eigen::Vector3d>& planned) {
    const FourCupDkpResult fit = solve_four_cup_dkp(request);
    if (fit.status != FourCupDkpStatus::Ok || fit.solutions.empty())
      throw std::logic_error("a planned hexapod pose has no solution: " + fit.message);
    const auto gap = [&](const FourCupSolution& s) {
      double g = 0;
      for (int j = 0; j < 3; ++j) g = std::max(g, (s.tool_cups[j] - planned[j]).norm());
      return g;
    };
    const FourCupSolution& nearest = *std::min_element(
        fit.solutions.begin(), fit.solutions.end(),
        [&](const FourCupSolution& a, const FourCupSolution& b) { return gap(a) < gap(b); });
    double worst = 0;
    for (int j = 0; j < 3; ++j) worst = std::max(worst, nearest.uncertainty[j].norm);
    return worst;
  };
  WorstToolCupUncertainty worst;
  for (const HexapodPose& pose : poses) {
    const std::vector<Eigen::Vector3d> tool = pose_tool_cups(pose, geometry);
    const std::vector<PhysicalLeg> design(
        pose.legs.begin(), pose.legs.begin() + static_cast<std::ptrdiff_t>(kDesignLegs.size()));
    const double three = worst_cup(four_cup_distances({base_cups.begin(), base_cups.begin() + 3},
                                                      {tool.begin(), tool.begin() + 3}, design),
                                   tool);
    // Fourth cups that no leg reaches are left out of four_cup_distances' fixtures.
    std::vector<Eigen::Vector3d> base_reached(base_cups.begin(), base_cups.begin() + 3);
    std::vector<Eigen::Vector3d> tool_reached(tool.begin(), tool.begin() + 3);
    for (const PhysicalLeg& l : pose.legs) {
      if (l.base == 3) base_reached = base_cups;
      if (l.tool == 3) tool_reached = tool;
    }
    worst.design_legs = std::max(worst.design_legs, three);
    worst.all_legs =
        std::max(worst.all_legs,
                 pose.legs.size() > kDesignLegs.size()
                     ? worst_cup(four_cup_distances(base_reached, tool_reached, pose.legs), tool)
                     : three);
  }
  return worst;
}

}  // namespace robcal::hexapod
