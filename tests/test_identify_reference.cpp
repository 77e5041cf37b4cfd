// Identification on the independent reference data set (tests/data/irb120-published, README
// there): the full fit must reach the independent fit's noise floor on the 1000 validation
// configurations, kinematic must be visibly worse, base worse still, and the noise-free set must
// give back the true robot.

#include <gtest/gtest.h>

#include "robcal/identify/identification.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

MeasurementSet reference_points(const std::string& file, const Tool& tool) {
  const auto table = test::read_csv(test::data_path("irb120-published/" + file));
  MeasurementSet set;
  set.kind = MeasurementKind::Points;
  set.file = file;
  for (size_t r = 0; r < table.rows.size(); ++r) {
    PointMeasurement m;
    m.config = std::to_string(static_cast<int>(table.at(r, "config")));
    m.target = tool.target_index(std::to_string(static_cast<int>(table.at(r, "target"))));
    for (int j = 0; j < 6; ++j) m.joints[j] = deg2rad(table.at(r, "j" + std::to_string(j + 1)));
    m.position_mm = {table.at(r, "x"), table.at(r, "y"), table.at(r, "z")};
    m.line = static_cast<int>(r) + 2;
    set.points.push_back(m);
  }
  return set;
}

struct ErrorStats {
  double mean = 0, max = 0;
};

/// Absolute position error of a calibrated robot on the validation set, by FK directly.
ErrorStats validate(const CalibratedRobot& robot, const MeasurementSet& validation) {
  ErrorStats s;
  for (const PointMeasurement& m : validation.points) {
    const Pose<double> F = flange_pose(robot.model, robot.tool.payload, robot.params, m.joints);
    const double e =
        (F * robot.tool.targets[static_cast<size_t>(m.target)].position_mm - m.position_mm).norm();
    s.mean += e;
    s.max = std::max(s.max, e);
  }
  s.mean /= static_cast<double>(validation.points.size());
  return s;
}

class ReferenceSet : public ::testing::Test {
 protected:
  void SetUp() override {
    model = load_robot("abb-irb120");
    tool = load_tool(test::data_path("irb120-published/tool.yaml"));
    calibration = reference_points("calibration.csv", tool);
    validation = reference_points("validation.csv", tool);
  }
  IdentificationResult run(CalibrationLevel level) {
    IdentifyOptions options;
    options.level = level;
    options.prediction_configurations = 200;
    return calibrate(model, tool, calibration, options);
  }
  RobotModel model;
  Tool tool;
  MeasurementSet calibration, validation;
};

TEST_F(ReferenceSet, FullFitReachesTheIndependentFitsNoiseFloor) {
  const IdentificationResult result = run(CalibrationLevel::Full);
  EXPECT_TRUE(result.status.converged) << result.status.message;
  EXPECT_EQ(result.identified_count, 30);  // 31 minus link3.d
  const ErrorStats s = validate(result.robot, validation);
  // Independent fit: mean 0.0343, max 0.0812 mm (validation noise included).
  EXPECT_NEAR(s.mean, 0.0343, 0.0005);
  EXPECT_NEAR(s.max, 0.0812, 0.001);
  // Calibration residual at the instrument noise (0.02 mm per axis).
  EXPECT_NEAR(result.sigma_mm, 0.02, 0.005);
  // Predicted against new measurements ≈ what the validation set shows (RMS of |e|).
  EXPECT_NEAR(result.predicted.rms_vs_measurements_mm, 0.0373, 0.006);
  RecordProperty("full_mean_mm", std::to_string(s.mean));
  RecordProperty("full_max_mm", std::to_string(s.max));
  std::cout << "reference full: mean " << s.mean << " max " << s.max << " sigma " << result.sigma_mm
            << " iterations " << result.status.iterations << " predicted vs truth rms "
            << result.predicted.rms_mm << "\n";
}

TEST_F(ReferenceSet, KinematicIsVisiblyWorseAndDropsLink3d) {
  const IdentificationResult result = run(CalibrationLevel::Kinematic);
  EXPECT_EQ(result.identified_count, 25);
  EXPECT_EQ(result.robot.status[static_cast<size_t>(link_param(3, 3))], ParameterStatus::Dropped);
  EXPECT_NE(result.robot.reason[static_cast<size_t>(link_param(3, 3))].find("link2.d"),
            std::string::npos);
  EXPECT_NE(result.robot.reason[static_cast<size_t>(link_param(3, 3))].find("parallel"),
            std::string::npos);
  const ErrorStats s = validate(result.robot, validation);
  EXPECT_NEAR(s.mean, 0.436, 0.002);  // independent fit: 0.436 mean, 1.897 max
  EXPECT_NEAR(s.max, 1.897, 0.005);
  std::cout << "reference kinematic: mean " << s.mean << " max " << s.max << "\n";
}

TEST_F(ReferenceSet, BaseOnlyPlacesTheNominalRobot) {
  const IdentificationResult result = run(CalibrationLevel::Base);
  EXPECT_EQ(result.identified_count, 6);
  EXPECT_TRUE(result.robot.base_fitted);
  const ErrorStats s = validate(result.robot, validation);
  EXPECT_NEAR(s.mean, 1.394, 0.002);  // independent fit: 1.394 mean, 4.064 max
  EXPECT_NEAR(s.max, 4.064, 0.005);
  std::cout << "reference base: mean " << s.mean << " max " << s.max << "\n";
}

TEST_F(ReferenceSet, NoiseFreeSetGivesBackTheTruth) {
  const MeasurementSet noise_free = reference_points("calibration_noisefree.csv", tool);
  IdentifyOptions options;
  options.level = CalibrationLevel::Full;
  const IdentificationResult result = calibrate(model, tool, noise_free, options);
  EXPECT_LT(result.rms_mm, 1e-5);
  const test::ReferenceTruth truth = test::load_reference_truth();
  double worst = 0;
  std::string worst_name;
  for (int i = 0; i < kComplianceOffset; ++i) {
    if (i == link_param(3, 3)) continue;
    double expected = truth.params[i], got = result.robot.params[i];
    if (i == link_param(2, 3)) {  // link2.d + link3.d come out as one sum
      expected += truth.params[link_param(3, 3)];
      got += result.robot.params[link_param(3, 3)];
    }
    const double error = std::abs(got - expected) * parameter_table()[i].to_external();
    if (error > worst) {
      worst = error;
      worst_name = parameter_table()[i].name;
    }
  }
  EXPECT_LT(worst, 2e-6) << worst_name;
  double worst_compliance = 0;
  for (int j = 2; j <= 6; ++j) {
    const int i = compliance_param(j);
    worst_compliance =
        std::max(worst_compliance, std::abs(result.robot.params[i] / truth.params[i] - 1.0));
  }
  EXPECT_LT(worst_compliance, 1e-4);
  std::cout << "noise-free: worst geometric error " << worst << " (" << worst_name
            << "), worst relative compliance error " << worst_compliance << "\n";
}

}  // namespace
}  // namespace robcal
