// The calibrated model file, byte for byte: a fixed calibration run (hand-set statistics with
// awkward decimals, cross-validation, problems, provenance) and a re-identification of it are
// written and compared with the files the serializer wrote when this test was added, so that
// changing how the file is built (issue 14: no YAML string round trips) cannot change a byte.
// Regenerated once, when the prediction's keys took their unit (against_truth: {mean_mm, rms_mm,
// max_mm}) and the model's tool section became the tool file's writer (target names quoted).

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "robcal/identify/calibrated_robot_file.hpp"
#include "robcal/identify/calibration_output.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

IdentificationResult fixed_result() {
  const Tool tool = load_tool(test::data_path("irb120-published/tool.yaml"));
  IdentificationResult r;
  r.robot = CalibratedRobot::nominal(load_robot("abb-irb120"), tool);
  r.robot.level = "full";
  r.robot.base_fitted = true;
  r.status = {true, 7, "Function tolerance reached.", 1.23456789012, 0.0212345678901};
  r.warnings = {"link6.d and tool.z are near-dependent: link6.d held at nominal"};
  r.residual_count = 180;
  r.identified_count = 27;
  r.sigma_mm = 0.0213456789123;
  r.mean_mm = 0.0187654321987;
  r.rms_mm = 0.0212345678901;
  r.max_mm = 0.0654321098765;
  r.start_rms_mm = 1.23456789012;
  r.noise_test = {true, 0.02, 203.456789012, 153, 0.00431234567, false};
  r.huber_scale_mm = 0.0612345678;
  r.by_target = {{"1", 20, 0.0201234567891, 0.0512345678912},
                 {"2", 20, 0.0223456789012, 0.0654321098765}};
  r.correlations = {{"link2.a", "joint2.offset", -0.912345678912}};
  r.outliers = {{"17", 19, 0.0654321098765}};
  r.condition_number = 1234.56789012345;
  r.predicted = {.configurations = 1000,
                 .mean_mm = 0.0112345678901,
                 .rms_mm = 0.0123456789012,
                 .max_mm = 0.0345678901234,
                 .measurement_sigma_mm = 0.02,
                 .mean_vs_measurements_mm = 0.0354321098765,
                 .rms_vs_measurements_mm = 0.0398765432109};
  return r;
}

CalibrationRun fixed_run() {
  CalibrationRun run;
  run.result = fixed_result();
  CrossValidation cv;
  cv.folds = 5;
  cv.seed = 1;
  cv.mean_mm = 0.0398765432198;
  cv.std_mm = 0.0176543219876;
  cv.max_mm = 0.0987654321098;
  run.cross_validation = cv;
  run.problems = {"the fit did not converge: check the measurements"};
  return run;
}

Provenance fixed_provenance() {
  Provenance p;
  p.robcal_version = "0.0.0";
  p.date_utc = "2026-11-29T08:00:00Z";
  p.command_line = "robcal calibrate --robot abb-irb120 --out 'my model.yaml'";
  p.files = {{"tool", "tests/data/irb120-published/tool.yaml", std::string(64, 'a')}};
  p.instrument = "laser tracker";
  p.instrument_sigma_mm = 0.02;
  p.robot = "ABB IRB 120";
  p.level = "full";
  p.seed = 1;
  return p;
}

void expect_golden(const std::string& written, const std::string& golden) {
  const std::string path = test::data_path("golden/" + golden);
  const std::string expected = read_text(path);
  if (written == expected) return;
  const std::string actual = ::testing::TempDir() + golden;
  std::ofstream(actual, std::ios::binary) << written;
  ADD_FAILURE() << "the model file differs from " << path << "; written: " << actual;
}

TEST(CalibrationOutputGolden, FreshCalibrationFile) {
  const Provenance provenance = fixed_provenance();
  expect_golden(calibrated_model_file(fixed_run(), &provenance), "calibrated_model.yaml");
}

TEST(CalibrationOutputGolden, ReidentificationAppendsARecord) {
  // The model file above read back, then re-identified twice: the first record is kept verbatim.
  const Provenance provenance = fixed_provenance();
  IdentificationResult again = fixed_result();
  again.robot = parse_calibrated_robot(calibrated_model_file(fixed_run(), &provenance),
                                       "calibrated_model.yaml");
  again.reidentification =
      Reidentification{"base",
                       {{"base.x", "mm", 0.0, 0.123456789012345, 0.00123456789012},
                        {"base.rz", "deg", 0.0, -0.0123456789012345, 0.000123456789012}}};
  again.robot = parse_calibrated_robot(calibrated_model_file(again, nullptr), "first.yaml");
  again.reidentification->what = "tool";
  expect_golden(calibrated_model_file(again, nullptr), "reidentified_model.yaml");
}

TEST(CalibrationOutputGolden, ModelFilesRoundTripByteForByte) {
  // Read, then written with what was read (its statistics and records kept): the same bytes.
  for (const std::string golden : {"calibrated_model.yaml", "reidentified_model.yaml"}) {
    const std::string text = read_text(test::data_path("golden/" + golden));
    EXPECT_EQ(calibrated_robot_to_yaml(parse_calibrated_robot(text, golden)), text) << golden;
  }
}

TEST(CalibrationOutputGolden, ModelToolSectionIsTheToolFile) {
  // One writer (emit_tool): the model's `tool:` is the tool file's text, indented under the key.
  const CalibratedRobot robot = fixed_result().robot;
  std::istringstream tool_file(tool_to_yaml(robot.tool));
  std::string indented = "tool:\n";
  for (std::string line; std::getline(tool_file, line);)
    if (!line.empty()) indented += "  " + line + "\n";
  EXPECT_NE(calibrated_robot_to_yaml(robot).find(indented), std::string::npos) << indented;
}

}  // namespace
}  // namespace robcal
