// Validation statistics by class (configuration, target, region) against a straightforward
// recomputation row by row, and the "no data" rows of empty classes.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "refusal.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/validate/base_fit.hpp"
#include "robcal/validate/class_statistics.hpp"
#include "robcal/validate/validation.hpp"
#include "test_validate_support.hpp"

namespace robcal {
namespace {

/// Count, mean and max per label, summed row by row.
struct Naive {
  std::map<std::string, std::pair<int, double>> sum;
  std::map<std::string, double> max;
  void add(const std::string& label, double e) {
    sum[label].first += 1;
    sum[label].second += e;
    max[label] = std::max(max[label], e);
  }
};

void expect_table_matches(const ClassTable& table, const Naive& naive, size_t rows) {
  SCOPED_TRACE(table.name);
  uint64_t total = 0;
  for (const ClassRow& r : table.rows) {
    SCOPED_TRACE(r.label);
    total += r.position_mm.count;
    const auto it = naive.sum.find(r.label);
    if (it == naive.sum.end()) {
      EXPECT_EQ(r.position_mm.count, 0u);
      EXPECT_EQ(value_or_no_data(r.position_mm, r.position_mm.mean), "no data");
      continue;
    }
    EXPECT_EQ(r.position_mm.count, static_cast<uint64_t>(it->second.first));
    EXPECT_NEAR(r.position_mm.mean, it->second.second / it->second.first, 1e-12);
    EXPECT_EQ(r.position_mm.max, naive.max.at(r.label));
  }
  EXPECT_EQ(total, rows);
}

TEST(ValidateClasses, MatchRowByRowRecomputation) {
  const CalibratedRobot robot = test::reference_true_robot();
  const MeasurementSet set =
      read_measurements_csv(test::data_path("irb120-published/validation.csv"), robot.tool,
                            {MeasurementKind::Points})
          .measurements;
  // The "calibration set": every 20th row's measured position.
  Eigen::Matrix3Xd calibration(3, 0);
  for (size_t r = 0; r < set.size(); r += 20) {
    calibration.conservativeResize(3, calibration.cols() + 1);
    calibration.col(calibration.cols() - 1) = set.points[r].position_mm;
  }
  const ValidationReport report = validate_model(robot, set, 2, 100.0, calibration);
  ASSERT_EQ(report.classes.size(), 5u);

  Naive front, up, flip, target, region;
  const std::vector<double> edges = kDefaultRegionEdgesMm;
  for (size_t r = 0; r < set.size(); ++r) {
    const double e = report.positions.position_error_mm[r];
    const std::string label = arm_config(robot.model, set.points[r].joints).label();
    front.add(label.starts_with("back") ? "back" : "front", e);
    up.add(label.find("-down-") != std::string::npos ? "down" : "up", e);
    flip.add(label.ends_with("-flip") ? "flip" : "no-flip", e);
    target.add(robot.tool.targets[static_cast<size_t>(set.points[r].target)].name, e);
    double nearest = 1e300;
    for (Eigen::Index c = 0; c < calibration.cols(); ++c)
      nearest = std::min(nearest, (calibration.col(c) - set.points[r].position_mm).norm());
    const char* labels[] = {"0–25 mm", "25–50 mm", "50–100 mm", "100–200 mm", "≥ 200 mm"};
    size_t k = 0;
    while (k < edges.size() && nearest >= edges[k]) ++k;
    region.add(labels[k], e);
  }
  EXPECT_EQ(report.classes[0].name, "front/back");
  expect_table_matches(report.classes[0], front, set.size());
  expect_table_matches(report.classes[1], up, set.size());
  expect_table_matches(report.classes[2], flip, set.size());
  EXPECT_EQ(report.classes[3].name, "target");
  EXPECT_EQ(report.classes[3].rows.size(), robot.tool.targets.size());
  expect_table_matches(report.classes[3], target, set.size());
  EXPECT_EQ(report.classes[4].name, "region");
  expect_table_matches(report.classes[4], region, set.size());
  // The calibration rows themselves are at distance 0: at least 50 rows in the first class.
  EXPECT_GE(report.classes[4].rows[0].position_mm.count, 50u);
  // Without calibration positions there is no region table.
  EXPECT_EQ(validate_model(robot, set, 2).classes.size(), 4u);
}

TEST(ValidateClasses, PairDistancesPerConfigurationClassAreThePairsInsideTheClass) {
  const CalibratedRobot truth = test::reference_true_robot();
  const MeasurementSet all =
      read_measurements_csv(test::data_path("irb120-published/validation.csv"), truth.tool,
                            {MeasurementKind::Points})
          .measurements;
  // 300 rows of the nominal robot (errors of a few mm), placed by a rigid fit.
  MeasurementSet set = all;
  set.points.resize(300);
  const CalibratedRobot nominal = fit_base(CalibratedRobot::nominal(truth.model, truth.tool), set);
  const ValidationReport report = validate_model(nominal, set, 2);
  const Eigen::Matrix3Xd& m = report.positions.measured_mm;
  const Eigen::Matrix3Xd& p = report.positions.predicted_mm;
  for (size_t t = 0; t < 3; ++t) {
    const ClassTable& table = report.classes[t];
    SCOPED_TRACE(table.name);
    for (size_t c = 0; c < table.rows.size(); ++c) {
      SCOPED_TRACE(table.rows[c].label);
      // Straightforward: every pair i < j with both rows in the class, in double precision.
      std::vector<Eigen::Index> rows;
      for (size_t r = 0; r < set.size(); ++r) {
        const ArmConfig config = arm_config(truth.model, set.points[r].joints);
        const bool in_second[] = {config.back, config.down, config.flip};
        if (in_second[t] == (c == 1)) rows.push_back(static_cast<Eigen::Index>(r));
      }
      uint64_t pairs = 0, positive = 0;
      double sum = 0, signed_sum = 0, max = 0;
      for (size_t i = 0; i < rows.size(); ++i)
        for (size_t j = i + 1; j < rows.size(); ++j) {
          const double e =
              (m.col(rows[i]) - m.col(rows[j])).norm() - (p.col(rows[i]) - p.col(rows[j])).norm();
          ++pairs;
          sum += std::abs(e);
          signed_sum += e;
          max = std::max(max, std::abs(e));
          positive += e > 0 ? 1 : 0;
        }
      ASSERT_TRUE(table.rows[c].pairs.has_value());
      const PairwiseDistanceErrors& got = *table.rows[c].pairs;
      EXPECT_EQ(got.stats.count, pairs);
      if (pairs == 0) {
        EXPECT_EQ(value_or_no_data(got.stats, got.stats.mean), "no data");
        continue;
      }
      EXPECT_NEAR(got.stats.mean, sum / static_cast<double>(pairs), 1e-6 * max);
      EXPECT_NEAR(got.stats.max, max, 1e-6 * max);
      EXPECT_NEAR(got.signed_mean, signed_sum / static_cast<double>(pairs), 1e-6 * max);
      EXPECT_NEAR(static_cast<double>(got.positive_pairs), static_cast<double>(positive), 2);
    }
  }
  // The target and region tables carry no pair statistics.
  EXPECT_FALSE(report.classes[3].rows[0].pairs.has_value());
}

TEST(ValidateClasses, EmptyClassSaysNoData) {
  const CalibratedRobot robot = test::reference_true_robot();
  MeasurementSet all = read_measurements_csv(test::data_path("irb120-published/validation.csv"),
                                             robot.tool, {MeasurementKind::Points})
                           .measurements;
  MeasurementSet front = all;
  front.points.clear();
  for (const PointMeasurement& m : all.points)
    if (!arm_config(robot.model, m.joints).back) front.points.push_back(m);
  ASSERT_GT(front.points.size(), 3u);
  const ValidationReport report = validate_model(robot, front, 1);
  const ClassRow& back = report.classes[0].rows[1];
  EXPECT_EQ(back.label, "back");
  EXPECT_EQ(back.position_mm.count, 0u);
  EXPECT_EQ(value_or_no_data(back.position_mm, back.position_mm.mean), "no data");
  EXPECT_EQ(value_or_no_data(report.classes[0].rows[0].position_mm,
                             report.classes[0].rows[0].position_mm.mean, 3),
            fmt::format("{:.3f}", report.positions.position_mm.mean));
  EXPECT_REFUSED((void)class_tables(robot, front, report.positions, std::nullopt, {50, 25}),
                 std::invalid_argument,
                 "class_tables: region edges must be positive and ascending");
}

TEST(ValidateClasses, OrientationErrorsOfPosesByClass) {
  const CalibratedRobot robot = test::reference_true_robot();
  MeasurementSet set;
  set.kind = MeasurementKind::Poses;
  // Rows 0, 1 with θ5 > 0 (no-flip), rows 2, 3 with θ5 < 0 (flip); orientation errors 0.1·(r+1)°.
  for (int r = 0; r < 4; ++r) {
    PoseMeasurement m;
    m.joints << 0.1 * r, 0.3, 0.2, 0.4, r < 2 ? 0.8 : -0.8, 0.5;
    const Pose<double> flange =
        flange_pose(robot.model, robot.tool.payload, robot.params, m.joints);
    const Pose<double> tcp = flange * Pose<double>{robot.tool.flange_T_tcp.rotation(),
                                                   robot.tool.flange_T_tcp.translation()};
    m.world_T_tcp.R =
        tcp.R *
        Eigen::AngleAxisd(deg2rad(0.1 * (r + 1)), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    m.world_T_tcp.p = tcp.p;
    set.poses.push_back(m);
  }
  const ValidationReport report = validate_model(robot, set, 1);
  const ClassTable& flips = report.classes[2];
  ASSERT_EQ(flips.name, "flip/no-flip");
  EXPECT_EQ(flips.rows[0].orientation_deg.count, 2u);
  EXPECT_NEAR(flips.rows[0].orientation_deg.mean, 0.15, 1e-9);
  EXPECT_NEAR(flips.rows[1].orientation_deg.mean, 0.35, 1e-9);
  EXPECT_NEAR(flips.rows[1].orientation_deg.max, 0.4, 1e-9);
  EXPECT_EQ(report.classes[3].rows[0].label, "tcp");
  EXPECT_EQ(report.classes[3].rows[0].orientation_deg.count, 4u);
}

TEST(ValidateClasses, DistanceToNearest) {
  Eigen::Matrix3Xd anchors(3, 2), points(3, 2);
  anchors << 0, 10, 0, 0, 0, 0;
  points << 3, 14, 4, 0, 0, 3;
  const std::vector<double> d = distance_to_nearest(points, anchors);
  EXPECT_DOUBLE_EQ(d[0], 5.0);  // (3, 4, 0) to the origin
  EXPECT_DOUBLE_EQ(d[1], 5.0);  // (14, 0, 3) to (10, 0, 0)
  EXPECT_REFUSED((void)distance_to_nearest(points, Eigen::Matrix3Xd(3, 0)), std::invalid_argument,
                 "distance_to_nearest: no anchor positions");
}

}  // namespace
}  // namespace robcal
