// The calibrate workflow the CLI and Python share (calibrate_workflow.hpp) and the measurement
// options validate takes through its request: the same numbers as the library calls it wraps,
// the option checks by flag, the refusal to write an untrustworthy model, units and rotation
// orders declared for files that do not declare them, and the poses-without-a-tcp warning.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/identify/calibrate_workflow.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/validate/validate_workflow.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

namespace fs = std::filesystem;

CalibrateFilesRequest published_request() {
  CalibrateFilesRequest request;
  request.robot = "abb-irb120";
  request.tool = test::data_path("irb120-published/tool.yaml");
  request.measurements = test::data_path("irb120-published/calibration.csv");
  return request;
}

std::string expect_input_error(const CalibrateFilesRequest& request) {
  try {
    (void)calibrate_files(request);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return {};
}

TEST(CalibrateWorkflow, SameNumbersAsTheLibraryCallsItWraps) {
  CalibrateFilesRequest request = published_request();
  request.request.options.instrument_sigma_mm = 0.02;
  request.request.kfold = 4;
  const CalibrationRun run = calibrate_files(request);
  const Tool tool = load_tool(request.tool);
  const MeasurementFile file = read_measurements_csv(request.measurements, tool);
  const CalibrationRun direct =
      run_calibration(load_robot("abb-irb120"), tool, file.measurements, request.request);
  EXPECT_EQ(run.result.values, direct.result.values);
  EXPECT_EQ(run.result.rms_mm, direct.result.rms_mm);
  EXPECT_EQ(run.result.noise_test.chi_square, direct.result.noise_test.chi_square);
  ASSERT_TRUE(run.cross_validation && direct.cross_validation);
  EXPECT_EQ(run.cross_validation->errors_mm, direct.cross_validation->errors_mm);
  EXPECT_EQ(run.warnings, direct.warnings);
  EXPECT_EQ(run.file, request.measurements);
  // One residual per row, whose statistics are the reported ones.
  ASSERT_EQ(run.result.row_errors_mm.size(), file.measurements.size());
  double sum = 0, sum_sq = 0;
  for (double e : run.result.row_errors_mm) {
    sum += e;
    sum_sq += e * e;
  }
  const auto rows = static_cast<double>(run.result.row_errors_mm.size());
  EXPECT_NEAR(sum / rows, run.result.mean_mm, 1e-12);
  EXPECT_NEAR(std::sqrt(sum_sq / rows), run.result.rms_mm, 1e-12);
}

TEST(CalibrateWorkflow, OptionsAreCheckedByFlag) {
  CalibrateFilesRequest request = published_request();
  request.request.options.instrument_sigma_mm = -1;
  EXPECT_NE(expect_input_error(request).find("finite number of mm >= 0"), std::string::npos);
  request.request.options.instrument_sigma_mm = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(expect_input_error(request).find("finite number of mm >= 0"), std::string::npos);
  request = published_request();
  request.loss = "cauchy";
  EXPECT_NE(expect_input_error(request).find("unknown loss 'cauchy'"), std::string::npos);
  request = published_request();
  request.euler = "ZZY";
  EXPECT_NE(expect_input_error(request).find("'ZZY' is not a rotation order"), std::string::npos);
  request = published_request();
  request.model = "model.yaml";
  EXPECT_NE(expect_input_error(request).find("give either --robot or --model"), std::string::npos);
  request = published_request();
  request.tool.clear();
  EXPECT_NE(expect_input_error(request).find("give the tool file (--tool)"), std::string::npos);
}

TEST(CalibrateWorkflow, AnUntrustworthyModelIsNotWrittenUnlessForced) {
  CalibrateFilesRequest request = published_request();
  request.robot = "abb-irb1600-6-12";  // another arm whose joint limits hold the data
  const CalibrationRun run = calibrate_files(request);
  ASSERT_FALSE(run.problems.empty());
  const fs::path path = fs::path(::testing::TempDir()) / "robcal_refused_model.yaml";
  fs::remove(path);
  const std::optional<std::string> refusal = write_calibration(run, path.string(), false, nullptr);
  ASSERT_TRUE(refusal.has_value());
  EXPECT_NE(refusal->find("not written: the fit is not trustworthy"), std::string::npos);
  EXPECT_NE(refusal->find(run.problems.front()), std::string::npos);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(write_calibration(run, path.string(), true, nullptr).has_value());
  EXPECT_TRUE(fs::exists(path));
  fs::remove(path);
  // A plausible fit is written without force.
  const CalibrationRun fine = calibrate_files(published_request());
  EXPECT_TRUE(fine.problems.empty());
  EXPECT_FALSE(write_calibration(fine, path.string(), false, nullptr).has_value());
  EXPECT_TRUE(fs::exists(path));
  fs::remove(path);
}

/// `text` written to a file of the test's temporary folder; returns its path.
std::string write_temporary(const std::string& name, const std::string& text) {
  const fs::path path = fs::path(::testing::TempDir()) / name;
  std::ofstream(path) << text;
  return path.string();
}

TEST(CalibrateWorkflow, ValidateTakesUnitsAndEulerOrderLikeCalibrate) {
  // The validation set in metres: declared by --units, the same errors as in millimetres.
  const test::CsvTable table = test::read_csv(test::data_path("irb120-published/validation.csv"));
  std::string metres = "config,target,j1,j2,j3,j4,j5,j6,x,y,z\n";
  for (const auto& row : table.rows) {
    metres += fmt::format("{:.0f},{:.0f}", row[0], row[1]);
    for (int j = 2; j < 8; ++j) metres += fmt::format(",{:.9f}", row[static_cast<size_t>(j)]);
    for (int a = 8; a < 11; ++a)
      metres += fmt::format(",{:.12f}", row[static_cast<size_t>(a)] / 1000);
    metres += "\n";
  }
  ValidateRequest request{"abb-irb120", test::data_path("irb120-published/tool.yaml"),
                          "",           test::data_path("irb120-published/validation.csv"),
                          "",           {}};
  request.options.fit_base = true;
  const ValidateResult mm = validate(request);
  request.measurements = write_temporary("robcal_validation_m.csv", metres);
  request.units = "m";
  const ValidateResult m = validate(request);
  ASSERT_TRUE(mm.report && m.report);
  EXPECT_NEAR(m.report->positions.position_mm.mean, mm.report->positions.position_mm.mean, 1e-6);
  EXPECT_NEAR(m.report->positions.position_mm.max, mm.report->positions.position_mm.max, 1e-6);
  request.euler = "intrinsic ZZY";
  try {
    (void)validate(request);
    ADD_FAILURE() << "bad rotation order accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "--euler");
    EXPECT_NE(std::string(e.what()).find("'intrinsic ZZY' is not a rotation order"),
              std::string::npos);
  }
}

TEST(CalibrateWorkflow, ValidateWarnsOfPosesWithoutATcp) {
  const RobotModel model = load_robot("abb-irb120");
  std::string poses = "config,j1,j2,j3,j4,j5,j6,x,y,z,qw,qx,qy,qz\n";
  const std::vector<Vector6d> joints = {(Vector6d() << 0.1, 0.2, 0.1, 0.3, 0.5, 0.2).finished(),
                                        (Vector6d() << -0.4, 0.1, 0.3, -0.2, 0.8, 1).finished(),
                                        (Vector6d() << 0.6, -0.3, 0.2, 0.5, -0.6, -1).finished()};
  for (size_t k = 0; k < joints.size(); ++k) {
    const Pose<double> F = flange_pose(model, PointMass{}, model.nominal(), joints[k]);
    const Eigen::Quaterniond q(F.R);
    poses += fmt::format(
        "P{},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},"
        "{:.12f},{:.12f},{:.12f},{:.12f}\n",
        k + 1, rad2deg(joints[k][0]), rad2deg(joints[k][1]), rad2deg(joints[k][2]),
        rad2deg(joints[k][3]), rad2deg(joints[k][4]), rad2deg(joints[k][5]), F.p.x(), F.p.y(),
        F.p.z(), q.w(), q.x(), q.y(), q.z());
  }
  ValidateRequest request{"abb-irb120", write_temporary("robcal_no_tcp_tool.yaml", "{}\n"),
                          "",           write_temporary("robcal_no_tcp_poses.csv", poses),
                          "",           {}};
  request.options.fit_base = true;
  const ValidateResult flange = validate(request);
  ASSERT_EQ(flange.warnings.size(), 1U);
  EXPECT_EQ(flange.warnings[0].rfind("POSES WITHOUT A TCP: the tool file has no 'tcp'", 0), 0U);
  EXPECT_LT(flange.report->positions.position_mm.max, 1e-6);  // the flange's own poses
  request.tool = write_temporary("robcal_tcp_tool.yaml",
                                 "tcp: {position_mm: [0, 0, 0], quaternion_wxyz: [1, 0, 0, 0]}\n");
  EXPECT_TRUE(validate(request).warnings.empty());
}

}  // namespace
}  // namespace robcal
