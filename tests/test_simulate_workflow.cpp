// The simulate workflow (sim/simulate_workflow.hpp): a cell's rules hold for random draws, and
// noise-free readings are exact.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "refusal.hpp"
#include "robcal/campaign/cell.hpp"
#include "robcal/campaign/feasibility.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/sim/simulate_workflow.hpp"

namespace robcal {
namespace {

std::string cell_with_a_fixture() {
  const std::string path = ::testing::TempDir() + "simulate-cell.yaml";
  std::ofstream out(path);
  out << "format: robcal-cell\nname: fixture cell\nrobot_base:\n"
         "  position_mm: [-812.25, 1503.5, -95]\n  rotation_xyz_deg: [0.25, -0.4, -57]\n"
         "instrument:\n  kind: laser-tracker\n  position_mm: [0, 0, 0]\n"
         "  range_mm: [0, 35000]\n  cone_half_angle_deg: 30\nfloor_z_mm: -95\n"
         "link_radius_mm: 60\nkeep_out:\n"
         "  - {name: fixture, min_mm: [-700, 1000, -95], max_mm: [-300, 1300, 400]}\n";
  return path;
}

int rejected_by(const campaign::Cell& cell, const SimulateResult& r) {
  const RobotModel model = load_robot(r.request.robot);
  int rejected = 0;
  for (const PointMeasurement& m : r.simulation.measurements.points)
    rejected += campaign::check_configuration(cell, model, r.tool, m.joints, m.target).reason !=
                campaign::Rejection::None;
  return rejected;
}

TEST(SimulateWorkflow, RandomConfigurationsKeepTheCellsRules) {
  const std::string path = cell_with_a_fixture();
  const campaign::Cell cell = campaign::load_cell(path);
  SimulateRequest request;
  request.random = 80;
  request.seed = 4;
  // The standard cell (same robot base, no fixture): some draws hit the fixture or hide the SMR,
  // so the rule below is not empty.
  const SimulateResult free = run_simulation(request);
  EXPECT_GT(rejected_by(cell, free), 0);
  request.cell = path;
  const SimulateResult kept = run_simulation(request);
  EXPECT_EQ(kept.simulation.measurements.size(), 80u);
  EXPECT_EQ(rejected_by(cell, kept), 0);
  const nlohmann::json j = simulation_json(kept);
  EXPECT_EQ(j["cell"], path);
  EXPECT_EQ(j["measured"], 80);
  EXPECT_FALSE(j.contains("files"));  // nothing asked to be written
}

TEST(SimulateWorkflow, ExactReadingsAreTheTrueRobotsPositions) {
  SimulateRequest request;
  request.random = 10;
  request.exact = true;
  const SimulateResult r = run_simulation(request);
  const TrueRobot truth = published_irb120_truth(load_robot("abb-irb120"), r.tool);
  for (const PointMeasurement& m : r.simulation.measurements.points) {
    const Pose<double> flange = true_flange_pose(truth, m.joints);
    const Eigen::Vector3d p =
        flange * truth.robot.tool.targets[static_cast<size_t>(m.target)].position_mm;
    EXPECT_LT((p - m.position_mm).norm(), 1e-9) << m.config;
  }
}

TEST(SimulateWorkflow, RefusalsNameTheFlag) {
  SimulateRequest request;
  EXPECT_REFUSED(run_simulation(request), InputError, "--configs FILE or --random N");
  request.random = 5;
  request.approach = "sideways";
  EXPECT_REFUSED(run_simulation(request), InputError, "--approach");
  request.approach = "below";
  request.noise_mm = -1;
  EXPECT_REFUSED(run_simulation(request), InputError, "--noise-mm");
}

}  // namespace
}  // namespace robcal
