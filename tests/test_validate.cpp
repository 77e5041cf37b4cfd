// Validation (docs/method/09-validation.md): statistics against hand-computed values, all-pairs
// distance errors against a naive double loop and across thread counts, position/orientation
// errors, the rigid base fit, and the reference data set's noise floor.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/validate/ballbar_error.hpp"
#include "robcal/validate/base_fit.hpp"
#include "robcal/validate/error_statistics_json.hpp"
#include "robcal/validate/validation.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

TEST(ValidateStatistics, HandComputed) {
  const std::vector<double> errors = {1, 2, 3, 4};
  const ErrorStatistics s = error_statistics(errors);
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  // Population std: sqrt(((1.5² + 0.5²)·2)/4) = sqrt(1.25).
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(s.mean_plus_3std(), 2.5 + 3 * std::sqrt(1.25));
  EXPECT_EQ(s.min, 1);
  EXPECT_EQ(s.max, 4);

  const ErrorStatistics one = error_statistics(std::vector<double>{0.7});
  EXPECT_EQ(one.mean, 0.7);
  EXPECT_EQ(one.std, 0.0);
  EXPECT_EQ(error_statistics({}).count, 0u);
  EXPECT_EQ(error_statistics({}).mean, 0.0);
}

// The one JSON form: every key names its unit, and rounding applies only when asked for.
TEST(ValidateStatistics, JsonKeysCarryTheUnit) {
  const ErrorStatistics s = error_statistics(std::vector<double>{0.5, 1.5});
  const nlohmann::json mm = error_statistics_json(s, "mm");
  EXPECT_EQ(mm, (nlohmann::json{{"count", 2},
                                {"mean_mm", 1.0},
                                {"std_mm", 0.5},
                                {"mean_plus_3std_mm", 2.5},
                                {"min_mm", 0.5},
                                {"max_mm", 1.5}}));
  const nlohmann::json deg =
      error_statistics_json(error_statistics(std::vector<double>{1.0 / 3}), "deg", 3);
  EXPECT_EQ(deg["mean_deg"].get<double>(), 0.333);
  EXPECT_EQ(deg["mean_plus_3std_deg"].get<double>(), 0.333);
  EXPECT_FALSE(deg.contains("mean_mm"));
}

TEST(ValidateHistogram, BinsClampAndMerge) {
  const std::vector<double> values = {0, 0.1, 0.25, 0.5, 0.99, 1.0, 5, -1};
  const Histogram h = make_histogram(values, 4, 0.0, 1.0);
  EXPECT_EQ(h.counts, (std::vector<uint64_t>{3, 1, 1, 3}));
  EXPECT_EQ(h.total(), values.size());
  EXPECT_DOUBLE_EQ(h.bin_width(), 0.25);
  const Histogram merged = merge_bins(h, 2);
  EXPECT_EQ(merged.counts, (std::vector<uint64_t>{4, 4}));
  EXPECT_DOUBLE_EQ(merged.bin_width(), 0.5);
  EXPECT_REFUSED((void)merge_bins(h, 3), std::invalid_argument,
                 "merge_bins: factor 3 does not divide 4 bins");
  EXPECT_REFUSED((void)make_histogram(values, 4, 1.0, 1.0), std::invalid_argument,
                 "upper > lower, got 4 bins over [1, 1)");

  const std::string text = histogram_text(h, "mm", 10);
  EXPECT_NE(text.find("   0.00 –    0.25 mm |##########|          3   37.5%"), std::string::npos)
      << text;
  EXPECT_NE(text.find("|###       |          1   12.5%"), std::string::npos) << text;
  // Trailing empty bins are not printed.
  const Histogram tail = make_histogram(std::vector<double>{0.1}, 4, 0.0, 1.0);
  const std::string tail_text = histogram_text(tail, "mm");
  EXPECT_EQ(std::count(tail_text.begin(), tail_text.end(), '\n'), 1) << tail_text;
}

TEST(ValidatePairwise, ThreePointsByHand) {
  Eigen::Matrix3Xd measured(3, 3), modelled(3, 3);
  measured << 0, 10, 0, 0, 0, 20, 0, 0, 0;
  modelled << 0, 10.5, 0, 0, 0, 19, 0, 0, 0;
  // Measured distances 10, 20, √500; modelled 10.5, 19, √471.25.
  const double e3 = std::sqrt(500.0) - std::sqrt(471.25);
  const PairwiseDistanceErrors r = pairwise_distance_errors(measured, modelled, 1, 4);
  EXPECT_EQ(r.stats.count, 3u);
  const double mean = (0.5 + 1 + e3) / 3;
  EXPECT_NEAR(r.stats.mean, mean, kPairErrorRelativeAccuracy * mean);
  EXPECT_NEAR(
      r.stats.std,
      std::sqrt(
          ((0.5 - mean) * (0.5 - mean) + (1 - mean) * (1 - mean) + (e3 - mean) * (e3 - mean)) / 3),
      2 * kPairErrorRelativeAccuracy);
  EXPECT_NEAR(r.stats.min, 0.5, kPairErrorRelativeAccuracy * 0.5);
  EXPECT_NEAR(r.stats.max, 1.0, kPairErrorRelativeAccuracy);
  EXPECT_EQ(r.histogram.total(), 3u);
  EXPECT_GE(r.histogram.upper, r.stats.max);
  // Signed (measured − modelled): −0.5, +1, +e3 > 0: two of three positive.
  EXPECT_EQ(r.positive_pairs, 2u);
  EXPECT_NEAR(r.positive_share(), 2.0 / 3, 1e-15);
  EXPECT_NEAR(r.signed_mean, (-0.5 + 1 + e3) / 3, kPairErrorRelativeAccuracy);
}

TEST(ValidatePairwise, FewerThanTwoRowsHaveNoPairs) {
  const Eigen::Matrix3Xd one = Eigen::Matrix3Xd::Ones(3, 1);
  const PairwiseDistanceErrors r = pairwise_distance_errors(one, one, 2);
  EXPECT_EQ(r.stats.count, 0u);
  EXPECT_EQ(r.stats.mean, 0.0);
  EXPECT_EQ(r.histogram.total(), 0u);
  // No rows at all (an empty class): no pairs either, not an error.
  const Eigen::Matrix3Xd none(3, 0);
  EXPECT_EQ(pairwise_distance_errors(none, none, 2).stats.count, 0u);
  EXPECT_REFUSED((void)pairwise_distance_errors(one, Eigen::Matrix3Xd::Ones(3, 2)),
                 std::invalid_argument, "1 measured and 2 modelled positions");
  Eigen::Matrix3Xd bad = Eigen::Matrix3Xd::Ones(3, 2);
  bad(1, 1) = NAN;
  EXPECT_REFUSED((void)pairwise_distance_errors(bad, bad), std::invalid_argument,
                 "positions must be finite and within ±1e12 mm");
  bad(1, 1) = 2e12;  // beyond what single-precision squares hold
  EXPECT_REFUSED((void)pairwise_distance_errors(bad, one.replicate(1, 2)), std::invalid_argument,
                 "positions must be finite and within ±1e12 mm");
}

/// N positions in a 1.6 m cube; the "model" sees them moved rigidly (a frame it does not
/// know), scaled by 1.0005 and with 0.05 mm noise, so distance errors span 0..~1 mm.
struct RandomPositions {
  Eigen::Matrix3Xd measured, modelled;
  RandomPositions(int n, uint64_t seed) : measured(3, n), modelled(3, n) {
    auto rng = test::seeded_rng(seed);
    std::uniform_real_distribution<double> coord(-800, 800);
    std::normal_distribution<double> noise(0, 0.05);
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    for (int i = 0; i < n; ++i) {
      measured.col(i) << coord(rng), coord(rng), coord(rng) + 1000;
      modelled.col(i) = R * measured.col(i) * 1.0005 + Eigen::Vector3d(300, -20, 5) +
                        Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    }
  }
};

/// 500 rows: every row's pairs in one piece of work; 1100: the first rows' pairs in several.
class ValidatePairwiseNaive : public ::testing::TestWithParam<int> {};

TEST_P(ValidatePairwiseNaive, MatchesNaiveDoubleLoop) {
  const int n = GetParam();
  const RandomPositions data(n, 11);
  const PairwiseDistanceErrors r = pairwise_distance_errors(data.measured, data.modelled, 2);
  std::vector<double> errors;
  double signed_sum = 0;
  uint64_t positive = 0, near_zero = 0;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const double e = (data.measured.col(i) - data.measured.col(j)).norm() -
                       (data.modelled.col(i) - data.modelled.col(j)).norm();
      errors.push_back(std::abs(e));
      signed_sum += e;
      positive += e > 0 ? 1 : 0;
      near_zero += std::abs(e) < 1e-9 ? 1 : 0;  // where the two formulas may disagree on sign
    }
  const ErrorStatistics naive = error_statistics(errors);
  EXPECT_NEAR(r.signed_mean, signed_sum / static_cast<double>(errors.size()),
              kPairErrorRelativeAccuracy * naive.mean);
  EXPECT_LE(r.positive_pairs > positive ? r.positive_pairs - positive : positive - r.positive_pairs,
            near_zero);
  // Scaled by 1.0005, the model's distances are the longer: most signed errors are negative.
  EXPECT_LT(r.positive_share(), 0.5);
  EXPECT_EQ(r.stats.count, naive.count);
  EXPECT_EQ(r.stats.count, static_cast<uint64_t>(n) * static_cast<uint64_t>(n - 1) / 2);
  // Each pair error carries a relative kPairErrorRelativeAccuracy (the naive one ~1e-13 mm).
  EXPECT_NEAR(r.stats.mean, naive.mean, kPairErrorRelativeAccuracy * naive.mean);
  EXPECT_NEAR(r.stats.std, naive.std, 2 * kPairErrorRelativeAccuracy * naive.mean);
  EXPECT_NEAR(r.stats.min, naive.min, kPairErrorRelativeAccuracy * naive.min);
  EXPECT_NEAR(r.stats.max, naive.max, kPairErrorRelativeAccuracy * naive.max);
  EXPECT_GT(naive.max, 0.3);  // the data do span a range
  // Histogram: the bins of the naive values over the same range, except that a value within
  // the accuracy of a bin edge may land in the neighbouring bin.
  const Histogram expected = make_histogram(errors, 128, r.histogram.lower, r.histogram.upper);
  const double width = r.histogram.upper / 128;
  int near_an_edge = 0;
  for (double e : errors) {
    const double from_edge = std::abs(e / width - std::round(e / width)) * width;
    near_an_edge += from_edge <= 2 * kPairErrorRelativeAccuracy * e ? 1 : 0;
  }
  uint64_t moved = 0;
  for (size_t b = 0; b < expected.counts.size(); ++b)
    moved += r.histogram.counts[b] > expected.counts[b]
                 ? r.histogram.counts[b] - expected.counts[b]
                 : expected.counts[b] - r.histogram.counts[b];
  EXPECT_LE(moved, 2u * static_cast<uint64_t>(near_an_edge));
  EXPECT_EQ(r.histogram.total(), naive.count);
  EXPECT_GE(r.histogram.upper, naive.max);
  // The bound is r1 + r2 after the rigid fit: not far above the largest error.
  EXPECT_LT(r.histogram.upper, 4 * naive.max);
}
INSTANTIATE_TEST_SUITE_P(Rows, ValidatePairwiseNaive, ::testing::Values(500, 1100));

TEST(ValidatePairwise, AccurateWhereTheNaiveFormulaIsNot) {
  // Long double reference on pairs whose lengths (~1 m) dwarf their errors (~1e-9 mm): the
  // naive difference of lengths would be off by ~1e-13 mm, a relative 1e-4. Once in the
  // instrument's frame, once with the model in a frame 0.6 m away, where the rounded residuals
  // m − p add their absolute floor (here 2e-6 of these tiny errors).
  for (const Eigen::Vector3d& offset :
       {Eigen::Vector3d::Zero().eval(), Eigen::Vector3d(300.123, -250.456, 500.789)}) {
    SCOPED_TRACE(offset.transpose());
    Eigen::Matrix3Xd measured(3, 40), modelled(3, 40);
    auto rng = test::seeded_rng(5);
    std::uniform_real_distribution<double> coord(-900, 900), tiny(-1e-9, 1e-9);
    for (int i = 0; i < 40; ++i) {
      measured.col(i) << coord(rng), coord(rng), coord(rng);
      modelled.col(i) = measured.col(i) + offset + Eigen::Vector3d(tiny(rng), tiny(rng), tiny(rng));
    }
    const PairwiseDistanceErrors r = pairwise_distance_errors(measured, modelled, 1);
    long double sum = 0, max = 0;
    double residuals = 0;  // the largest |m_i − p_i| + |m_j − p_j|
    for (int i = 0; i < 40; ++i)
      for (int j = i + 1; j < 40; ++j) {
        long double dm = 0, dp = 0;
        for (int k = 0; k < 3; ++k) {
          const long double a = static_cast<long double>(measured(k, i)) - measured(k, j);
          const long double b = static_cast<long double>(modelled(k, i)) - modelled(k, j);
          dm += a * a;
          dp += b * b;
        }
        const long double e = std::fabs(std::sqrt(dm) - std::sqrt(dp));
        sum += e;
        max = std::max(max, e);
        residuals = std::max(residuals, (measured.col(i) - modelled.col(i)).norm() +
                                            (measured.col(j) - modelled.col(j)).norm());
      }
    const double mean = static_cast<double>(sum / (40 * 39 / 2));
    // Long double itself carries ~1e-16 mm here, a relative 1e-7.
    const double floor = kPairErrorResidualRounding * residuals;
    EXPECT_NEAR(r.stats.mean, mean, (kPairErrorRelativeAccuracy + 1e-7) * mean + floor);
    EXPECT_NEAR(r.stats.max, static_cast<double>(max),
                (kPairErrorRelativeAccuracy + 1e-7) * static_cast<double>(max) + floor);
  }
}

TEST(ValidatePairwise, BitIdenticalForAnyThreadCount) {
  const RandomPositions data(1237, 3);  // not a multiple of the block or chunk size
  const PairwiseDistanceErrors one = pairwise_distance_errors(data.measured, data.modelled, 1);
  for (int threads : {2, 3, 8}) {
    SCOPED_TRACE(threads);
    const PairwiseDistanceErrors many =
        pairwise_distance_errors(data.measured, data.modelled, threads);
    EXPECT_EQ(std::bit_cast<uint64_t>(many.stats.mean), std::bit_cast<uint64_t>(one.stats.mean));
    EXPECT_EQ(std::bit_cast<uint64_t>(many.stats.std), std::bit_cast<uint64_t>(one.stats.std));
    EXPECT_EQ(many.stats.min, one.stats.min);
    EXPECT_EQ(many.stats.max, one.stats.max);
    EXPECT_EQ(many.histogram.upper, one.histogram.upper);
    EXPECT_EQ(many.histogram.counts, one.histogram.counts);
    EXPECT_EQ(std::bit_cast<uint64_t>(many.signed_mean), std::bit_cast<uint64_t>(one.signed_mean));
    EXPECT_EQ(many.positive_pairs, one.positive_pairs);
  }
  EXPECT_EQ(one.histogram.total(), one.stats.count);
}

/// The reference robot (truth.yaml) as a calibrated robot with its tool and world frame.
CalibratedRobot reference_robot() {
  const test::ReferenceTruth truth = test::load_reference_truth();
  CalibratedRobot robot;
  robot.model = truth.model;
  robot.params = truth.params;
  robot.tool = load_tool(test::data_path("irb120-published/tool.yaml"));
  robot.tool.payload = truth.payload;
  robot.base_fitted = true;
  robot.level = "full";
  return robot;
}

TEST(ValidateReference, TrueRobotIsAtTheNoiseFloor) {
  const CalibratedRobot robot = reference_robot();
  const MeasurementSet set =
      read_measurements_csv(test::data_path("irb120-published/validation.csv"), robot.tool)
          .measurements;
  const ValidationReport report = validate_model(robot, set, 2);
  // 0.02 mm Gaussian noise per axis: |error| is Maxwell distributed with mean
  // 0.02·√(8/π) = 0.0319 mm and std 0.02·√(3 − 8/π) = 0.0135 mm.
  const double sigma = 0.02;
  EXPECT_NEAR(report.positions.position_mm.mean, sigma * std::sqrt(8 / std::numbers::pi), 0.0015);
  EXPECT_NEAR(report.positions.position_mm.std, sigma * std::sqrt(3 - 8 / std::numbers::pi),
              0.0015);
  EXPECT_LT(report.positions.position_mm.max, 0.1);
  EXPECT_EQ(report.positions.position_mm.count, 1000u);
  ASSERT_EQ(report.positions.per_target.size(), 3u);
  uint64_t rows = 0;
  for (const TargetErrorStatistics& t : report.positions.per_target) {
    rows += t.position_mm.count;
    EXPECT_NEAR(t.position_mm.mean, 0.032, 0.004) << t.target;
  }
  EXPECT_EQ(rows, 1000u);
  EXPECT_EQ(report.position_histogram.total(), 1000u);
  // A distance error is the projection of the difference of two noise vectors (σ√2 per axis)
  // on the line between the points: |N(0, 2σ²)|, mean σ√2·√(2/π) = 2σ/√π = 0.0226 mm.
  EXPECT_EQ(report.distances.stats.count, 1000u * 999u / 2);
  EXPECT_NEAR(report.distances.stats.mean, 2 * sigma / std::sqrt(std::numbers::pi), 0.001);
  EXPECT_EQ(report.distances.histogram.total(), report.distances.stats.count);
}

TEST(ValidateReference, NominalRobotIsMillimetresOff) {
  CalibratedRobot robot = reference_robot();
  const CalibratedRobot nominal = CalibratedRobot::nominal(robot.model, robot.tool);
  const MeasurementSet set =
      read_measurements_csv(test::data_path("irb120-published/validation.csv"), robot.tool)
          .measurements;
  const ValidationReport report = validate_model(fit_base(nominal, set), set, 2);
  // docs/method/11-published-results.md: the IRB 120 is 1–5 mm off before calibration (3.168 mm
  // published; 1.394 mm for a base-only fit in the reference README).
  EXPECT_GT(report.positions.position_mm.mean, 0.8);
  EXPECT_LT(report.positions.position_mm.mean, 3.5);
  EXPECT_GT(report.distances.stats.mean, 0.3);
}

TEST(ValidateBaseFit, RecoversAKnownBase) {
  // A robot without compliance placed by a known base; its exact positions; the same robot at
  // the origin, fitted: the base parameters come back.
  CalibratedRobot placed = reference_robot();
  for (int link = 2; link <= 6; ++link) placed.params[compliance_param(link)] = 0;
  placed.params[0] = 812.5;
  placed.params[1] = -240.25;
  placed.params[2] = 35.0;
  placed.params[3] = deg2rad(1.5);
  placed.params[4] = deg2rad(-2.25);
  placed.params[5] = deg2rad(130.0);
  MeasurementSet set;
  set.kind = MeasurementKind::Points;
  auto rng = test::seeded_rng(9);
  std::uniform_real_distribution<double> angle(-1.2, 1.2);
  for (int r = 0; r < 30; ++r) {
    PointMeasurement m;
    m.config = std::to_string(r);
    m.target = r % 3;
    for (int j = 0; j < 6; ++j) m.joints[j] = angle(rng);
    set.points.push_back(m);
  }
  const Eigen::Matrix3Xd exact = predicted_positions(placed, set);
  for (int r = 0; r < 30; ++r) set.points[static_cast<size_t>(r)].position_mm = exact.col(r);

  CalibratedRobot origin = placed;
  origin.params.head<6>().setZero();
  origin.base_fitted = false;
  const CalibratedRobot fitted = fit_base(origin, set);
  EXPECT_TRUE(fitted.base_fitted);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(fitted.params[k], placed.params[k], 1e-8) << k;
  for (int k = 3; k < 6; ++k) EXPECT_NEAR(fitted.params[k], placed.params[k], 1e-11) << k;
  EXPECT_LT(position_errors(fitted, set).position_mm.max, 1e-8);
}

TEST(ValidateBaseFit, ResidualsAreTheRigidFitResiduals) {
  // The nominal robot against the reference data: after fit_base the model's position errors
  // are exactly the residuals of the rigid best fit of its (origin) predictions.
  const CalibratedRobot robot = reference_robot();
  const CalibratedRobot nominal = CalibratedRobot::nominal(robot.model, robot.tool);
  const MeasurementSet set =
      read_measurements_csv(test::data_path("irb120-published/calibration.csv"), robot.tool)
          .measurements;
  const Eigen::Matrix3Xd p = predicted_positions(nominal, set);
  Eigen::Matrix3Xd m(3, p.cols());
  for (Eigen::Index r = 0; r < p.cols(); ++r)
    m.col(r) = set.points[static_cast<size_t>(r)].position_mm;
  const Eigen::Matrix4d T = Eigen::umeyama(p, m, false);
  const PositionErrors errors = position_errors(fit_base(nominal, set), set);
  for (Eigen::Index r = 0; r < p.cols(); ++r) {
    const double residual =
        (m.col(r) - (T.topLeftCorner<3, 3>() * p.col(r) + T.topRightCorner<3, 1>())).norm();
    EXPECT_NEAR(errors.position_error_mm[static_cast<size_t>(r)], residual, 1e-9);
  }
}

TEST(ValidateBaseFit, RefusesPositionsThatFixNoFrame) {
  const CalibratedRobot robot = reference_robot();
  MeasurementSet set;
  set.file = "line.csv";
  for (int r = 0; r < 5; ++r)
    set.points.push_back({std::to_string(r), 0, Vector6d::Zero(), {10.0 * r, 0, 0}, r + 2});
  try {
    (void)fit_base(robot, set);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "line.csv: 5 measured positions do not fix a world frame: at least 3 positions not "
              "on one line are needed");
  }
}

TEST(ValidatePoses, PositionAndOrientationErrors) {
  CalibratedRobot robot = reference_robot();
  robot.tool.flange_T_tcp =
      Eigen::Translation3d(10, 20, 150) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY());
  MeasurementSet set;
  set.kind = MeasurementKind::Poses;
  const Eigen::Vector3d offset(0.3, -0.4, 1.2);  // |offset| = 1.3 mm
  for (int r = 0; r < 4; ++r) {
    PoseMeasurement m;
    m.config = std::to_string(r);
    m.joints << 0.1 * r, 0.5, -0.2, 0.3 * r, 0.7, -1.0;
    const Pose<double> flange =
        flange_pose(robot.model, robot.tool.payload, robot.params, m.joints);
    m.world_T_tcp.R =
        flange.R * robot.tool.flange_T_tcp.rotation() *
        Eigen::AngleAxisd(deg2rad(0.25 * (r + 1)), Eigen::Vector3d(1, 1, 0).normalized())
            .toRotationMatrix();
    m.world_T_tcp.p = flange * robot.tool.flange_T_tcp.translation() + offset;
    set.poses.push_back(m);
  }
  const PositionErrors e = position_errors(robot, set);
  for (int r = 0; r < 4; ++r) {
    EXPECT_NEAR(e.position_error_mm[static_cast<size_t>(r)], 1.3, 1e-9);
    EXPECT_NEAR(e.orientation_error_deg[static_cast<size_t>(r)], 0.25 * (r + 1), 1e-9);
  }
  EXPECT_NEAR(e.orientation_deg.mean, 0.625, 1e-9);
  EXPECT_TRUE(e.per_target.empty());
  // Pose error with a weight of 40 mm/rad: √(1.3² + (40·θ)²), θ = 0.25°·(r + 1), by hand.
  const PositionErrors w = position_errors(robot, set, 40.0);
  EXPECT_EQ(w.orientation_weight_mm, 40.0);
  for (int r = 0; r < 4; ++r) {
    const double theta = 0.25 * (r + 1) * std::numbers::pi / 180;
    EXPECT_NEAR(w.pose_error_mm[static_cast<size_t>(r)],
                std::sqrt(1.3 * 1.3 + 40 * theta * 40 * theta), 1e-9);
  }
  EXPECT_GT(e.pose_mm.mean, w.pose_mm.mean);  // the default 100 mm/rad weighs more
}

/// Ballbar rows of `robot` around `centre`: lengths from the model itself plus `offsets`.
MeasurementSet ballbar_rows(const CalibratedRobot& robot, const Eigen::Vector3d& centre,
                            const std::vector<double>& offsets) {
  MeasurementSet set;
  set.kind = MeasurementKind::Distances;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> angle(-1.2, 1.2);
  for (size_t r = 0; r < offsets.size(); ++r) {
    DistanceMeasurement m;
    m.config = std::to_string(r);
    m.target = static_cast<int>(r % robot.tool.targets.size());
    for (int j = 0; j < 6; ++j) m.joints[j] = angle(rng);
    const Eigen::Vector3d p = flange_pose(robot.model, robot.tool.payload, robot.params, m.joints) *
                              robot.tool.targets[static_cast<size_t>(m.target)].position_mm;
    m.length_mm = (p - centre).norm() + offsets[r];
    set.distances.push_back(m);
  }
  return set;
}

TEST(ValidateBallbar, GivenCentreGivesTheLengthOffsetsBack) {
  const CalibratedRobot robot = reference_robot();
  const Eigen::Vector3d centre(400, -50, 300);
  const std::vector<double> offsets = {0.01, -0.02, 0.03, 0.0, -0.01, 0.02, 0.005, -0.005};
  const BallbarErrors e = ballbar_errors(robot, ballbar_rows(robot, centre, offsets), centre);
  EXPECT_FALSE(e.centre_fitted);
  for (size_t r = 0; r < offsets.size(); ++r) EXPECT_NEAR(e.length_error_mm[r], offsets[r], 1e-9);
  EXPECT_NEAR(e.absolute_mm.max, 0.03, 1e-9);
  EXPECT_NEAR(e.absolute_mm.mean, 0.0125, 1e-9);  // (1+2+3+0+1+2+0.5+0.5)/8 · 0.01
  EXPECT_NEAR(e.signed_mean_mm, 0.00375, 1e-9);
  int rows = 0;
  for (const TargetErrorStatistics& t : e.per_target) rows += static_cast<int>(t.position_mm.count);
  EXPECT_EQ(rows, 8);
}

TEST(ValidateBallbar, IdentifiedCentreIsTheTrueOneForExactLengths) {
  const CalibratedRobot robot = reference_robot();
  const Eigen::Vector3d centre(400, -50, 300);
  const MeasurementSet set = ballbar_rows(robot, centre, std::vector<double>(30, 0.0));
  const BallbarErrors e = ballbar_errors(robot, set, std::nullopt);
  EXPECT_TRUE(e.centre_fitted);
  EXPECT_LT((e.centre_mm - centre).norm(), 1e-7);
  EXPECT_LT(e.absolute_mm.max, 1e-8);
  // Too few rows to locate a centre: an InputError naming the way out.
  MeasurementSet three = set;
  three.distances.resize(3);
  EXPECT_REFUSED(
      (void)ballbar_errors(robot, three, std::nullopt), InputError,
      "--ballbar-centre: cannot locate the ballbar centre: the distances need at least four rows");
}

/// Five readings of a 150 mm bar on lines 2..6 of "b.csv".
MeasurementSet bar_readings(const std::vector<double>& lengths) {
  MeasurementSet set;
  set.kind = MeasurementKind::Distances;
  set.file = "b.csv";
  for (size_t r = 0; r < lengths.size(); ++r) {
    DistanceMeasurement m;
    m.length_mm = lengths[r];
    m.line = static_cast<int>(r) + 2;
    set.distances.push_back(m);
  }
  return set;
}

TEST(ValidateBallbar, ReadingsOutsideTheBarsRangeAreRefusedByLine) {
  const MeasurementSet set = bar_readings({150.2, 150.4, 149.8, 152.5, 151.3});
  // Given length: 152.5 (line 5) and 151.3 (line 6) are more than 1 mm from 150.
  EXPECT_REFUSED((void)check_ballbar_readings(set, 150.0, std::nullopt), InputError,
                 "b.csv:5 (length): reading 152.5000 mm is outside the ballbar's range 150 ± 1 "
                 "mm (nominal length given; 2 of 5 readings are outside)");
  const BallbarRange wide = check_ballbar_readings(set, 150.0, 2.5);
  EXPECT_EQ(wide.nominal_length_mm, 150.0);
  EXPECT_EQ(wide.range_mm, 2.5);
  EXPECT_TRUE(wide.length_given);
  // Default length: the median reading, 150.4; only 152.5 is out of ±1 mm of it.
  EXPECT_REFUSED((void)check_ballbar_readings(set, std::nullopt, std::nullopt), InputError,
                 "b.csv:5 (length): reading 152.5000 mm is outside the ballbar's range 150.4 ± "
                 "1 mm (nominal length the median reading; 1 of 5");
  const BallbarRange median = check_ballbar_readings(set, std::nullopt, 2.1);
  EXPECT_EQ(median.nominal_length_mm, 150.4);
  EXPECT_FALSE(median.length_given);
  // The edge itself is readable.
  EXPECT_NO_THROW((void)check_ballbar_readings(bar_readings({149.0, 151.0}), 150.0, 1.0));
  // Bad set-ups name their flag.
  EXPECT_REFUSED((void)check_ballbar_readings(set, 0.0, std::nullopt), InputError,
                 "--ballbar-length: expected the bar's nominal length as a positive length");
  EXPECT_REFUSED((void)check_ballbar_readings(set, std::nan(""), std::nullopt), InputError,
                 "--ballbar-length");
  EXPECT_REFUSED((void)check_ballbar_readings(set, 150.0, -1.0), InputError,
                 "--ballbar-range: expected the bar's measuring range");
  EXPECT_REFUSED((void)check_ballbar_readings(set, 150.0, 150.0), InputError,
                 "--ballbar-range: a range of ±150 mm is not below the bar's length 150 mm");
}

TEST(ValidateBallbar, LengthErrorsByConfigurationClass) {
  const CalibratedRobot robot = reference_robot();
  const Eigen::Vector3d centre(400, -50, 300);
  std::vector<double> offsets;
  for (int r = 0; r < 40; ++r) offsets.push_back(0.001 * (r % 7) - 0.003);
  const MeasurementSet set = ballbar_rows(robot, centre, offsets);
  const BallbarErrors e = ballbar_errors(robot, set, centre);
  ASSERT_EQ(e.classes.size(), 3u);
  EXPECT_EQ(e.classes[2].name, "flip/no-flip");
  for (size_t t = 0; t < 3; ++t) {
    uint64_t rows = 0;
    for (size_t c = 0; c < 2; ++c) {
      // Straightforward: the |offsets| of the rows in the class.
      double sum = 0, max = 0;
      uint64_t n = 0;
      for (size_t r = 0; r < set.size(); ++r) {
        const ArmConfig config = arm_config(robot.model, set.distances[r].joints);
        const bool second[] = {config.back, config.down, config.flip};
        if (second[t] != (c == 1)) continue;
        ++n;
        sum += std::abs(offsets[r]);
        max = std::max(max, std::abs(offsets[r]));
      }
      const ErrorStatistics& s = e.classes[t].rows[c].position_mm;
      EXPECT_EQ(s.count, n);
      if (n > 0) {
        EXPECT_NEAR(s.mean, sum / static_cast<double>(n), 1e-9);
        EXPECT_NEAR(s.max, max, 1e-9);
      }
      rows += s.count;
    }
    EXPECT_EQ(rows, set.size());
  }
}

TEST(ValidatePositions, TargetWithoutCoordinatesIsNamed) {
  CalibratedRobot robot = reference_robot();
  robot.tool.targets[1].known = false;
  MeasurementSet set;
  set.file = "v.csv";
  set.points.push_back({"c", 1, Vector6d::Zero(), Eigen::Vector3d::Zero(), 7});
  try {
    (void)position_errors(robot, set);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("v.csv:7 (target): target '2' has no coordinates"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace robcal
