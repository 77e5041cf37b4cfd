// Configuration design (docs/method/05-observability.md §1): observability indices, rank-r
// information updates, candidates, selection quality against random sets and the continuous
// D-optimum.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numeric>

#include "../src/design/leverage_cache.hpp"
#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/design/candidates.hpp"
#include "robcal/design/design_matrix.hpp"
#include "robcal/design/observability.hpp"
#include "robcal/design/selection.hpp"
#include "robcal/identify/unknowns.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

Eigen::MatrixXd random_matrix(std::mt19937_64& rng, int rows, int cols) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd A(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) A(i, j) = normal(rng);
  return A;
}

TEST(DesignIndices, DiagonalJacobianGivesItsEntriesAsSingularValues) {
  // σ = 1, 2, 4 from one configuration: O1 = 8^(1/3) = 2, O2 = 1/4, O3 = 1, O4 = 1/4,
  // O5 = 1/(1 + 1/2 + 1/4) = 4/7.
  const Eigen::Vector3d s(1, 2, 4);
  const ObservabilityIndices o = observability_indices(Eigen::MatrixXd(s.asDiagonal()), 1);
  EXPECT_NEAR(o.O1, 2.0, 1e-12);
  EXPECT_NEAR(o.O2, 0.25, 1e-12);
  EXPECT_NEAR(o.O3, 1.0, 1e-12);
  EXPECT_NEAR(o.O4, 0.25, 1e-12);
  EXPECT_NEAR(o.O5, 4.0 / 7.0, 1e-12);
}

TEST(DesignIndices, OrthogonalColumnsOfTwoConfigurations) {
  // Columns orthogonal with norms 3, 4, 12 (rows of two 3-row configurations):
  // σ = {12, 4, 3}; O1 = (144)^(1/3)/√2, O2 = 3/12, O3 = 3, O4 = 9/12, O5 = 1/(1/3+1/4+1/12).
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, 3);
  J(0, 0) = 3;        // column 0: norm 3
  J(1, 1) = 4 * 0.6;  // column 1: (0.6, 0.8)·4 on rows 1 and 4
  J(4, 1) = 4 * 0.8;
  J(2, 2) = 12.0 / std::sqrt(2.0);  // column 2: rows 2 and 5
  J(5, 2) = -12.0 / std::sqrt(2.0);
  const ObservabilityIndices o = observability_indices(J, 2);
  EXPECT_NEAR(o.O1, std::cbrt(144.0) / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(o.O2, 0.25, 1e-12);
  EXPECT_NEAR(o.O3, 3.0, 1e-12);
  EXPECT_NEAR(o.O4, 0.75, 1e-12);
  EXPECT_NEAR(o.O5, 1.0 / (1.0 / 3 + 1.0 / 4 + 1.0 / 12), 1e-12);
}

TEST(DesignIndices, RankDeficientJacobianScoresZeroNotNaN) {
  Eigen::MatrixXd J(4, 3);
  J << 1, 2, 3, 4, 5, 9, 0, 1, 1, 2, 0, 2;  // column 2 = column 0 + column 1
  const ObservabilityIndices o = observability_indices(J, 2);
  EXPECT_EQ(o.O1, 0.0);
  EXPECT_EQ(o.O2, 0.0);
  EXPECT_EQ(o.O3, 0.0);
  EXPECT_EQ(o.O4, 0.0);
  EXPECT_EQ(o.O5, 0.0);
  // Fewer rows than parameters: rank deficient too.
  EXPECT_EQ(observability_indices(Eigen::MatrixXd::Identity(2, 3), 1).O1, 0.0);
}

TEST(DesignInformation, RankThreeUpdatesMatchRecomputation) {
  SCOPED_TRACE("seed 7");
  auto rng = test::seeded_rng(7);
  const int m = 12;
  InformationMatrix info(m, 1e-6);
  Eigen::MatrixXd M = Eigen::MatrixXd::Identity(m, m) * 1e-6;
  std::vector<Eigen::MatrixXd> blocks;
  for (int k = 0; k < 20; ++k) {
    blocks.push_back(random_matrix(rng, 3, m));
    const double predicted_gain = info.gain(blocks.back());
    const double before = info.log_det();
    info.add(blocks.back());
    M += blocks.back().transpose() * blocks.back();
    EXPECT_NEAR(info.log_det() - before, predicted_gain, 1e-9 * std::abs(predicted_gain));
  }
  for (int k = 0; k < 6; ++k) {
    const Eigen::MatrixXd& A = blocks[static_cast<size_t>(3 * k)];
    const double predicted_loss = info.loss(A);
    const double before = info.log_det();
    info.remove(A);
    M -= A.transpose() * A;
    EXPECT_NEAR(info.log_det() - before, predicted_loss, 1e-9 * std::abs(predicted_loss));
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(M);
  const Eigen::MatrixXd inverse = llt.solve(Eigen::MatrixXd::Identity(m, m));
  const double log_det = 2 * llt.matrixLLT().diagonal().array().log().sum();
  EXPECT_NEAR(info.log_det(), log_det, 1e-9 * std::abs(log_det));
  EXPECT_LE((info.inverse() - inverse).norm(), 1e-9 * inverse.norm());
  EXPECT_LE((info.matrix() - M).norm(), 1e-12 * M.norm());
}

TEST(DesignInformation, RankOneUpdatesMatchRecomputation) {
  auto rng = test::seeded_rng(11);
  const int m = 5;
  Eigen::MatrixXd start = random_matrix(rng, 8, m);
  Eigen::MatrixXd M = start.transpose() * start;
  InformationMatrix info(M);
  const Eigen::MatrixXd a = random_matrix(rng, 1, m);
  // Matrix determinant lemma by hand: det(M + aᵀa) = det M · (1 + a M⁻¹ aᵀ).
  const double lemma = std::log1p((a * M.inverse() * a.transpose())(0, 0));
  EXPECT_NEAR(info.gain(a), lemma, 1e-12);
  info.add(a);
  M += a.transpose() * a;
  EXPECT_LE((info.inverse() - M.inverse()).norm(), 1e-9 * M.inverse().norm());
  EXPECT_NEAR(info.log_det(), std::log(M.determinant()),
              1e-9 * std::abs(std::log(M.determinant())));
  // Removing a block that would make M singular is reported as −∞, not NaN.
  InformationMatrix single(Eigen::MatrixXd(a.transpose() * a + Eigen::MatrixXd::Identity(m, m)));
  EXPECT_GT(single.loss(a), -std::numeric_limits<double>::infinity());
  InformationMatrix rank_one(m, 1.0);
  EXPECT_NEAR(rank_one.gain(a), std::log1p(a.squaredNorm()), 1e-12);
}

TEST(DesignInformation, LeverageBlocksFollowUpdatesAsRecomputation) {
  // A random design big enough for the two-thread sweep; blocks G_i = A_i M⁻¹ A_iᵀ kept by the
  // rank-3 updates must equal the blocks computed from scratch from an independently summed M.
  auto rng = test::seeded_rng(13);
  const int n = 2500, m = 11;
  DesignMatrix design;
  design.rows_per_candidate = 3;
  design.rows = random_matrix(rng, 3 * n, m);
  InformationMatrix info(m, 1e-3);
  LeverageCache<3> cache(design, 1e-3);
  Eigen::MatrixXd M = Eigen::MatrixXd::Identity(m, m) * 1e-3;
  const auto check = [&](const char* when) {
    const Eigen::MatrixXd P = M.inverse();
    double worst = 0;
    for (int i = 0; i < n; i += 7) {
      const Eigen::MatrixXd G = design.block(i) * P * design.block(i).transpose();
      worst = std::max(worst, (cache.block(i) - G).norm() / G.norm());
    }
    EXPECT_LT(worst, 1e-9) << when;
  };
  for (int k = 0; k < 12; ++k) {
    const auto u = info.factor(design.block(k), +1.0);
    info.apply(design.block(k), +1.0, u);
    cache.update(u.W, +1.0);
    M += design.block(k).transpose() * design.block(k);
  }
  check("after 12 additions");
  // A removal scored first (projections kept), then applied.
  const auto removal = info.factor(design.block(4), -1.0);
  cache.project(removal.W);
  const Eigen::Matrix3d b = design.block(100) * removal.W;
  EXPECT_LT((cache.projection(100) - b).norm(), 1e-12 * b.norm());
  info.apply(design.block(4), -1.0, removal);
  cache.apply(-1.0);
  M -= design.block(4).transpose() * design.block(4);
  check("after a removal");
  // Gain and loss from the blocks (determinant lemma) against recomputed log-determinants.
  const auto log_det = [](const Eigen::MatrixXd& X) { return std::log(X.determinant()); };
  const Eigen::MatrixXd A = design.block(200);
  EXPECT_NEAR(std::log((Eigen::Matrix3d::Identity() + cache.block(200)).determinant()),
              log_det(M + A.transpose() * A) - log_det(M), 1e-9);
  const Eigen::MatrixXd C = design.block(7);
  EXPECT_NEAR(std::log((Eigen::Matrix3d::Identity() - cache.block(7)).determinant()),
              log_det(M - C.transpose() * C) - log_det(M), 1e-9);
  // Recomputation from the tracked inverse agrees with the updated blocks.
  LeverageCache<3> fresh(design, info.inverse());
  for (int i = 0; i < n; i += 97)
    EXPECT_LT((fresh.block(i) - cache.block(i)).norm(), 1e-9 * fresh.block(i).norm());
}

// Shared IRB 120 candidate set: 5000 feasible configurations, published constraints, the
// reference tool (three SMRs), points.
struct Irb120Design {
  RobotModel model = load_robot("abb-irb120");
  Tool tool = load_tool(test::data_path("irb120-published/tool.yaml"));
  std::vector<Candidate> candidates;
  DesignMatrix design;

  explicit Irb120Design(int count, uint64_t seed = 1) {
    auto rng = test::seeded_rng(seed);
    CandidateOptions options;
    options.count = count;
    candidates = generate_candidates(model, tool, options, rng).candidates;
    DesignSettings settings;
    settings.parameters = level_parameters(CalibrationLevel::Full);
    design = build_design_matrix(model, tool, candidates, settings);
  }
};

const Irb120Design& irb120_5000() {
  static const Irb120Design d(5000);
  return d;
}

TEST(DesignCandidates, RespectLimitsConstraintsFloorAndVisibility) {
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = load_tool(test::data_path("irb120-published/tool.yaml"));
  auto rng = test::seeded_rng(3);
  CandidateOptions options;
  options.count = 300;
  options.floor_z_mm = 100;
  // An instrument that sees only target 2, and only when it is in front of the robot (x > 0).
  options.visible = [](const Pose<double>& world_T_flange, int target) {
    return target == 1 && world_T_flange.p.x() > 0;
  };
  const CandidateSet set = generate_candidates(model, tool, options, rng);
  ASSERT_EQ(set.candidates.size(), 300u);
  EXPECT_GT(set.below_floor + set.not_visible, 0);
  const JointConstraints pub = published_joint_constraints();
  for (const Candidate& c : set.candidates) {
    EXPECT_EQ(c.target, 1);
    EXPECT_TRUE(model.within_limits(c.joints));
    for (int j = 0; j < kJointCount; ++j) {
      EXPECT_GE(c.joints[j], pub.range[j].lower);
      EXPECT_LE(c.joints[j], pub.range[j].upper);
    }
    const Pose<double> flange = flange_pose(model, tool.payload, model.nominal(), c.joints);
    EXPECT_GT(flange.p.x(), 0);
    for (const Target& t : tool.targets) EXPECT_GE((flange * t.position_mm).z(), 100);
  }
  // Same seed, same candidates.
  auto rng2 = test::seeded_rng(3);
  const CandidateSet again = generate_candidates(model, tool, options, rng2);
  EXPECT_EQ(again.candidates[17].joints, set.candidates[17].joints);
}

TEST(DesignCandidates, ClearErrorsWhenNothingIsFeasible) {
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = load_tool(test::data_path("irb120-published/tool.yaml"));
  auto rng = test::seeded_rng(5);
  CandidateOptions options;
  options.count = 10;
  options.draws_per_candidate = 20;
  options.visible = [](const Pose<double>&, int) { return false; };
  try {
    generate_candidates(model, tool, options, rng);
    FAIL() << "an instrument that sees nothing must be an error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "--instrument");
    EXPECT_NE(std::string(e.what()).find("instrument can see"), std::string::npos) << e.what();
  }
  options.visible = nullptr;
  options.floor_z_mm = 5000;  // above the robot's reach
  EXPECT_REFUSED(generate_candidates(model, tool, options, rng), InputError,
                 "--floor-mm: no feasible candidate configuration in");
  options.floor_z_mm = 0;
  options.constraints.range[2] = {deg2rad(80), deg2rad(90)};  // IRB 120 joint 3 stops at 70°
  try {
    generate_candidates(model, tool, options, rng);
    FAIL() << "an empty joint range must be an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("joint 3"), std::string::npos) << e.what();
  }
  options.count = 1'000'000'000;  // `plan --candidates 1e9`: refused before any allocation
  EXPECT_REFUSED(generate_candidates(model, tool, options, rng), InputError,
                 "--candidates: expected 1 to 200000 candidates");
  EXPECT_REFUSED(joint_constraints_preset("loose"), InputError,
                 "unknown constraint preset 'loose', expected 'published' or 'none'");
}

TEST(DesignMatrixTest, FullModelDropsLink3DAndScalesColumns) {
  const Irb120Design& d = irb120_5000();
  ASSERT_EQ(d.design.candidates(), 5000);
  // Axes 2 and 3 are parallel: link3.d depends on link2.d and is the one dropped
  // (docs/method/03-error-model.md).
  ASSERT_EQ(d.design.dropped.size(), 1u);
  EXPECT_EQ(parameter_table()[static_cast<size_t>(d.design.dropped[0])].name, "link3.d");
  EXPECT_EQ(d.design.columns(), 30);
  for (int j = 0; j < d.design.columns(); ++j)
    EXPECT_NEAR(d.design.rows.col(j).norm() / std::sqrt(5000.0), 1.0, 1e-12);
}

TEST(DesignMatrixTest, PoseRowsMatchFiniteDifferencesOfTheToolPose) {
  const RobotModel model = load_robot("abb-irb120");
  Tool tool = load_tool(test::data_path("irb120-published/tool.yaml"));
  tool.flange_T_tcp.translation() = Eigen::Vector3d(10, 20, 150);
  tool.flange_T_tcp.linear() =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  Candidate c;
  c.joints << 0.3, 0.5, -0.4, 1.0, 0.7, -0.5;
  c.target = -1;
  DesignSettings settings;
  settings.kind = MeasurementKind::Poses;
  settings.orientation_lever_mm = 100;
  ParameterVector params = model.nominal();
  for (int i = kComplianceOffset; i < kScaleOffset; ++i) params[i] = 1e-7;  // FD needs c ≠ 0
  const Eigen::MatrixXd J = candidate_jacobian(model, tool, params, c, settings);
  const Eigen::Isometry3d tcp = tool.flange_T_tcp;
  const auto tool_pose = [&](const Eigen::VectorXd& x) {
    const Pose<double> f = flange_pose(model, tool.payload, ParameterVector(x), c.joints);
    return std::pair<Eigen::Matrix3d, Eigen::Vector3d>{f.R * tcp.linear(), f * tcp.translation()};
  };
  const auto [R0, p0] = tool_pose(params);
  // Position, and the rotation vector of R(x)·R0ᵀ times the lever arm.
  const auto f = [&](const Eigen::VectorXd& x) {
    const auto [R, p] = tool_pose(x);
    const Eigen::AngleAxisd aa(R * R0.transpose());
    Eigen::VectorXd out(6);
    out << p, 100.0 * aa.angle() * aa.axis();
    return out;
  };
  const Eigen::MatrixXd numeric = test::numerical_jacobian(f, params, 1e-7);
  for (int col = 0; col < kParameterCount; ++col) {
    // Compliance columns need a larger step: use a relative check on their scale.
    const double scale = std::max(1.0, numeric.col(col).norm());
    EXPECT_LE((J.col(col) - numeric.col(col)).norm(), 2e-5 * scale) << "column " << col;
  }
}

TEST(DesignSelection, DOptimalBeatsRandomAndIsNearTheContinuousOptimum) {
  const Irb120Design& d = irb120_5000();
  const Selection fast = select_d_optimal(d.design, 40);
  ASSERT_EQ(fast.chosen.size(), 40u);
  const ObservabilityIndices chosen = observability_indices(d.design, fast.chosen);

  // 20 random 40-sets from the same candidates.
  auto rng = test::seeded_rng(2);
  std::vector<int> all(5000);
  std::iota(all.begin(), all.end(), 0);
  const ContinuousDesign optimum = d_optimal_continuous(d.design);
  ASSERT_TRUE(optimum.converged);
  double best_random_o1 = 0, mean_random_eff = 0;
  for (int k = 0; k < 20; ++k) {
    std::shuffle(all.begin(), all.end(), rng);
    const std::vector<int> random(all.begin(), all.begin() + 40);
    best_random_o1 = std::max(best_random_o1, observability_indices(d.design, random).O1);
    mean_random_eff += d_efficiency(d.design, random, optimum) / 20;
  }
  const double efficiency = d_efficiency(d.design, fast.chosen, optimum);
  std::printf(
      "[ design ] IRB 120 full, points, 40 of 5000: O1 selected %.4f, best of 20 random "
      "%.4f; D-efficiency selected %.4f, random mean %.4f (continuous gap %.1e, %d "
      "iterations)\n",
      chosen.O1, best_random_o1, efficiency, mean_random_eff, optimum.gap, optimum.iterations);
  RecordProperty("d_efficiency", std::to_string(efficiency));
  EXPECT_GT(chosen.O1, best_random_o1);
  EXPECT_GE(efficiency, 0.95);
  EXPECT_LT(mean_random_eff, efficiency);
}

TEST(DesignSelection, PublishedExchangeImprovesOnItsStart) {
  const Irb120Design d(150);
  auto rng = test::seeded_rng(4);
  const Selection published = select_published_exchange(d.design, 30, rng);
  ASSERT_EQ(published.chosen.size(), 30u);
  std::vector<int> unique = published.chosen;
  std::sort(unique.begin(), unique.end());
  EXPECT_EQ(std::unique(unique.begin(), unique.end()), unique.end());
  const Selection fast = select_d_optimal(d.design, 30);
  const double o1_published = observability_indices(d.design, published.chosen).O1;
  const double o1_fast = observability_indices(d.design, fast.chosen).O1;
  // Random 30-sets of these candidates for comparison.
  auto rng2 = test::seeded_rng(5);
  std::vector<int> all(150);
  std::iota(all.begin(), all.end(), 0);
  double best_random = 0;
  for (int k = 0; k < 10; ++k) {
    std::shuffle(all.begin(), all.end(), rng2);
    best_random = std::max(
        best_random,
        observability_indices(d.design, std::vector<int>(all.begin(), all.begin() + 30)).O1);
  }
  std::printf(
      "[ design ] 30 of 150: O1 published exchange %.4f, fast D-optimal %.4f, best "
      "random %.4f\n",
      o1_published, o1_fast, best_random);
  EXPECT_GT(o1_published, best_random);
  EXPECT_GE(o1_fast, 0.98 * o1_published);
}

TEST(DesignSelection, FastMatchesOrBeatsThePublishedExchangeOnTheSameCandidates) {
  // O1 = det(JᵀJ)^(1/2m)/√n: at a fixed count the larger log det is the larger O1. Small
  // candidate sets, where local optima are closest: every candidate seed 100–114 at 25 of 150
  // with three published starts, and at 40 of 300 the five sets (of 20 tried, two starts each)
  // where a single descent, without restarts, ended below a published run (it did in 8 of 117
  // such trials, by up to 0.11 % of O1).
  // With the restarts the fast selection is at least as good in all but one case (40 of 300,
  // seed 105, published start 8: 0.0042 % lower, a different local optimum 6 configurations
  // away), so the bound checked is "never more than 0.01 % of O1 below", and the strict
  // losses are counted.
  struct Case {
    int candidates, count;
    uint64_t candidate_seed, published_seed;
  };
  std::vector<Case> cases;
  for (uint64_t c = 100; c < 115; ++c)
    for (uint64_t p : {7u, 8u, 9u}) cases.push_back({150, 25, c, p});
  for (uint64_t c : {105u, 108u, 109u, 202u, 208u}) cases.push_back({300, 40, c, 8});
  int strictly_below = 0;
  for (const Case& k : cases) {
    SCOPED_TRACE(::testing::Message()
                 << k.count << " of " << k.candidates << ", candidate seed " << k.candidate_seed
                 << ", published seed " << k.published_seed);
    const Irb120Design d(k.candidates, k.candidate_seed);
    auto rng = test::seeded_rng(k.published_seed);
    const Selection published = select_published_exchange(d.design, k.count, rng);
    const Selection fast = select_d_optimal(d.design, k.count);
    ASSERT_EQ(published.chosen.size(), static_cast<size_t>(k.count));
    ASSERT_EQ(fast.chosen.size(), static_cast<size_t>(k.count));
    EXPECT_EQ(fast.restarts, 5);
    // Both indices recomputed here from the chosen rows.
    const double o1_fast = observability_indices(d.design, fast.chosen).O1;
    const double o1_published = observability_indices(d.design, published.chosen).O1;
    EXPECT_GE(o1_fast, o1_published * (1 - 1e-4));
    if (information_log_det(d.design, fast.chosen) <
        information_log_det(d.design, published.chosen) - 1e-9) {
      ++strictly_below;
      std::printf("[ design ] %d of %d, seeds %d/%d: fast O1 %.6f below published %.6f\n", k.count,
                  k.candidates, static_cast<int>(k.candidate_seed),
                  static_cast<int>(k.published_seed), o1_fast, o1_published);
    }
  }
  std::printf("[ design ] fast below the published exchange in %d of %zu cases\n", strictly_below,
              cases.size());
  EXPECT_LE(strictly_below, 1);
}

TEST(DesignSelection, RidgeKeptThroughTheExchangeLeavesTheExactLogDetAndNoBetterSwap) {
  // The search keeps a 1e-6 ridge on M throughout. The reported log det must be the exact one
  // of the chosen set (here recomputed by LDLᵀ of Σ A_iᵀA_i over the rows of the chosen
  // candidates), and the ridge must not have steered the exchange off the exact optimum: no
  // single swap of a chosen for an unchosen candidate raises the exact log det.
  const Irb120Design d(150);
  const Selection fast = select_d_optimal(d.design, 30);
  const int R = d.design.rows_per_candidate;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(d.design.columns(), d.design.columns());
  for (int i : fast.chosen) {
    const Eigen::MatrixXd A = d.design.rows.middleRows(i * R, R);
    M += A.transpose() * A;
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(M);
  EXPECT_NEAR(fast.log_det, ldlt.vectorD().array().log().sum(), 1e-9 * std::abs(fast.log_det));

  std::vector<char> chosen(150, 0);
  for (int i : fast.chosen) chosen[static_cast<size_t>(i)] = 1;
  double best_gain = -1e300;
  for (size_t out = 0; out < fast.chosen.size(); ++out)
    for (int in = 0; in < 150; ++in) {
      if (chosen[static_cast<size_t>(in)]) continue;
      std::vector<int> swapped = fast.chosen;
      swapped[out] = in;
      best_gain = std::max(best_gain, information_log_det(d.design, swapped) - fast.log_det);
    }
  std::printf("[ design ] 30 of 150: log det %.6f, best single swap changes it by %.3e\n",
              fast.log_det, best_gain);
  EXPECT_LE(best_gain, 1e-6);
}

TEST(DesignSelection, CountBelowIdentifiableParametersIsAnError) {
  const Irb120Design d(200);
  try {
    select_d_optimal(d.design, 9);  // 27 equations for 30 parameters
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "--count");
    EXPECT_NE(std::string(e.what()).find("at least 10"), std::string::npos) << e.what();
  }
  EXPECT_REFUSED(select_d_optimal(d.design, 201), InputError,
                 "--count: asked for 201 configurations but only 200 feasible candidates");
}

// The multiplicative algorithm as written in the literature, with M⁻¹ formed explicitly and
// d_i = tr(A_i M⁻¹ A_iᵀ) summed entry by entry, the step w_i ← w_i (d_i/m)^λ renormalised:
// d_optimal_continuous (which forms only the lower triangle of M, takes d_i as |L⁻¹ A_iᵀ|² and
// steps with λ = 2, retreating to λ = 1 when log det falls) must follow the same iterates.
ContinuousDesign straightforward_continuous(const DesignMatrix& design, double tolerance,
                                            double power) {
  const int n = design.candidates();
  const double m = design.columns();
  const auto information = [&](const Eigen::VectorXd& weights) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(design.columns(), design.columns());
    for (int i = 0; i < n; ++i)
      if (weights[i] > 0) M += weights[i] * design.block(i).transpose() * design.block(i);
    return M;
  };
  ContinuousDesign out;
  out.weights = Eigen::VectorXd::Constant(n, 1.0 / n);
  Eigen::VectorXd previous_weights;
  double previous_log_det = 0;
  double step_power = power;
  for (out.iterations = 0; out.iterations < 20000; ++out.iterations) {
    Eigen::MatrixXd M = information(out.weights);
    out.log_det = std::log(M.determinant());
    if (previous_weights.size() > 0 && step_power != 1 && !(out.log_det >= previous_log_det)) {
      // Downhill: the classical step from the design before.
      out.weights = previous_weights;
      M = information(out.weights);
      out.log_det = std::log(M.determinant());
      step_power = 1;
      ++out.retreats;
    } else {
      previous_weights = out.weights;
      previous_log_det = out.log_det;
      step_power = power;
    }
    const Eigen::MatrixXd M_inverse = M.inverse();
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    double d_max = 0;
    for (int i = 0; i < n; ++i) {
      if (out.weights[i] == 0) continue;
      d[i] = (design.block(i) * M_inverse * design.block(i).transpose()).trace();
      d_max = std::max(d_max, d[i]);
    }
    out.gap = d_max / m - 1;
    if (out.gap <= tolerance) {
      out.converged = true;
      break;
    }
    const double eps = out.gap;
    const double h = 1 + eps / 2 - std::sqrt(eps * (4 + eps - 4 / m)) / 2;
    for (int i = 0; i < n; ++i) {
      if (out.weights[i] == 0) continue;
      out.weights[i] = d[i] < m * h ? 0 : out.weights[i] * std::pow(d[i] / m, step_power);
    }
    out.weights /= out.weights.sum();
  }
  return out;
}

TEST(DesignSelection, ContinuousOptimumFollowsTheStraightforwardMultiplicativeAlgorithm) {
  const Irb120Design d(300);
  for (const double tolerance : {1e-2, 1e-3}) {
    const ContinuousDesign fast = d_optimal_continuous(d.design, tolerance);
    const ContinuousDesign plain = straightforward_continuous(d.design, tolerance, 2);
    ASSERT_TRUE(plain.converged);
    EXPECT_TRUE(fast.converged);
    EXPECT_EQ(fast.iterations, plain.iterations);
    EXPECT_EQ(fast.retreats, plain.retreats);
    EXPECT_NEAR(fast.log_det, plain.log_det, 1e-9);
    EXPECT_NEAR(fast.gap, plain.gap, 1e-9);
    EXPECT_LT((fast.weights - plain.weights).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_EQ((fast.weights.array() > 0).count(), (plain.weights.array() > 0).count());
  }
}

// The accelerated step reaches the optimum of the classical algorithm (λ = 1, proven monotone):
// by the equivalence theorem both log dets lie within m·gap below the optimum's, and the
// accelerated run needs fewer iterations.
// A larger exponent overshoots (λ = 4 here): each step that lowers log det is taken again with
// λ = 1, in both implementations alike, and the run still converges.
TEST(DesignSelection, ContinuousOptimumRetreatsFromADownhillStep) {
  const Irb120Design d(300);
  const ContinuousDesign fast = d_optimal_continuous(d.design, 1e-3, 20000, 4);
  const ContinuousDesign plain = straightforward_continuous(d.design, 1e-3, 4);
  ASSERT_TRUE(plain.converged);
  EXPECT_TRUE(fast.converged);
  EXPECT_GT(plain.retreats, 0);
  EXPECT_EQ(fast.retreats, plain.retreats);
  EXPECT_EQ(fast.iterations, plain.iterations);
  EXPECT_NEAR(fast.log_det, plain.log_det, 1e-9);
  EXPECT_LT((fast.weights - plain.weights).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(DesignSelection, AcceleratedContinuousOptimumMatchesTheClassicalOne) {
  const Irb120Design d(300);
  const double m = d.design.columns();
  const ContinuousDesign fast = d_optimal_continuous(d.design, 1e-3);
  const ContinuousDesign classical = straightforward_continuous(d.design, 1e-3, 1);
  ASSERT_TRUE(fast.converged);
  ASSERT_TRUE(classical.converged);
  EXPECT_LE(fast.log_det, classical.log_det + m * classical.gap + 1e-9);
  EXPECT_LE(classical.log_det, fast.log_det + m * fast.gap + 1e-9);
  EXPECT_LT(fast.iterations, classical.iterations);
  std::printf(
      "[ design ] continuous optimum, 300 candidates, gap 1e-3: %d iterations "
      "accelerated (%d retreats), %d classical\n",
      fast.iterations, fast.retreats, classical.iterations);
}

}  // namespace
}  // namespace robcal
