// The world frame from table nests applied to measurements (issue 16): readings of a simulated
// robot taken by an instrument in two different places, each expressed in the world through
// the frame fitted to four nests and written/read as `robcal frames world`'s file, give back
// the world positions and orientations (round trip, 1e-9); a bad frame file is named.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "refusal.hpp"
#include "robcal/campaign/frames.hpp"
#include "robcal/campaign/frames_file.hpp"
#include "robcal/campaign/frames_world.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal::campaign {
namespace {

Pose<double> placement(const Eigen::Vector3d& rotation_vector, const Eigen::Vector3d& p) {
  return {
      Eigen::AngleAxisd(rotation_vector.norm(), rotation_vector.normalized()).toRotationMatrix(),
      p};
}

TEST(CampaignWorldFrame, MeasurementsOfAMovedInstrumentRoundTripToTheWorld) {
  const RobotModel model = load_robot("abb-irb120");
  const ParameterVector params = model.nominal();
  // The world truth: a few flange poses of the robot (the targets' positions and the poses).
  MeasurementSet world_points, world_poses;
  world_points.kind = MeasurementKind::Points;
  world_poses.kind = MeasurementKind::Poses;
  for (int k = 0; k < 6; ++k) {
    Vector6d q;
    q << 0.3 * k - 0.7, 0.1 * k - 0.2, 0.2 - 0.05 * k, 0.4 * k, 0.5 + 0.1 * k, -0.3 * k;
    const Pose<double> f = flange_pose(model, PointMass{}, params, q);
    world_points.points.push_back({"C" + std::to_string(k), 0, q, f.p, k + 2});
    world_poses.poses.push_back({"C" + std::to_string(k), q, f, k + 2});
  }
  const std::vector<Eigen::Vector3d> nests_world = {
      {600, -400, 0}, {600, 400, 0}, {-300, 400, 0}, {-300, -400, 10}};
  // The instrument in two places (instrument_T_world), as when it is moved between sessions.
  for (const Pose<double>& instrument_T_world :
       {placement(Eigen::Vector3d(0.02, -0.01, 2.5), Eigen::Vector3d(-2500, 300, -900)),
        placement(Eigen::Vector3d(-0.03, 0.05, -0.8), Eigen::Vector3d(1800, -2200, -750))}) {
    std::vector<Eigen::Vector3d> nests_measured;
    for (const Eigen::Vector3d& n : nests_world) nests_measured.push_back(instrument_T_world * n);
    const FrameEstimate frame = frame_from_nests(nests_measured, nests_world, 0.01);
    // Through the file `robcal frames world` writes.
    const Pose<double> read =
        parse_world_frame(frame_yaml("frame", frame, "test"), "world-frame.yaml");
    EXPECT_LT((read.p - instrument_T_world.p).norm(), 1e-9);
    EXPECT_LT((read.R - instrument_T_world.R).norm(), 1e-12);

    // What the instrument reads, in its own frame.
    MeasurementSet seen_points = world_points, seen_poses = world_poses;
    for (PointMeasurement& m : seen_points.points)
      m.position_mm = instrument_T_world * m.position_mm;
    for (PoseMeasurement& m : seen_poses.poses) m.world_T_tcp = instrument_T_world * m.world_T_tcp;
    ASSERT_GT((seen_points.points[0].position_mm - world_points.points[0].position_mm).norm(), 100);

    const MeasurementSet back_points = measurements_in_frame(seen_points, read);
    const MeasurementSet back_poses = measurements_in_frame(seen_poses, read);
    for (size_t k = 0; k < world_points.points.size(); ++k) {
      EXPECT_LT((back_points.points[k].position_mm - world_points.points[k].position_mm).norm(),
                1e-9);
      EXPECT_EQ(back_points.points[k].config, world_points.points[k].config);
      EXPECT_EQ(back_points.points[k].line, world_points.points[k].line);
      EXPECT_EQ(back_points.points[k].joints, world_points.points[k].joints);
      EXPECT_LT((back_poses.poses[k].world_T_tcp.p - world_poses.poses[k].world_T_tcp.p).norm(),
                1e-9);
      EXPECT_LT((back_poses.poses[k].world_T_tcp.R - world_poses.poses[k].world_T_tcp.R).norm(),
                1e-12);
    }
  }
}

TEST(CampaignWorldFrame, DistancesAreUnchangedAndABadFileIsNamed) {
  MeasurementSet distances;
  distances.kind = MeasurementKind::Distances;
  distances.distances.push_back({"C1", 0, Vector6d::Zero(), 150.25, 3});
  const MeasurementSet same = measurements_in_frame(
      distances, placement(Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(1, 2, 3)));
  EXPECT_EQ(same.distances[0].length_mm, 150.25);
  try {
    (void)parse_world_frame("frame: {position_mm: [1, 2], rotation_xyz_deg: [0, 0, 0]}\n",
                            "w.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "w.yaml");
    EXPECT_NE(std::string(e.what()).find("position_mm"), std::string::npos) << e.what();
  }
  EXPECT_REFUSED((void)parse_world_frame("base: {}\n", "w.yaml"), InputError,
                 "w.yaml:1:1: missing key 'frame'");
}

}  // namespace
}  // namespace robcal::campaign
