// The built-in Fanuc and KUKA robot files against the ROS-Industrial OPW parameter sets, which
// use the controller's joint convention: the flange must agree for the same controller joints.
// The OPW forward kinematics below is written from Brandstötter, Angerer & Hofbaur (2014), the
// formulation opw_kinematics implements: q = sign·J − offset, then
//   C = (a1 + c2·sin q2 + k·sin(q2 + q3 + ψ3), b, c1 + c2·cos q2 + k·cos(q2 + q3 + ψ3)) turned by
//   q1, R = Rz(q1)·Ry(q2 + q3)·Rz(q4)·Ry(q5)·Rz(q6), flange = C + c4·R·ẑ, ψ3 = atan2(a2, c3), k =
//   |(a2, c3)|.
// KUKA: tests/data/opw/opw_parameters_kr6r900_2.yaml (ROS-I kuka_experimental, Apache-2.0).
// Fanuc: the ROS-I/JeroenDM parameters may not be copied into the project; the test reads them
// from $ROBCAL_EXTERNAL_DATA_DIR, else from shared/data/external beside the source tree or one of
// its parents (CI keeps shared/ beside the clone), and says where it looked when it is absent.
// ROS-I's Fanuc joint 3 is the relative elbow angle: joint_3_ros = J3 + J2 (J3 of the teach
// pendant is measured from the horizontal).

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <regex>

#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "test_external_data.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

struct OpwParameters {
  double a1, a2, b, c1, c2, c3, c4;  // mm
  std::array<double, 6> offsets;     // rad
  std::array<double, 6> signs;
};

/// A number or "deg(x)" as ROS-I writes offsets.
double opw_angle(const YAML::Node& node) {
  const std::string text = node.as<std::string>();
  std::smatch m;
  if (std::regex_match(text, m, std::regex(R"(\s*deg\(\s*([-+0-9.eE]+)\s*\)\s*)")))
    return deg2rad(std::stod(m[1]));
  return std::stod(text);
}

/// Reads an OPW parameter file (metres) whatever prefix its keys carry.
OpwParameters read_opw(const std::string& path) {
  const YAML::Node root = YAML::LoadFile(path);
  YAML::Node geometry, offsets, signs;
  auto find = [](const YAML::Node& map, const std::string& suffix) {
    for (const auto& kv : map)
      if (kv.first.as<std::string>().ends_with(suffix)) return kv.second;
    return YAML::Node();
  };
  YAML::Node block = root["manipulator"] ? root["manipulator"] : root;
  geometry = find(block, "geometric_parameters");
  offsets = find(block, "joint_offsets");
  signs = find(block, "joint_sign_corrections");
  OpwParameters p{};
  p.a1 = 1000 * geometry["a1"].as<double>();
  p.a2 = 1000 * geometry["a2"].as<double>();
  p.b = 1000 * geometry["b"].as<double>();
  p.c1 = 1000 * geometry["c1"].as<double>();
  p.c2 = 1000 * geometry["c2"].as<double>();
  p.c3 = 1000 * geometry["c3"].as<double>();
  p.c4 = 1000 * geometry["c4"].as<double>();
  for (int i = 0; i < 6; ++i) {
    p.offsets[i] = opw_angle(offsets[i]);
    p.signs[i] = signs[i].as<double>();
  }
  return p;
}

Pose<double> opw_forward(const OpwParameters& p, const Vector6d& joints) {
  std::array<double, 6> q;
  for (int i = 0; i < 6; ++i) q[i] = joints[i] * p.signs[i] - p.offsets[i];
  const double psi3 = std::atan2(p.a2, p.c3), k = std::hypot(p.a2, p.c3);
  const double cx1 = p.c2 * std::sin(q[1]) + k * std::sin(q[1] + q[2] + psi3) + p.a1;
  const double cz1 = p.c2 * std::cos(q[1]) + k * std::cos(q[1] + q[2] + psi3) + p.c1;
  const Eigen::Vector3d C(cx1 * std::cos(q[0]) - p.b * std::sin(q[0]),
                          cx1 * std::sin(q[0]) + p.b * std::cos(q[0]), cz1);
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  Pose<double> out;
  out.R = (AngleAxisd(q[0], Vector3d::UnitZ()) * AngleAxisd(q[1] + q[2], Vector3d::UnitY()) *
           AngleAxisd(q[3], Vector3d::UnitZ()) * AngleAxisd(q[4], Vector3d::UnitY()) *
           AngleAxisd(q[5], Vector3d::UnitZ()))
              .toRotationMatrix();
  out.p = C + p.c4 * out.R.col(2);
  return out;
}

struct Agreement {
  double worst_mm = 0, worst_rad = 0;
};

/// Our flange vs OPW's for 2,000 seeded random controller joints inside the limits.
Agreement compare(const std::string& robot, const OpwParameters& opw, bool fanuc_coupling) {
  const RobotModel model = load_robot(robot);
  std::mt19937_64 rng(42);
  Agreement a;
  for (int n = 0; n < 2000; ++n) {
    Vector6d J;
    for (int i = 0; i < kJointCount; ++i)
      J[i] =
          std::uniform_real_distribution<double>(model.limits[i].lower, model.limits[i].upper)(rng);
    Vector6d ros = J;
    if (fanuc_coupling) ros[2] = J[2] + J[1];
    const Pose<double> ours = flange_pose(model, PointMass{}, model.nominal(), J);
    const Pose<double> theirs = opw_forward(opw, ros);
    a.worst_mm = std::max(a.worst_mm, (ours.p - theirs.p).norm());
    a.worst_rad = std::max(a.worst_rad, rotation_distance(ours.R, theirs.R));
  }
  return a;
}

TEST(RobotFiles, KukaKr6R900MatchesRosIndustrialOpwParameters) {
  const OpwParameters opw = read_opw(test::data_path("opw/opw_parameters_kr6r900_2.yaml"));
  const Agreement a = compare("kuka-kr6-r900-sixx", opw, false);
  std::printf("KR 6 R900 vs ROS-I OPW: worst %.2e mm, %.2e rad\n", a.worst_mm, a.worst_rad);
  EXPECT_LT(a.worst_mm, 1e-9);
  EXPECT_LT(a.worst_rad, 1e-12);
}

TEST(RobotFiles, FanucLrMate200iCMatchesRosIndustrialOpwParameters) {
  const test::ExternalFile file =
      test::find_external_data("JeroenDM__wip_fanuc_opw_parameters/kinematics_lrmate200ic.yaml");
  if (!file.path)
    GTEST_SKIP() << "the read-only reference is not beside the source tree; looked at:"
                 << file.searched;
  const std::filesystem::path& path = *file.path;
  const OpwParameters opw = read_opw(path.string());
  // The OPW geometry is docs/method/02-frames.md §7's table: a1 = link2.a, a2 = −link4.a, c1 = d1,
  // c2 = link3.a, c3 = link4.d, c4 = link6.d.
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  EXPECT_NEAR(opw.a1, model.mdh[1].a, 1e-9);
  EXPECT_NEAR(opw.a2, -model.mdh[3].a, 1e-9);
  EXPECT_NEAR(opw.c1, model.mdh[0].d, 1e-9);
  EXPECT_NEAR(opw.c2, model.mdh[2].a, 1e-9);
  EXPECT_NEAR(opw.c3, model.mdh[3].d, 1e-9);
  EXPECT_NEAR(opw.c4, model.mdh[5].d, 1e-9);
  const Agreement a = compare("fanuc-lrmate200ic", opw, true);
  std::printf("LR Mate 200iC vs ROS-I OPW (J3_ros = J3 + J2): worst %.2e mm, %.2e rad\n",
              a.worst_mm, a.worst_rad);
  // The file writes π/2 and π to 11 digits (5e-12 rad): 1e-8 mm over the 700 mm arm.
  EXPECT_LT(a.worst_mm, 1e-8);
  EXPECT_LT(a.worst_rad, 1e-10);
  // Without the coupling the flange would be far off: the map is what makes them agree.
  EXPECT_GT(compare("fanuc-lrmate200ic", opw, false).worst_mm, 10.0);
}

}  // namespace
}  // namespace robcal
