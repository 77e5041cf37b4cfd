// Four-cup ballbar hexapod (issue 20): over-determined direct kinematics in least squares, its GUM
// uncertainty, and the checks that refuse ill-posed fixtures and poses that cannot be set up.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/hexapod/cup_collision.hpp"
#include "robcal/hexapod/four_cup_kinematics.hpp"
#include "test_support.hpp"

namespace robcal::hexapod {
namespace {

using Points = std::vector<Eigen::Vector3d>;

/// The design 1^12 2^123 3^1 on cups 1..3 in measurement order, then `extra`.
std::vector<PhysicalLeg> design_legs_plus(const std::vector<PhysicalLeg>& extra) {
  std::vector<PhysicalLeg> legs;
  for (const LegRoles& r : kDesignLegs) legs.push_back({r.base, r.tool});
  legs.insert(legs.end(), extra.begin(), extra.end());
  return legs;
}

/// Cups expressed in the base fixture frame of base cups 1..3 (the solver's frame).
Points in_base_frame(const Points& base, const Points& cups) {
  const Pose<double> frame = frame_from_cups(Cups<double>{base[0], base[1], base[2]});
  Points out;
  for (const Eigen::Vector3d& c : cups) out.push_back(frame.R.transpose() * (c - frame.p));
  return out;
}

double max_gap(const Points& a, const Points& b) {
  double gap = 0;
  for (size_t i = 0; i < a.size(); ++i) gap = std::max(gap, (a[i] - b[i]).norm());
  return gap;
}

/// A nominal-size cell: base cups 300 mm apart with B4 off the triangle, tool cups 150 mm apart
/// with T4, the tool fixture facing the base about 250 mm above it.
struct Cell {
  Points base, tool;
  std::vector<PhysicalLeg> legs;
};
Cell nominal_four_cup_cell() {
  Cell c;
  const Cups<double> b = triangle_from_sides(300.0, 300.0, 300.0);
  c.base = {b[0], b[1], b[2], Eigen::Vector3d(150, -120, 3)};
  const Cups<double> t = triangle_from_sides(150.0, 150.0, 150.0);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitX()).toRotationMatrix() *
      Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d p(80, 160, 250);
  for (const Eigen::Vector3d& local : {t[0], t[1], t[2], Eigen::Vector3d(75, -60, 0)})
    c.tool.push_back(R * local + p);
  c.legs = design_legs_plus({{3, 3}, {3, 0}, {2, 3}});
  return c;
}

/// The nominal cell's distances and their solution.
struct Solved {
  Cell cell = nominal_four_cup_cell();
  FourCupDkpRequest request = four_cup_distances(cell.base, cell.tool, cell.legs);
  FourCupDkpResult result = solve_four_cup_dkp(request);
};

/// The solution whose tool cups are nearest to `cups` (a reference into `r`).
const FourCupSolution& nearest(const FourCupDkpResult&& r, const Points& cups) = delete;
const FourCupSolution& nearest(const FourCupDkpResult& r, const Points& cups) {
  const FourCupSolution* best = &r.solutions.at(0);
  for (const FourCupSolution& s : r.solutions)
    if (max_gap(s.tool_cups, cups) < max_gap(best->tool_cups, cups)) best = &s;
  return *best;
}

TEST(HexapodFourCup, ThreeCupsReproduceTheClosedFormAndItsJetSensitivities) {
  // With 3 + 3 cups and the six design legs the fit is square: it must return the cascade's
  // solutions, and J⁺ the Jet derivatives of the cascade (uncertainty.hpp), distance for distance.
  const HexapodGeometry g{{301, 299, 300.5}, {150, 151, 149.5}, 300};
  LegLengths<double> legs;
  legs.fill(g.leg_mm);
  FourCupDkpRequest request{{g.base, {}}, {g.tool, {}}, {}};
  for (const LegRoles& r : kDesignLegs) request.legs.push_back({r.base, r.tool, g.leg_mm});
  const FourCupDkpResult result = solve_four_cup_dkp(request);
  ASSERT_EQ(result.status, FourCupDkpStatus::Ok) << result.message;
  const DkpResult closed = solve_dkp(g.base, g.tool, legs);
  ASSERT_EQ(result.solutions.size(), closed.solutions.size());
  const std::vector<ModeUncertainty> jets = dkp_uncertainty(g);
  for (const FourCupSolution& s : result.solutions) {
    SCOPED_TRACE(s.mode);
    const AssemblyModeSolution* expected = closed.mode(s.mode);
    ASSERT_NE(expected, nullptr);
    EXPECT_LT(max_gap(s.tool_cups, Points(expected->tool.begin(), expected->tool.end())), 1e-9);
    EXPECT_LT(s.max_residual_mm, 1e-9);
    const auto jet =
        std::find_if(jets.begin(), jets.end(), [&](auto& m) { return m.mode == s.mode; });
    ASSERT_NE(jet, jets.end());
    EXPECT_LT((s.sensitivity - jet->sensitivity).cwiseAbs().maxCoeff(), 1e-7);
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(s.uncertainty[j].norm, jet->cups[j].norm, 1e-7);
  }
  EXPECT_EQ(result.distance_names[0], "b12");
  EXPECT_EQ(result.distance_names[6], "rho11");
}

TEST(HexapodFourCup, RoundTripOn2000RandomGeometries) {
  const uint64_t seed = 2020;
  SCOPED_TRACE(seed);
  auto rng = test::seeded_rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto fixture = [&](double size, bool fourth) {
    Points cups;
    for (int k = 0; k < 3; ++k) {
      const double angle = 2 * std::numbers::pi * k / 3 + 0.25 * u(rng);
      const double radius = size / std::sqrt(3.0) * (1 + 0.2 * u(rng));
      cups.emplace_back(radius * std::cos(angle), radius * std::sin(angle), 0);
    }
    if (fourth) {
      // Off the lines through the others by at least a tenth of the size, a little off-plane.
      for (;;) {
        const Eigen::Vector3d c(size * u(rng), size * u(rng), 0.03 * size * u(rng));
        bool clear = true;
        for (int i = 0; i < 3 && clear; ++i) {
          const Eigen::Vector3d a = cups[i], d = (cups[(i + 1) % 3] - a).normalized();
          clear = ((c - a) - (c - a).dot(d) * d).head<2>().norm() > 0.1 * size;
        }
        if (clear) {
          cups.push_back(c);
          break;
        }
      }
    }
    return cups;
  };
  int truth_first = 0, worst_iterations = 0;
  double worst = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const bool base4 = trial % 3 != 2, tool4 = trial % 3 != 1;
    Points base = fixture(300 * (1 + 0.3 * u(rng)), base4);
    const Points tool_local = fixture(150 * (1 + 0.3 * u(rng)), tool4);
    // The tool fixture faces the base (turned over), tilted up to ~20°, 150–350 mm above it.
    const Eigen::Matrix3d R =
        (Eigen::AngleAxisd(std::numbers::pi * u(rng), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(0.35 * u(rng), Eigen::Vector3d(u(rng), u(rng), 0).normalized()) *
         Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    const Eigen::Vector3d p(60 * u(rng), 60 * u(rng), 250 + 100 * u(rng));
    Points tool;
    for (const Eigen::Vector3d& c : tool_local) tool.push_back(R * c + p);
    std::vector<PhysicalLeg> extra;
    if (base4) extra.insert(extra.end(), {{3, 1}, {3, 2}});
    if (tool4) extra.insert(extra.end(), {{1, 3}, {2, 3}});
    if (base4 && tool4) extra.push_back({3, 3});
    const FourCupDkpRequest request = four_cup_distances(base, tool, design_legs_plus(extra));
    const FourCupDkpResult result = solve_four_cup_dkp(request);
    ASSERT_EQ(result.status, FourCupDkpStatus::Ok) << "trial " << trial << ": " << result.message;
    const Points expected = in_base_frame(base, tool);
    const FourCupSolution& truth = nearest(result, expected);
    const double gap = max_gap(truth.tool_cups, expected);
    truth_first += &truth == &result.solutions[0];
    worst_iterations = std::max(worst_iterations, truth.iterations);
    worst = std::max(worst, gap);
    ASSERT_LE(gap, 1e-9) << "trial " << trial;
    EXPECT_LE(max_gap(result.solutions[0].base_cups, in_base_frame(base, base)), 1e-9);
  }
  // Redundant legs single out the assembly mode: the smallest residual is the true configuration.
  EXPECT_EQ(truth_first, 2000);
  std::printf("four-cup DKP round trip: worst %.3g mm over 2000 geometries, ≤ %d iterations\n",
              worst, worst_iterations);
}

TEST(HexapodFourCup, SensitivitiesMatchFiniteDifferencesOfTheSolver) {
  const Solved solved;
  const Cell& c = solved.cell;
  const FourCupDkpRequest& request = solved.request;
  ASSERT_EQ(solved.result.status, FourCupDkpStatus::Ok) << solved.result.message;
  const FourCupSolution& truth = solved.result.solutions[0];
  ASSERT_LT(max_gap(truth.tool_cups, in_base_frame(c.base, c.tool)), 1e-9);
  // The distances as a vector in the result's order, and back.
  const auto to_request = [&](const Eigen::VectorXd& d) {
    FourCupDkpRequest r = request;
    r.base.sides = {d[0], d[1], d[2]};
    r.base.fourth = {d[3], d[4], d[5]};
    r.tool.sides = {d[6], d[7], d[8]};
    r.tool.fourth = {d[9], d[10], d[11]};
    for (size_t i = 0; i < r.legs.size(); ++i) r.legs[i].length_mm = d[12 + i];
    return r;
  };
  Eigen::VectorXd d0(12 + request.legs.size());
  d0 << request.base.sides.d12, request.base.sides.d23, request.base.sides.d31,
      (*request.base.fourth)[0], (*request.base.fourth)[1], (*request.base.fourth)[2],
      request.tool.sides.d12, request.tool.sides.d23, request.tool.sides.d31,
      (*request.tool.fourth)[0], (*request.tool.fourth)[1], (*request.tool.fourth)[2],
      Eigen::VectorXd::Zero(request.legs.size());
  for (size_t i = 0; i < request.legs.size(); ++i) d0[12 + i] = request.legs[i].length_mm;
  ASSERT_EQ(solved.result.distance_names.size(), size_t(d0.size()));
  EXPECT_EQ(solved.result.distance_names[3], "b14");
  EXPECT_EQ(solved.result.distance_names[12], "rho11");
  const auto f = [&](const Eigen::VectorXd& d) {
    // The solution continuing the true one.
    const FourCupDkpResult r = solve_four_cup_dkp(to_request(d));
    const FourCupSolution& near = nearest(r, truth.tool_cups);
    Eigen::VectorXd out(12);
    for (int j = 0; j < 4; ++j) out.segment<3>(3 * j) = near.tool_cups[j];
    return out;
  };
  const Eigen::MatrixXd numeric = test::numerical_jacobian(f, d0, 1e-4);
  EXPECT_LT((numeric - truth.sensitivity).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(HexapodFourCup, GumUncertaintyAgreesWithMonteCarloWithinOnePercent) {
  const Solved solved;
  const Cell& c = solved.cell;
  ASSERT_EQ(solved.result.status, FourCupDkpStatus::Ok) << solved.result.message;
  const FourCupSolution& s = solved.result.solutions[0];
  const uint64_t seed = 11;
  SCOPED_TRACE(seed);
  auto rng = test::seeded_rng(seed);
  const double sigma = 0.51e-3;
  const std::vector<CupUncertainty> mc =
      four_cup_uncertainty_monte_carlo(solved.request, s, sigma, 60000, rng);
  ASSERT_EQ(mc.size(), 4u);
  EXPECT_REFUSED(four_cup_uncertainty_monte_carlo(solved.request, s, 0, 100, rng), InputError,
                 "Monte Carlo needs σ > 0 and at least 2 samples (σ = 0 mm, 100 samples)");
  EXPECT_REFUSED(four_cup_uncertainty_monte_carlo(solved.request, s, sigma, 1, rng), InputError,
                 "Monte Carlo needs σ > 0 and at least 2 samples (σ = 0.00051 mm, 1 samples)");
  double worst_ratio = 0;
  for (int j = 0; j < 4; ++j) {
    SCOPED_TRACE(s.uncertainty[j].cup);
    EXPECT_NEAR(mc[j].norm / s.uncertainty[j].norm, 1, 0.01);
    worst_ratio = std::max(worst_ratio, std::abs(mc[j].norm / s.uncertainty[j].norm - 1));
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(mc[j].per_axis[a] / s.uncertainty[j].per_axis[a], 1, 0.01) << "axis " << a;
  }
  // The same cell with three cups each and the six design legs: the extra cups and legs can
  // only reduce the uncertainty of T1..T3 (more observations in a least-squares fit).
  const Points base3(c.base.begin(), c.base.begin() + 3), tool3(c.tool.begin(), c.tool.begin() + 3);
  const FourCupDkpResult three =
      solve_four_cup_dkp(four_cup_distances(base3, tool3, design_legs_plus({})));
  ASSERT_EQ(three.status, FourCupDkpStatus::Ok);
  const auto same = std::find_if(three.solutions.begin(), three.solutions.end(), [&](auto& t) {
    return max_gap(t.tool_cups, Points(s.tool_cups.begin(), s.tool_cups.begin() + 3)) < 1e-9;
  });
  ASSERT_NE(same, three.solutions.end());
  for (int j = 0; j < 3; ++j) EXPECT_LT(s.uncertainty[j].norm, same->uncertainty[j].norm);
  std::printf(
      "four-cup GUM vs Monte Carlo (60000 draws): worst |ratio − 1| = %.4f; T1..T3 norm "
      "%.3f %.3f %.3f σ (three cups: %.3f %.3f %.3f σ)\n",
      worst_ratio, s.uncertainty[0].norm, s.uncertainty[1].norm, s.uncertainty[2].norm,
      same->uncertainty[0].norm, same->uncertainty[1].norm, same->uncertainty[2].norm);
}

TEST(HexapodFourCup, NoisyDistancesStillSingleOutTheAssemblyMode) {
  // The claim of FourCupDkpResult::solutions: with readings at the gauge's σ the true mode is the
  // one with a residual at σ, every other one far above.
  const Solved solved;
  const Points truth = in_base_frame(solved.cell.base, solved.cell.tool);
  const uint64_t seed = 12;
  SCOPED_TRACE(seed);
  auto rng = test::seeded_rng(seed);
  const double sigma = 0.51e-3;
  std::normal_distribution<double> noise(0, sigma);
  double worst_rms = 0, closest_other = 1e9;
  for (int draw = 0; draw < 200; ++draw) {
    FourCupDkpRequest r = solved.request;
    for (double* d : {&r.base.sides.d12, &r.base.sides.d23, &r.base.sides.d31, &r.tool.sides.d12,
                      &r.tool.sides.d23, &r.tool.sides.d31})
      *d += noise(rng);
    for (double& d : *r.base.fourth) d += noise(rng);
    for (double& d : *r.tool.fourth) d += noise(rng);
    for (MeasuredLeg& leg : r.legs) leg.length_mm += noise(rng);
    const FourCupDkpResult result = solve_four_cup_dkp(r);
    ASSERT_EQ(result.status, FourCupDkpStatus::Ok) << result.message;
    EXPECT_LT(max_gap(result.solutions[0].tool_cups, truth), 40 * sigma) << "draw " << draw;
    worst_rms = std::max(worst_rms, result.solutions[0].rms_residual_mm);
    for (size_t k = 1; k < result.solutions.size(); ++k)
      closest_other = std::min(closest_other, result.solutions[k].rms_residual_mm);
  }
  EXPECT_LT(worst_rms, 3 * sigma);
  EXPECT_GT(closest_other, 100 * sigma);
  std::printf(
      "noisy four-cup DKP (σ = %.2g mm, 200 draws): true mode rms ≤ %.3g mm, other modes "
      "≥ %.3g mm\n",
      sigma, worst_rms, closest_other);
}

TEST(HexapodFourCup, RefusesIllPosedInputWithReasons) {
  Cell c = nominal_four_cup_cell();
  // B4 on the line B1 B2 (its midpoint): collinear with the others.
  Cell collinear = c;
  collinear.base[3] = 0.5 * (c.base[0] + c.base[1]);
  FourCupDkpResult r =
      solve_four_cup_dkp(four_cup_distances(collinear.base, collinear.tool, collinear.legs));
  EXPECT_EQ(r.status, FourCupDkpStatus::InvalidInput);
  EXPECT_NE(r.message.find("base fixture: the fourth cup B4 is collinear with B1 and B2"),
            std::string::npos)
      << r.message;
  EXPECT_EQ(r.culprit, FourCupInput::BaseFixture);
  collinear = c;
  collinear.tool[3] = c.tool[2] + 0.4 * (c.tool[2] - c.tool[1]);  // beyond T3 on the line T2 T3
  r = solve_four_cup_dkp(four_cup_distances(collinear.base, collinear.tool, collinear.legs));
  EXPECT_NE(r.message.find("tool fixture: the fourth cup T4 is collinear with T2 and T3"),
            std::string::npos)
      << r.message;
  EXPECT_EQ(r.culprit, FourCupInput::ToolFixture);

  FourCupDkpRequest request = four_cup_distances(c.base, c.tool, design_legs_plus({{2, 3}}));
  r = solve_four_cup_dkp(request);
  EXPECT_EQ(r.message,
            "base cup B4 has no leg: measure at least one leg from B4 or leave the cup out");
  EXPECT_EQ(r.culprit, FourCupInput::Legs);  // the missing leg, not the fixture
  request = four_cup_distances(c.base, c.tool, design_legs_plus({{3, 0}}));
  r = solve_four_cup_dkp(request);
  EXPECT_NE(r.message.find("tool cup T4 has no leg"), std::string::npos) << r.message;
  request = four_cup_distances(c.base, c.tool, c.legs);
  request.legs.push_back({0, 4, 300});
  EXPECT_NE(solve_four_cup_dkp(request).message.find(
                "leg B1-T5: the fixtures have cups B1..B4 and T1..T4"),
            std::string::npos);
  request = four_cup_distances(c.base, c.tool, c.legs);
  request.legs[7].length_mm = std::nan("");
  EXPECT_NE(solve_four_cup_dkp(request).message.find("leg B4-T1 = nan mm is not a positive length"),
            std::string::npos);
  request = four_cup_distances(c.base, c.tool, c.legs);
  request.base.fourth->at(1) = -2;
  r = solve_four_cup_dkp(request);
  EXPECT_NE(r.message.find("base fixture: side d24 = -2 mm"), std::string::npos);
  EXPECT_EQ(r.culprit, FourCupInput::BaseFixture);
  // Without ρ31 no base cup reaches T1 alone: no 3-3 design to start from.
  request = four_cup_distances(c.base, c.tool, c.legs);
  request.legs.erase(request.legs.begin() + 5);
  r = solve_four_cup_dkp(request);
  EXPECT_EQ(r.status, FourCupDkpStatus::InvalidInput);
  EXPECT_NE(r.message.find("do not include a 1^12 2^123 3^1 design"), std::string::npos);
  EXPECT_EQ(r.culprit, FourCupInput::Legs);
}

TEST(HexapodCupCollision, RefusesCoincidingCupsCrossingLegsAndLegsThroughCups) {
  const Cell c = nominal_four_cup_cell();
  const CupClearance clearance;  // 25 mm cups
  EXPECT_EQ(cup_collision(c.base, c.tool, c.legs, clearance), "");
  Points tool = c.tool;
  tool[2] = c.base[1] + Eigen::Vector3d(0, 0, 10);
  EXPECT_EQ(cup_collision(c.base, tool, c.legs, clearance),
            "tool cup T3 is 10.0 mm from base cup B2, closer than a cup diameter (25 mm): the cups "
            "collide");
  // The whole tool fixture below the base plane: ρ11 goes through the base plate.
  tool = c.tool;
  for (Eigen::Vector3d& t : tool) t.z() -= 400;
  EXPECT_EQ(
      cup_collision(c.base, tool, c.legs, clearance),
      "leg B1-T1 crosses the base fixture: the tool cup is on the closed side of the base plane");
  // The tool fixture turned over (cups opening upwards, away from the base).
  tool = c.tool;
  const Eigen::Vector3d mid = (c.tool[0] + c.tool[1] + c.tool[2]) / 3;
  for (Eigen::Vector3d& t : tool)
    t = mid + Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitX()) * (t - mid);
  EXPECT_NE(cup_collision(c.base, tool, c.legs, clearance).find("crosses the tool fixture"),
            std::string::npos);
  // A leg from B1 straight up past B4's column: put T1 above the far side of B2 so that ρ11
  // grazes B2's cup.
  tool = c.tool;
  const Eigen::Vector3d shift =
      c.base[0] + 2.0 * (c.base[1] - c.base[0]) + Eigen::Vector3d(0, 0, 8) - c.tool[0];
  for (Eigen::Vector3d& t : tool) t += shift;
  const std::string reason = cup_collision(c.base, tool, c.legs, clearance);
  EXPECT_NE(reason.find("leg B1-T1 passes"), std::string::npos) << reason;
  EXPECT_NE(reason.find("from cup B2, within a cup radius (12.5 mm)"), std::string::npos) << reason;
}

TEST(HexapodCupCollision, ScreeningRefusesTheFiftyFourPosesOfAThreeHundredMillimetreToolTriangle) {
  // Issue 20: with a 300 mm tool triangle, 54 of the 72 planned poses put a tool cup on a base cup.
  const HexapodGeometry big{{300, 300, 300}, {300, 300, 300}, 300};
  const std::vector<HexapodPose> poses = enumerate_poses(big, ToolRelabelling::Rotations);
  ASSERT_EQ(poses.size(), 72u);
  const PoseScreening s = screen_poses(poses, big, deg2rad(30), 50, CupClearance{});
  int coincide = 0;
  for (const auto& r : s.refused)
    coincide += r.reason.find("the cups coincide") != std::string::npos;
  EXPECT_EQ(coincide, 54);
  // The other 18: 9 whose legs go through the tool plate (next test), 9 that can be set up.
  EXPECT_EQ(s.refused.size(), 63u);
  for (const auto& k : s.kept)
    for (const auto& r : s.refused) EXPECT_NE(k.label, r.pose.label);
  std::printf("300 mm tool triangle: %zu refused (%d coinciding cups), %zu kept\n",
              s.refused.size(), coincide, s.kept.size());
  EXPECT_REFUSED(
      screen_poses(poses, big, deg2rad(30), 50, CupClearance{0}), InputError,
      "--cup-diameter-mm (cup_diameter_mm): expected a positive cup diameter in mm, found 0");
}

TEST(HexapodCupCollision, DefaultGeometryRefusesThePosesWhoseToolCupsFaceAwayFromTheBase) {
  // With the tool cups numbered counter-clockwise seen from the side they open to
  // (fixture.hpp), a pose whose tool-fixture normal points away from the base cups' centroid
  // has the ballbar going through the tool plate. Independent criterion: the centroids.
  const HexapodGeometry g;  // 300 / 150 / 300
  const std::vector<HexapodPose> poses = enumerate_poses(g, ToolRelabelling::Rotations);
  const PoseScreening s = screen_poses(poses, g, deg2rad(30), 50, CupClearance{});
  const Cups<double> base = fixture_cups(g.base, "base fixture");
  int facing_away = 0;
  for (const HexapodPose& p : poses) {
    const bool away =
        (centroid(base) - centroid(p.tool_cups)).dot(frame_from_cups(p.tool_cups).R.col(2)) < 0;
    facing_away += away;
    const bool refused = std::any_of(s.refused.begin(), s.refused.end(),
                                     [&](const auto& r) { return r.pose.label == p.label; });
    EXPECT_EQ(refused, away) << p.label << " " << p.description();
  }
  EXPECT_EQ(facing_away, 36);  // assembly modes 1 and 3 of the enumeration
  for (const auto& r : s.refused) {
    EXPECT_TRUE(r.pose.mode == 1 || r.pose.mode == 3) << r.pose.label;
    EXPECT_NE(r.reason.find("crosses the tool fixture"), std::string::npos) << r.reason;
  }
  std::printf(
      "rotation-only numbering: %zu of 72 refused (tool cups facing away), %zu kept after "
      "pruning\n",
      s.refused.size(), s.kept.size());
  // The default numbering turns those 36 to face the base: nothing refused.
  EXPECT_TRUE(screen_poses(enumerate_poses(g), g, deg2rad(30), 50, CupClearance{}).refused.empty());
}

TEST(HexapodCupCollision, FacingBaseRelabellingGivesSeventyTwoPosesThatCanBeSetUp) {
  const HexapodGeometry g{{301, 299, 300.5}, {150, 151, 149.5}, 300};
  const std::vector<HexapodPose> rotations = enumerate_poses(g, ToolRelabelling::Rotations);
  const std::vector<HexapodPose> facing = enumerate_poses(g);  // the default
  ASSERT_EQ(facing.size(), 72u);
  const Cups<double> base = fixture_cups(g.base, "base fixture");
  const Cups<double> tool = fixture_cups(g.tool, "tool fixture");
  for (size_t i = 0; i < facing.size(); ++i) {
    const HexapodPose& p = facing[i];
    SCOPED_TRACE(p.label + " " + p.description());
    // Modes 2 and 4 keep the rotations; modes 1 and 3 take the mirrored numbering.
    EXPECT_EQ(p.design.tool_mirrored(), p.mode == 1 || p.mode == 3);
    if (!p.design.tool_mirrored()) {
      EXPECT_LT(max_gap(Points(p.tool_cups.begin(), p.tool_cups.end()),
                        Points(rotations[i].tool_cups.begin(), rotations[i].tool_cups.end())),
                1e-12);
    }
    // Still a pose of these fixtures with every leg at 300 mm.
    for (const PhysicalLeg& leg : p.legs)
      EXPECT_NEAR((base[leg.base] - p.tool_cups[leg.tool]).norm(), 300, 1e-9);
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b)
        EXPECT_NEAR((p.tool_cups[a] - p.tool_cups[b]).norm(), (tool[a] - tool[b]).norm(), 1e-9);
  }
  const PoseScreening s = screen_poses(facing, g, deg2rad(30), 50, CupClearance{});
  EXPECT_TRUE(s.refused.empty()) << s.refused.front().pose.label << ": "
                                 << s.refused.front().reason;
  std::printf(
      "facing-base relabelling: 72 poses, %zu refused, %zu kept after pruning (30°, 50 mm)\n",
      s.refused.size(), s.kept.size());
  const HexapodGeometry big{{300, 300, 300}, {300, 300, 300}, 300};
  const PoseScreening b = screen_poses(enumerate_poses(big, ToolRelabelling::FacingBase), big,
                                       deg2rad(30), 50, CupClearance{});
  // The cups coincide in the same 54 poses as with the rotations only (issue 20's count).
  EXPECT_EQ(b.refused.size(), 54u);
  for (const auto& r : b.refused) EXPECT_NE(r.reason.find("the cups coincide"), std::string::npos);
  std::printf("300 mm tool triangle, facing-base relabelling: %zu refused, %zu kept\n",
              b.refused.size(), b.kept.size());
}

}  // namespace
}  // namespace robcal::hexapod
