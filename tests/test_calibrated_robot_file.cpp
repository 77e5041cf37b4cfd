// The calibrated model file: a round trip through YAML keeps every parameter, status, reason,
// the covariance and the tool; bad files give errors naming the file, line and key.

#include <gtest/gtest.h>

#include <filesystem>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/io/atomic_file.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

CalibratedRobot example_robot() {
  const RobotModel model = load_robot("fanuc-lrmate200ic");  // with a coupled joint map
  Tool tool = load_tool(test::data_path("irb120-published/tool.yaml"));
  tool.flange_T_tcp.translation() = Eigen::Vector3d(1, 2, 150);
  CalibratedRobot robot = CalibratedRobot::nominal(model, tool);
  robot.level = "kinematic";
  robot.base_fitted = true;
  auto rng = test::seeded_rng(3);
  std::normal_distribution<double> n(0, 1);
  for (int i = 0; i < kParameterCount; ++i) robot.params[i] += 0.01 * n(rng);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(kParameterCount, kParameterCount);
  for (int i = 0; i < kComplianceOffset; ++i) {
    robot.status[static_cast<size_t>(i)] = ParameterStatus::Identified;
    for (int j = 0; j < kComplianceOffset; ++j) A(i, j) = 1e-3 * n(rng);
  }
  robot.covariance = A * A.transpose();
  robot.status[static_cast<size_t>(link_param(3, 3))] = ParameterStatus::Dropped;
  robot.reason[static_cast<size_t>(link_param(3, 3))] = "depends on link2.d (+1.000)";
  robot.covariance.row(link_param(3, 3)).setZero();
  robot.covariance.col(link_param(3, 3)).setZero();
  return robot;
}

std::string temp_file(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("robcal_test_" + name)).string();
}

TEST(CalibratedRobotFile, RoundTripKeepsEverything) {
  CalibratedRobot robot = example_robot();
  robot.statistics = "rms_mm: 0.02";
  const std::string path = temp_file("model.yaml");
  write_file_atomically(path, calibrated_robot_to_yaml(robot));
  const CalibratedRobot back = load_calibrated_robot(path);
  EXPECT_EQ(back.statistics, robot.statistics);
  EXPECT_EQ(back.level, "kinematic");
  EXPECT_TRUE(back.base_fitted);
  EXPECT_EQ(back.model.name, robot.model.name);
  EXPECT_TRUE(back.model.joint_map.matrix.isApprox(robot.model.joint_map.matrix));
  for (int i = 0; i < kParameterCount; ++i) {
    EXPECT_NEAR(back.params[i], robot.params[i], 1e-14 * std::max(1.0, std::abs(robot.params[i])))
        << parameter_table()[i].name;
    EXPECT_EQ(back.status[static_cast<size_t>(i)], robot.status[static_cast<size_t>(i)]);
    EXPECT_EQ(back.reason[static_cast<size_t>(i)], robot.reason[static_cast<size_t>(i)]);
  }
  ASSERT_EQ(back.covariance.rows(), kParameterCount);
  EXPECT_LT((back.covariance - robot.covariance).norm(), 1e-14 * robot.covariance.norm());
  ASSERT_EQ(back.tool.targets.size(), robot.tool.targets.size());
  for (size_t t = 0; t < robot.tool.targets.size(); ++t)
    EXPECT_LT((back.tool.targets[t].position_mm - robot.tool.targets[t].position_mm).norm(), 1e-12);
  EXPECT_NEAR(back.tool.payload.mass_kg, 2.6, 1e-15);
  EXPECT_LT((back.tool.flange_T_tcp.translation() - Eigen::Vector3d(1, 2, 150)).norm(), 1e-12);
  std::filesystem::remove(path);
}

TEST(CalibratedRobotFile, NominalModelWithoutCovarianceLoads) {
  const CalibratedRobot robot = CalibratedRobot::nominal(load_robot("abb-irb120"), Tool{});
  const std::string path = temp_file("nominal.yaml");
  write_file_atomically(path, calibrated_robot_to_yaml(robot));
  const CalibratedRobot back = load_calibrated_robot(path);
  EXPECT_EQ(back.covariance.size(), 0);
  EXPECT_FALSE(back.base_fitted);
  EXPECT_EQ(back.params, robot.params);
  std::filesystem::remove(path);
}

void expect_error(const std::string& text, const std::string& expected_part) {
  const std::string path = temp_file("bad.yaml");
  write_file_atomically(path, text);
  try {
    load_calibrated_robot(path);
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(expected_part), std::string::npos) << message;
  }
  std::filesystem::remove(path);
}

TEST(CalibratedRobotFile, BadFilesNameFileLineAndKey) {
  const std::string good = calibrated_robot_to_yaml(example_robot());
  const auto replace = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  };
  expect_error(replace("name: link3.a,", "name: link3.q,"), "unknown parameter 'link3.q'");
  expect_error(replace("name: link3.a, unit: mm", "name: link3.a, unit: deg"),
               "link3.a is in mm, not deg");
  expect_error(replace("name: link3.a,", "name: link3.d,"), "given twice");
  expect_error(replace("status: identified", "status: maybe"), "unknown status 'maybe'");
  expect_error(replace("parameters:", "params:"), "not a calibrated model");
  // Unknown keys (issue 21): a typo would silently drop what the key holds.
  expect_error(replace("covariance:", "covarience:"),
               "(covarience): unknown key 'covarience': did you mean 'covariance'?");
  expect_error(replace("name: link3.a, unit: mm, nominal", "name: link3.a, unit: mm, nominl"),
               "unknown key 'nominl': did you mean 'nominal'?");
  expect_error(replace("  units:", "  unit:"), "unknown key 'unit': did you mean 'units'?");
  // Line numbers: the bad value sits on a line of its own.
  expect_error(replace("name: link4.a", "name: [oops"), "YAML syntax error");
}

}  // namespace
}  // namespace robcal
