// ROS-Industrial OPW parameter files read as robcal models (io/opw_file.hpp): the flange poses
// against those computed by the C++ opw_kinematics (tests/data/opw/cases.yaml, NOTICE.md), the
// built-in KUKA KR 6 R900 sixx against its own ROS-Industrial OPW file, and bad input.

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <random>

#include "robcal/core/units.hpp"
#include "robcal/io/opw_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/closed_form_ik.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

Pose<double> fk(const RobotModel& model, const Vector6d& joints) {
  return flange_pose(model, PointMass{}, model.nominal(), joints);
}

// Every case of the oracle: the imported model's flange at the listed joints is the pose
// opw_kinematics computed (translation in metres to 16 digits, quaternion [x, y, z, w]).
void expect_oracle_poses(const std::string& parameters, const std::string& opw_file) {
  const RobotModel model = load_opw_robot(test::data_path("opw/" + opw_file));
  const YAML::Node root = YAML::LoadFile(test::data_path("opw/cases.yaml"));
  int cases = 0;
  double worst_mm = 0, worst_rad = 0;
  for (const YAML::Node& c : root["cases"]) {
    if (c["parameters"].as<std::string>() != parameters) continue;
    ++cases;
    Vector6d q;
    for (int i = 0; i < kJointCount; ++i) q[i] = deg2rad(c["joints"][i].as<double>());
    const YAML::Node t = c["pose"]["translation"], qn = c["pose"]["quaternion"];
    const Eigen::Vector3d p(1000 * t[0].as<double>(), 1000 * t[1].as<double>(),
                            1000 * t[2].as<double>());
    const Eigen::Matrix3d R = Eigen::Quaterniond(qn[3].as<double>(), qn[0].as<double>(),
                                                 qn[1].as<double>(), qn[2].as<double>())
                                  .normalized()
                                  .toRotationMatrix();
    const Pose<double> ours = fk(model, q);
    worst_mm = std::max(worst_mm, (ours.p - p).norm());
    worst_rad = std::max(worst_rad, rotation_distance(ours.R, R));
  }
  std::printf("[ %s from %s ] %d cases: worst %.2e mm, %.2e rad\n", parameters.c_str(),
              opw_file.c_str(), cases, worst_mm, worst_rad);
  EXPECT_EQ(cases, 1024);
  EXPECT_LT(worst_mm, 1e-9);
  EXPECT_LT(worst_rad, 1e-12);
  // The imported model has the ortho-parallel closed form.
  EXPECT_TRUE(analyze_ortho_parallel(model));
}

TEST(OpwFile, Irb2400FlangeMatchesOpwKinematics) {
  expect_oracle_poses("Irb2400_10", "opw_parameters_irb2400_10.yaml");
}

TEST(OpwFile, Kr6R700UnderAPlanningGroupMatchesOpwKinematics) {
  expect_oracle_poses("KukaKR6_R700_sixx", "opw_parameters_kr6r700_sixx.yaml");
}

TEST(OpwFile, RosIndustrialKr6R900FileGivesTheBuiltInRobot) {
  const RobotModel imported = load_opw_robot(test::data_path("opw/opw_parameters_kr6r900_2.yaml"));
  const RobotModel builtin = load_robot("kuka-kr6-r900-sixx");
  std::mt19937_64 rng(1515);
  double worst = 0;
  for (int n = 0; n < 1000; ++n) {
    Vector6d q;
    for (int i = 0; i < kJointCount; ++i) q[i] = std::uniform_real_distribution<double>(-3, 3)(rng);
    worst = std::max(worst, (fk(imported, q).p - fk(builtin, q).p).norm());
  }
  EXPECT_LT(worst, 1e-9);
}

// FANUC: ROS's joint 3 is the controller's J3 + J2; with the coupling the model takes the
// controller's values, so the two agree when fed (J) and (J1, J2, J3 + J2, ...).
TEST(OpwFile, FanucCouplingTakesTheControllersJ3) {
  OpwParameters p;
  p.a1 = 75;
  p.a2 = -75;
  p.c1 = 330;
  p.c2 = 300;
  p.c3 = 320;
  p.c4 = 80;
  p.offsets = {0, 0, deg2rad(-90), 0, 0, deg2rad(180)};
  p.signs = {1, 1, -1, -1, -1, -1};
  const RobotModel ros = robot_from_opw(p);
  OpwImportOptions options;
  options.fanuc_j2_j3_coupling = true;
  const RobotModel controller = robot_from_opw(p, options);
  Vector6d j;
  j << 0.1, 0.2, -0.3, 0.4, 0.5, 0.6;
  Vector6d j_ros = j;
  j_ros[2] += j[1];
  EXPECT_LT((fk(ros, j_ros).p - fk(controller, j).p).norm(), 1e-9);
  // And it is the built-in LR Mate 200iC (whose file states this derivation).
  const RobotModel builtin = load_robot("fanuc-lrmate200ic");
  EXPECT_LT((fk(builtin, j).p - fk(controller, j).p).norm(), 1e-9);
}

void expect_refusal(const std::string& text, const std::string& key, const std::string& what) {
  try {
    parse_opw_parameters(yaml::parse(text, "bad.yaml"));
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("bad.yaml"), std::string::npos) << message;
    EXPECT_NE(message.find(key), std::string::npos) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
  }
}

TEST(OpwFile, BadInputNamesTheKey) {
  const std::string geometry =
      "opw_kinematics_geometric_parameters: {a1: 0.1, a2: 0, b: 0, c1: 0.5, c2: 0.6, c3: 0.6, "
      "c4: 0.1}\n";
  expect_refusal("foo: 1\n", "opw_kinematics_geometric_parameters", "missing");
  expect_refusal(
      "opw_kinematics_geometric_parameters: {a1: 0.1, a2: 0, b: 0, c1: 0.5, c3: 0.6, c4: 0.1}\n",
      "c2", "missing");
  expect_refusal(
      "opw_kinematics_geometric_parameters: {a1: 0.1, a2: 0, b: 0.02, c1: 0.5, c2: 0.6, c3: "
      "0.6, c4: 0.1}\n",
      "b", "lateral offset");
  expect_refusal(geometry + "opw_kinematics_joint_offsets: [0, 0, deg(x), 0, 0, 0]\n",
                 "opw_kinematics_joint_offsets", "deg(x)");
  expect_refusal(geometry + "opw_kinematics_joint_offsets: [0, 0, 0]\n",
                 "opw_kinematics_joint_offsets", "6 joint offsets");
  expect_refusal(geometry + "opw_kinematics_joint_sign_corrections: [1, 1, 2, 1, 1, 1]\n",
                 "opw_kinematics_joint_sign_corrections", "1 or -1");
}

}  // namespace
}  // namespace robcal
