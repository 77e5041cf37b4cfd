// UR calibration.conf (io/ur_calibration_file.hpp) in and out through `model import|export`:
// FK of the imported model against UR's standard DH written out here with the calibrated sums
// of a real UR10e (ROS ur_calibration's doc/algorithm.rst example, metres and radians), the
// deltas round-tripping, and the refusals.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "refusal.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/identify/model_exchange.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/ur_calibration_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

/// The calibrated UR10e's DH sums (nominal + delta) as the controller reports them.
constexpr double kTheta[6] = {-2.4147806894359e-07, 1.60233952386695,      -1.68607190752171,
                              0.0837331147700119,   -1.01260355871158e-07, 3.91986209186124e-08};
constexpr double kA[6] = {2.12234865571206e-05,  0.0193171326277006,    -0.569251663611088,
                          -4.61409023720934e-05, -6.39280053471802e-05, 0};
constexpr double kD[6] = {0.180539811714259, 439.140974079901,  -446.027059806332,
                          7.0603368964236,   0.119811341150314, 0.115670917257426};
constexpr double kAlpha[6] = {1.57014608044242, 0.0013941666682559, 0.00693818880325995,
                              1.56998468543761, -1.57038520649543,  0};

/// UR's standard DH: Π Rz(q_i + θ_i)·Tz(d_i)·Tx(a_i)·Rx(α_i), in mm.
Eigen::Isometry3d ur_dh_flange(const Vector6d& q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 6; ++i) {
    T = T * Eigen::AngleAxisd(q[i] + kTheta[i], Eigen::Vector3d::UnitZ());
    T = T * Eigen::Translation3d(1000 * kA[i], 0, 1000 * kD[i]);
    T = T * Eigen::AngleAxisd(kAlpha[i], Eigen::Vector3d::UnitX());
  }
  return T;
}

std::string imported_model_file(const std::string& name) {
  const ModelImportResult r =
      import_model({"", "", "ur-calibration", test::data_path("ur/ur10e-calibration.conf"),
                    "universal-robots-ur10e"});
  EXPECT_TRUE(r.model_file);
  EXPECT_EQ(r.ur_calibration.calibration_status, 2);
  const std::string path = ::testing::TempDir() + name;
  write_file_atomically(path, r.yaml);
  return path;
}

// The model file written by the import, read back, reproduces UR's DH chain with the sums.
TEST(UrCalibration, ImportedModelMatchesUrsDhWithDeltas) {
  const CalibratedRobot robot = load_calibrated_robot(imported_model_file("ur-import.yaml"));
  auto rng = test::seeded_rng(1515);
  std::uniform_real_distribution<double> joint(-2 * std::numbers::pi, 2 * std::numbers::pi);
  double worst_mm = 0, worst_rad = 0;
  for (int n = 0; n < 10000; ++n) {
    Vector6d q;
    for (double& x : q) x = joint(rng);
    const Pose<double> ours =
        flange_pose(robot.model, robot.tool.payload, robot.params.data(), q.data());
    const Eigen::Isometry3d ur = ur_dh_flange(q);
    worst_mm = std::max(worst_mm, (ours.p - ur.translation()).norm());
    worst_rad = std::max(
        worst_rad, Eigen::AngleAxisd(Eigen::Matrix3d(ours.R * ur.rotation().transpose())).angle());
  }
  std::printf("[UR10e calibration.conf] 10000 configurations: worst %.2e mm, %.2e rad\n", worst_mm,
              worst_rad);
  EXPECT_LT(worst_mm, 1e-9);
  EXPECT_LT(worst_rad, 1e-12);
}

// File → model file → export: the same deltas (metres, radians) to 1e-9; nothing left out.
TEST(UrCalibration, DeltasRoundTrip) {
  const UrCalibration in = load_ur_calibration(test::data_path("ur/ur10e-calibration.conf"));
  const ModelExportResult out =
      export_model({"", imported_model_file("ur-round.yaml"), "ur-calibration"});
  EXPECT_TRUE(out.left_out.empty());
  EXPECT_EQ(out.left_out_max_mm, 0);
  const UrCalibration back = parse_ur_calibration(out.text, "exported");
  double worst = 0;
  for (int i = 0; i < kJointCount; ++i) {
    worst = std::max(worst, std::abs(back.delta_theta[i] - in.delta_theta[i]));
    worst = std::max(worst, std::abs(back.delta_alpha[i] - in.delta_alpha[i]));
    worst = std::max(worst, std::abs(back.delta_a[i] - in.delta_a[i]) / 1000);
    worst = std::max(worst, std::abs(back.delta_d[i] - in.delta_d[i]) / 1000);
  }
  EXPECT_LT(worst, 1e-9);
  // The nominal robot's deltas are all zero.
  const UrCalibration zero = parse_ur_calibration(
      export_model({"universal-robots-ur5e", "", "ur-calibration"}).text, "nominal");
  for (int i = 0; i < kJointCount; ++i) {
    EXPECT_EQ(zero.delta_theta[i], 0) << i;
    EXPECT_EQ(zero.delta_a[i], 0) << i;
    EXPECT_EQ(zero.delta_d[i], 0) << i;
    EXPECT_EQ(zero.delta_alpha[i], 0) << i;
  }
}

// A calibrated model's base placement off axis 1, tool and compliance are named as left out;
// base z and gamma are joint 1's d and θ.
TEST(UrCalibration, ExportNamesWhatTheFileCannotHold) {
  CalibratedRobot robot = CalibratedRobot::nominal(load_robot("universal-robots-ur10e"), Tool{});
  robot.params[0] = 1500;  // base.x, mm
  robot.params[2] = 0.25;  // base.z → delta_d[0]
  robot.params[5] = 1e-3;  // base.gamma → delta_theta[0]
  robot.params[compliance_param(2)] = 1e-8;
  robot.tool.tcp_given = true;
  robot.tool.flange_T_tcp.translation() << 0, 0, 150;
  const std::string path = ::testing::TempDir() + "ur-left-out.yaml";
  write_file_atomically(path, calibrated_robot_to_yaml(robot));
  const ModelExportResult out = export_model({"", path, "ur-calibration", 3, 500});
  ASSERT_EQ(out.left_out.size(), 3u);
  EXPECT_EQ(out.left_out[0].rfind("base.x", 0), 0u);
  EXPECT_EQ(out.left_out[1].rfind("joint2.compliance", 0), 0u);
  EXPECT_EQ(out.left_out[2].rfind("tool tcp", 0), 0u);
  EXPECT_GT(out.left_out_max_mm, 0);
  const UrCalibration c = parse_ur_calibration(out.text, "exported");
  EXPECT_NEAR(c.delta_d[0], 0.25, 1e-12);
  EXPECT_NEAR(c.delta_theta[0], 1e-3, 1e-15);
}

TEST(UrCalibration, Refusals) {
  const std::string deltas =
      "delta_theta = [0, 0, 0, 0, 0, 0]\ndelta_a = [0, 0, 0, 0, 0, 0]\n"
      "delta_d = [0, 0, 0, 0, 0, 0]\n";
  EXPECT_REFUSED(parse_ur_calibration(deltas, "c.conf"), InputError, "no [mounting] section");
  EXPECT_REFUSED(parse_ur_calibration("[mounting]\n" + deltas, "c.conf"), InputError,
                 "c.conf (delta_alpha): [mounting] has no delta_alpha");
  EXPECT_REFUSED(parse_ur_calibration("[mounting]\ndelta_a = [0, 0, x, 0, 0, 0]\n", "c.conf"),
                 InputError, "c.conf:2:18 (delta_a): expected a number, found 'x'");
  EXPECT_REFUSED(parse_ur_calibration("[mounting]\ndelta_a = [0, 0, 0]\n", "c.conf"), InputError,
                 "c.conf:2:10 (delta_a): expected six numbers (one per joint), found 3");
  EXPECT_REFUSED(parse_ur_calibration("[mounting]\ndelta_d 0\n", "c.conf"), InputError,
                 "c.conf:2:1: expected 'key = value'");
  UrCalibration c;
  c.file = "c.conf";
  c.delta_alpha[5] = 1e-3;
  EXPECT_REFUSED(params_from_ur_calibration(load_robot("universal-robots-ur10e"), c), InputError,
                 "c.conf (delta_alpha): the sixth delta_alpha is 0.001, not 0");
  EXPECT_REFUSED(params_from_ur_calibration(load_robot("fanuc-crx10ia-l"), UrCalibration{}),
                 InputError, "joint map must be the identity");
  EXPECT_REFUSED(import_model({"", "", "ur-calibration", "c.conf", ""}), InputError, "--robot");
}

}  // namespace
}  // namespace robcal
