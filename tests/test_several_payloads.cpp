// Several payloads in one calibration (issue 19, docs/method/03-error-model.md §7): the tool
// file's `payloads`, the measurement file's `payload` column, and on a simulated IRB 120 whose
// rows carry seeded random payloads: the compliances come out with smaller σ and less
// correlated with the geometry than from one payload, within 3σ of the truth, and validation
// uses each row's payload.

#include <gtest/gtest.h>

#include <fstream>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/identify/identification.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/simulator.hpp"
#include "robcal/validate/validation.hpp"
#include "test_error_groups_support.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

TEST(SeveralPayloads, ToolFileAndMeasurementColumnRoundTrip) {
  const Tool tool = test::tool_with_payloads();
  // Through a file: the tool reader accepts the 'payloads' key.
  const std::string path = testing::TempDir() + "several-payloads-tool.yaml";
  std::ofstream(path) << tool_to_yaml(tool);
  const Tool back = load_tool(path);
  ASSERT_EQ(back.payloads.size(), 2u);
  EXPECT_EQ(back.payloads[1].name, "gripper");
  EXPECT_EQ(back.payloads[1].mass.mass_kg, 6.0);
  EXPECT_EQ(back.payloads[1].mass.cog_mm, Eigen::Vector3d(60, 20, 150));
  EXPECT_EQ(back.payload_index("empty"), 0);
  EXPECT_EQ(&back.payload_of(-1), &back.payload);

  MeasurementSet set;
  set.points.push_back({"C1", 0, Vector6d::Constant(0.1), Eigen::Vector3d(1, 2, 3), 0});
  set.points.push_back({"C2", 1, Vector6d::Constant(0.2), Eigen::Vector3d(4, 5, 6), 0});
  set.points.push_back({"C3", 2, Vector6d::Constant(0.3), Eigen::Vector3d(7, 8, 9), 0});
  set.points[1].payload = 1;
  set.points[2].payload = 0;
  set.points[1].approach << 1, -1, 1, 1, 0, 1;  // both optional columns in one file
  const std::string text = write_measurements_csv(set, tool);
  EXPECT_NE(text.find(",approach,payload\n"), std::string::npos) << text;
  EXPECT_NE(text.find(",+-++0+,gripper\n"), std::string::npos) << text;
  EXPECT_NE(text.find(",empty\n"), std::string::npos) << text;  // C3 names payload 0
  const MeasurementFile read = parse_measurements_csv(text, "m.csv", tool);
  EXPECT_TRUE(read.warnings.empty());
  ASSERT_EQ(read.measurements.size(), 3u);
  for (size_t r = 0; r < 3; ++r) {
    EXPECT_EQ(read.measurements.payload(r), set.payload(r));
    EXPECT_EQ(read.measurements.points[r].approach, set.points[r].approach);
  }
  // Without any payload named, the file keeps today's columns.
  set.points[1].payload = set.points[2].payload = -1;
  set.points[1].approach.setOnes();
  EXPECT_EQ(write_measurements_csv(set, tool).find("payload"), std::string::npos);

  std::string bad = text;
  bad.replace(bad.find(",gripper\n"), 9, ",grippr\n");
  EXPECT_REFUSED(parse_measurements_csv(bad, "m.csv", tool), InputError,
                 "m.csv:3:13 (payload): unknown payload 'grippr': expected a name under "
                 "'payloads:' in the tool file ('empty', 'gripper')");
}

/// 100 calibration and 60 validation positions on the published IRB 120; `several`: each row
/// carries a payload drawn (seeded) from the tool's three.
test::GroupCampaign simulate(bool several, uint64_t seed) {
  const TrueRobot truth =
      published_irb120_truth(load_robot("abb-irb120"), test::tool_with_payloads());
  SimulationOptions sim;
  sim.random_payloads = several;
  return test::simulate_campaign(truth, 0.01, seed, published_joint_box(truth.robot.model), sim);
}

IdentificationResult fit(const MeasurementSet& data) {
  IdentifyOptions options;
  options.level = CalibrationLevel::Full;
  return calibrate(load_robot("abb-irb120"), test::tool_with_payloads(), data, options);
}

/// The largest |correlation| between a compliance and a geometric parameter.
double geometry_compliance_correlation(const CalibratedRobot& robot) {
  double worst = 0;
  for (int joint = 2; joint <= kJointCount; ++joint) {
    const int c = compliance_param(joint);
    for (int g = 0; g < kComplianceOffset; ++g) {
      if (robot.status[static_cast<size_t>(g)] != ParameterStatus::Identified) continue;
      const double r =
          robot.covariance(c, g) / std::sqrt(robot.covariance(c, c) * robot.covariance(g, g));
      worst = std::max(worst, std::abs(r));
    }
  }
  return worst;
}

// The check: payloads that change between rows separate compliance from geometry
// (the deflection changes while the geometry does not): every compliance's σ shrinks and the
// strongest geometry/compliance correlation drops, against the same number of rows with one
// payload. The estimates stay within 3σ of the truth and validation with each row's payload
// is at the noise.
TEST(SeveralPayloads, ComplianceSeparatedFromGeometry) {
  const test::GroupCampaign one = simulate(false, 1990);
  const test::GroupCampaign several = simulate(true, 1990);
  int carried[3] = {0, 0, 0};
  for (size_t r = 0; r < several.calibration.size(); ++r)
    ++carried[several.calibration.payload(r) + 1];
  for (int n : carried) EXPECT_GT(n, 20);  // each payload carried in some rows
  const IdentificationResult a = fit(one.calibration);
  const IdentificationResult b = fit(several.calibration);
  const TrueRobot truth =
      published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
  for (int joint = 2; joint <= kJointCount; ++joint) {
    const int i = compliance_param(joint);
    const double sa = std::sqrt(a.robot.covariance(i, i)), sb = std::sqrt(b.robot.covariance(i, i));
    std::printf("joint%d.compliance σ: one payload %.3g, several %.3g rad/N·mm (ratio %.2f)\n",
                joint, sa, sb, sb / sa);
    EXPECT_LT(sb, 0.5 * sa) << parameter_table()[i].name;  // measured 0.26–0.47
    EXPECT_LT(std::abs(b.robot.params[i] - truth.robot.params[i]), 3 * sb)
        << parameter_table()[i].name;
  }
  const double ra = geometry_compliance_correlation(a.robot),
               rb = geometry_compliance_correlation(b.robot);
  std::printf("largest geometry/compliance correlation: one payload %.3f, several %.3f\n", ra, rb);
  EXPECT_GT(ra, 0.9);   // measured 0.937
  EXPECT_LT(rb, 0.85);  // measured 0.783
  const double validation =
      validate_model(b.robot, several.validation, 1).positions.position_mm.mean;
  std::printf("validation mean with each row's payload: %.4f mm\n", validation);
  EXPECT_LT(validation, 0.03);
}

}  // namespace
}  // namespace robcal
