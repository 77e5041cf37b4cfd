// Ballbar test path: points on the sphere around the taught centre, joints from the compensation
// IK that put the ball there, predicted readings of a second model (the published IRB 120 as
// the real robot) checked against the bar's range, and the configurations file.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/simulator.hpp"
#include "robcal/sim/true_robot.hpp"
#include "robcal/validate/ballbar_path.hpp"

namespace robcal {
namespace {

BallbarPathRequest irb120_request() {
  BallbarPathRequest r;
  r.robot = CalibratedRobot::nominal(load_robot("abb-irb120"), default_simulation_tool());
  r.target = 0;  // "1", on the flange axis
  r.centre_mm = Eigen::Vector3d(400, 0, 300);
  r.length_mm = 100;
  r.elevations_deg = {-30, 0, 30};
  r.points_per_ring = 8;
  r.world_R_tcp = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return r;
}

TEST(ValidateBallbarPath, PointsOnTheSphereAndExactJoints) {
  const BallbarPathRequest request = irb120_request();
  const BallbarPath path = ballbar_path(request);
  ASSERT_EQ(path.points.size(), 24u);
  EXPECT_EQ(path.problems(), 0);
  const Eigen::Vector3d ball = request.robot.tool.targets[0].position_mm;
  for (const BallbarPathPoint& p : path.points) {
    EXPECT_NEAR((p.position_mm - request.centre_mm).norm(), 100, 1e-9);
    EXPECT_EQ(p.problem, "");
    EXPECT_NEAR((p.position_mm - request.centre_mm).normalized().z(),
                std::sin(p.elevation_deg * M_PI / 180), 1e-12);
    const Pose<double> flange = flange_pose(request.robot.model, request.robot.tool.payload,
                                            request.robot.params, p.joints);
    EXPECT_LT((flange * ball - p.position_mm).norm(), 1e-6);
    EXPECT_LT(std::abs(p.predicted_offset_mm), 1e-6);  // the reading model is the commanding one
  }
  // The configurations file reads back (robcal simulate --configs).
  const std::string csv = ballbar_path_csv(path, "1");
  const std::string file = testing::TempDir() + "ballbar_path.csv";
  { std::ofstream(file) << csv; }
  const auto configs = read_configurations_csv(file, request.robot.tool);
  ASSERT_EQ(configs.size(), 24u);
  EXPECT_EQ(configs[5].target, 0);
  EXPECT_LT((configs[5].joints - path.points[5].joints).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(ValidateBallbarPath, PredictedReadingsOfTheRealRobotAgainstTheRange) {
  BallbarPathRequest request = irb120_request();
  const TrueRobot truth =
      published_irb120_truth(request.robot.model, request.robot.tool, {0, 0, 0, 0, 0, 0});
  request.reading_model = truth.robot;
  BallbarPath path = ballbar_path(request);
  double largest = 0;
  int outside = 0;
  for (const BallbarPathPoint& p : path.points) {
    // The simulator's true arm at these joints reads this much off the bar's length.
    const Eigen::Vector3d ball =
        true_flange_pose(truth, p.joints) * truth.robot.tool.targets[0].position_mm;
    EXPECT_NEAR(p.predicted_offset_mm, (ball - request.centre_mm).norm() - 100, 1e-9);
    largest = std::max(largest, std::abs(p.predicted_offset_mm));
    outside += std::abs(p.predicted_offset_mm) > 1.0 ? 1 : 0;
  }
  // The nominal model misses the real arm by millimetres here and there: the check says where.
  EXPECT_GT(largest, 0.05);
  EXPECT_EQ(path.problems(), outside);
  request.range_mm = largest / 2;
  path = ballbar_path(request);
  EXPECT_GT(path.problems(), 0);
  for (const BallbarPathPoint& p : path.points)
    if (!p.problem.empty()) {
      EXPECT_GT(std::abs(p.predicted_offset_mm), request.range_mm);
      EXPECT_NE(p.problem.find("outside its"), std::string::npos) << p.problem;
    }
}

TEST(ValidateBallbarPath, UnreachableAndBadRequests) {
  BallbarPathRequest request = irb120_request();
  request.centre_mm = Eigen::Vector3d(3000, 0, 0);
  const BallbarPath path = ballbar_path(request);
  EXPECT_EQ(path.problems(), 24);
  EXPECT_NE(path.points[0].problem.find("not reachable in front-up-noflip"), std::string::npos)
      << path.points[0].problem;
  EXPECT_EQ(ballbar_path_csv(path, "1"), "config,target,j1,j2,j3,j4,j5,j6\n");
  request = irb120_request();
  request.length_mm = 0;
  EXPECT_REFUSED((void)ballbar_path(request), InputError,
                 "--length: expected a positive length in mm, found 0");
  request = irb120_request();
  request.range_mm = request.length_mm;  // the bar would read down to 0 mm
  EXPECT_REFUSED((void)ballbar_path(request), InputError,
                 "--range: the bar reads --length ± --range: a range of 100 mm must be below the "
                 "length, 100 mm");
  request = irb120_request();
  request.elevations_deg = {90};
  EXPECT_REFUSED((void)ballbar_path(request), InputError,
                 "--elevations: elevations must lie strictly within ±90°, found 90°");
  request = irb120_request();
  request.target = 7;
  EXPECT_REFUSED((void)ballbar_path(request), InputError,
                 "--target: the ball's target must be a target of the tool with known coordinates; "
                 "target index 7 is not");
}

}  // namespace
}  // namespace robcal
