// `model export` (identify/model_exchange.hpp): the accuracy cost of what URDF leaves out,
// against a hand-derived figure, and the import's choice of file.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/identify/model_exchange.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

// A joint 6 scale 1 + ε turns the tool by ε·q6 about axis 6 (the flange z of the IRB 120): a
// TCP r = 100 mm off the axis moves by 2r·sin(ε·|q6|/2) ≈ r·ε·|q6|. With q6 uniform on ±L
// (L = 400°): max → r·ε·L, RMS → r·ε·L/√3.
TEST(ModelExchange, CostOfAJointScaleIsTheArcOfTheTcp) {
  CalibratedRobot robot = CalibratedRobot::nominal(load_robot("abb-irb120"), Tool{});
  const double eps = 1e-4, r = 100, L = 400 * std::numbers::pi / 180;
  robot.params[scale_param(6)] = 1 + eps;
  robot.tool.tcp_given = true;
  robot.tool.flange_T_tcp.translation() << r, 0, 0;
  const std::string path = ::testing::TempDir() + "model-exchange-scale.yaml";
  write_file_atomically(path, calibrated_robot_to_yaml(robot));
  const ModelExportResult out = export_model({"", path, "urdf", 7, 20000});
  ASSERT_EQ(out.left_out.size(), 1u);
  EXPECT_EQ(out.left_out[0].rfind("joint6.scale", 0), 0u);
  EXPECT_NEAR(out.left_out_max_mm, r * eps * L, 0.002 * r * eps * L);
  EXPECT_NEAR(out.left_out_rms_mm, r * eps * L / std::sqrt(3.0), 0.02 * r * eps * L);
  EXPECT_NE(out.text.find("<link name=\"tcp\"/>"), std::string::npos);
}

TEST(ModelExchange, NominalRobotLeavesNothingOut) {
  const ModelExportResult out = export_model({"abb-irb120", ""});
  EXPECT_TRUE(out.left_out.empty());
  EXPECT_EQ(out.left_out_max_mm, 0);
}

TEST(ModelExchange, ImportChoosesTheFileKind) {
  const std::string path = ::testing::TempDir() + "model-exchange-irb120.urdf";
  write_file_atomically(path, export_model({"abb-irb120", ""}).text);
  EXPECT_FALSE(import_model({path, ""}).model_file);  // a robot file
  const ModelImportResult skew = import_model({test::data_path("urdf/skew6r.urdf"), ""});
  EXPECT_TRUE(skew.model_file);  // the tilted mount needs the base parameters
  EXPECT_NE(skew.yaml.find("base_fitted: true"), std::string::npos);
}

}  // namespace
}  // namespace robcal
