// The robot library (data/robots): every file loads with a maker, a source and a reach; the
// MDH tables written from ROS-Industrial URDFs and OPW files reproduce the URDF joint chains
// (origins and axes transcribed here from the xacro files the robot files name); every robot's
// nominal IK is dispatched (closed form where the geometry has one) and round-trips random
// configurations of every branch.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/closed_form_ik.hpp"
#include "robcal/kinematics/nominal_chain.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "test_compensate_support.hpp"
#include "test_ik_round_trip.hpp"

namespace robcal {
namespace {

/// One URDF revolute joint: origin xyz (m), axis; rpy is zero on all chains below.
struct UrdfJoint {
  Eigen::Vector3d xyz, axis;
};

/// A URDF chain from base_link to the flange frame robcal uses (ROS tool0 or KUKA's $FLANGE).
struct UrdfChain {
  const char* file;
  std::array<UrdfJoint, 6> joints;
  Eigen::Vector3d tool_xyz;
  Eigen::Vector3d tool_rpy;
  bool fanuc_j3;  ///< ROS joint 3 = controller J3 + J2
};

Eigen::Matrix3d rpy(const Eigen::Vector3d& a) {
  return (Eigen::AngleAxisd(a.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(a.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(a.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Pose<double> urdf_fk(const UrdfChain& c, Vector6d q) {
  if (c.fanuc_j3) q[2] += q[1];
  Pose<double> T;
  for (int i = 0; i < 6; ++i) {
    T.p += T.R * (1000.0 * c.joints[i].xyz);
    T.R = T.R * Eigen::AngleAxisd(q[i], c.joints[i].axis).toRotationMatrix();
  }
  T.p += T.R * (1000.0 * c.tool_xyz);
  T.R = T.R * rpy(c.tool_rpy);
  return T;
}

const Eigen::Vector3d X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
const double kPi = std::numbers::pi;

/// The CRX layout of crx10ial_macro.xacro with upper arm `upper_arm` (m): the CRX-10iA/L has
/// 0.710, the CRX-10iA 0.540 (its robot file names the source of that length).
UrdfChain crx_chain(const char* file, double upper_arm) {
  return {file,
          {{{{0, 0, 0.245}, Z},
            {{0, 0, 0}, Y},
            {{0, 0, upper_arm}, -Y},
            {{0, 0, 0}, -X},
            {{0.540, -0.150, 0}, -Y},
            {{0.160, 0, 0}, -X}}},
          {0, 0, 0},
          {kPi, -kPi / 2, 0},
          true};
}

// Transcribed from the xacro files named in each robot file.
const std::vector<UrdfChain>& chains() {
  static const std::vector<UrdfChain> c = {
      {"fanuc-lrmate200id",
       {{{{0, 0, 0.330}, Z},
         {{0.050, 0, 0}, Y},
         {{0, 0, 0.330}, -Y},
         {{0, 0, 0.035}, -X},
         {{0.335, 0, 0}, -Y},
         {{0.080, 0, 0}, -X}}},
       {0, 0, 0},
       {kPi, -kPi / 2, 0},
       true},
      crx_chain("fanuc-crx10ia-l", 0.710),
      crx_chain("fanuc-crx10ia", 0.540),
      {"fanuc-m20ia",
       {{{{0, 0, 0.525}, Z},
         {{0.150, 0, 0}, Y},
         {{0, 0, 0.790}, -Y},
         {{0, 0, 0.250}, -X},
         {{0.835, 0, 0}, -Y},
         {{0.100, 0, 0}, -X}}},
       {0, 0, 0},
       {kPi, -kPi / 2, 0},
       true},
      {"fanuc-r2000ic-165f",
       {{{{0, 0, 0.670}, Z},
         {{0.312, 0, 0}, Y},
         {{0, 0, 1.075}, -Y},
         {{0, 0, 0.225}, -X},
         {{1.280, 0, 0}, -Y},
         {{0.215, 0, 0}, -X}}},
       {0, 0, 0},
       {kPi, -kPi / 2, 0},
       true},
      {"yaskawa-gp7",
       {{{{0, 0, 0.330}, Z},
         {{0.040, 0, 0}, Y},
         {{0, 0, 0.445}, -Y},
         {{0.440, 0, 0.040}, -X},
         {{0, 0, 0}, -Y},
         {{0, 0, 0}, -X}}},
       {0.080, 0, 0},
       {kPi, -kPi / 2, 0},
       false},
      {"kuka-kr120-r2500-pro",
       {{{{0, 0, 0.675}, -Z},
         {{0.350, 0, 0}, Y},
         {{1.150, 0, 0}, Y},
         {{1.000, 0, -0.041}, -X},
         {{0, 0, 0}, Y},
         {{0, 0, 0}, -X}}},
       {0.215, 0, 0},
       {0, kPi / 2, 0},
       false},
      {"abb-irb6700-235-265",
       {{{{0, 0, 0.288}, Z},
         {{0.320, 0, 0.492}, Y},
         {{0, 0, 1.135}, Y},
         {{0, 0, 0.200}, X},
         {{1.1825, 0, 0}, Y},
         {{0.165, 0, 0}, X}}},
       {0.035, 0, 0},
       {0, kPi / 2, 0},
       false},
      {"kuka-kr10-r1100-sixx",
       {{{{0, 0, 0.400}, -Z},
         {{0.025, 0, 0}, Y},
         {{0.560, 0, 0}, Y},
         {{0, 0, 0.035}, -X},
         {{0.515, 0, 0}, Y},
         {{0.080, 0, 0}, -X}}},
       {0, 0, 0},
       {0, kPi / 2, 0},
       false},
      {"staubli-tx2-60",
       {{{{0, 0, 0.375}, Z},
         {{0, 0, 0}, Y},
         {{0, 0.020, 0.290}, Y},
         {{0, 0, 0}, Z},
         {{0, 0, 0.310}, Y},
         {{0, 0, 0.070}, Z}}},
       {0, 0, 0},
       {0, 0, 0},
       false},
  };
  return c;
}

using test::random_joints;

TEST(RobotLibrary, EveryRobotHasMakerSourceAndReach) {
  const auto names = builtin_robot_names();
  EXPECT_GE(names.size(), 30u);
  for (const std::string& name : names) {
    const RobotModel model = load_robot(name);
    EXPECT_FALSE(model.manufacturer.empty()) << name;
    EXPECT_FALSE(model.source.empty()) << name;
    EXPECT_GT(model.reach_mm, 0) << name;
    // The reach stated is what the arm reaches: the flange's largest distance from axis 1 over
    // random joints lies within 25 % of it (data sheets measure to the wrist centre or flange).
    std::mt19937_64 rng(7);
    const NominalChain chain = make_nominal_chain(model);
    double largest = 0;
    for (int n = 0; n < 20000; ++n) {
      const Pose<double> T = nominal_flange_pose(chain, random_joints(model, rng));
      largest = std::max(largest, std::hypot(T.p.x(), T.p.y()));
    }
    EXPECT_NEAR(largest / model.reach_mm, 1.0, 0.25) << name << ": " << largest << " mm";
  }
}

TEST(RobotLibrary, MdhTablesReproduceTheUrdfChains) {
  std::mt19937_64 rng(2511);
  for (const UrdfChain& c : chains()) {
    const RobotModel model = load_robot(c.file);
    const NominalChain chain = make_nominal_chain(model);
    double worst_mm = 0, worst_rad = 0;
    for (int n = 0; n < 10000; ++n) {
      const Vector6d q = random_joints(model, rng);
      const Pose<double> ours = nominal_flange_pose(chain, q);
      const Pose<double> urdf = urdf_fk(c, q);
      worst_mm = std::max(worst_mm, (ours.p - urdf.p).norm());
      worst_rad = std::max(worst_rad, rotation_distance(ours.R, urdf.R));
    }
    EXPECT_LT(worst_mm, 1e-9) << c.file;
    EXPECT_LT(worst_rad, 1e-12) << c.file;
  }
}

// Every robot with a closed form: random configurations labelled by the link frames, the
// branch solver seeded with them returns them (test::ik_round_trip_ok: the pose, and the joints
// within the wrist's conditioning); every robot has one (the general 6R inverse for the CRX).
TEST(RobotLibrary, EveryRobotsIkRoundTripsEveryBranch) {
  std::mt19937_64 rng(2512);
  for (const std::string& name : builtin_robot_names()) {
    const RobotModel model = load_robot(name);
    std::string why;
    const auto g = analyze_closed_form(model, &why);
    ASSERT_TRUE(g) << name << ": " << why;
    const NominalChain chain = make_nominal_chain(model);
    std::array<int, 8> count{};
    int failures = 0, draws = 0;
    while (*std::min_element(count.begin(), count.end()) < 2000 && draws < 400000) {
      ++draws;
      const Vector6d q = random_joints(model, rng);
      const ArmConfig config = arm_config(model, q);
      if (count[config.index()] >= 2000) continue;
      ++count[config.index()];
      const Pose<double> target = nominal_flange_pose(chain, q);
      const IkBranchResult r = nominal_ik_branch(*g, target, config, q);
      if (r.status != IkStatus::Solved) {
        ++failures;
        continue;
      }
      if (!test::ik_round_trip_ok(model, chain, q, target, r.solution.joints)) {
        ++failures;
        std::printf("  %s: drawn joints (rad) %a %a %a %a %a %a, returned %.3e rad away\n",
                    name.c_str(), q[0], q[1], q[2], q[3], q[4], q[5],
                    (r.solution.joints - q).cwiseAbs().maxCoeff());
      }
    }
    std::string counts;
    for (int c : count) counts += " " + std::to_string(c);
    std::printf("[ %s, %s ] %d draws, per branch:%s, %d failures\n", name.c_str(),
                closed_form_name(*g), draws, counts.c_str(), failures);
    // Open (issue 15, docs/method/02-frames.md §7): the general 6R inverse still loses a
    // near-singular twin on the CRX-10iA/L (|sin θ5| = 2e-3) in about 60,000 configurations
    // (none in these draws; the TX2-60 lost 1 of 16,000 here before session 8); the closed forms
    // lose none.
    const bool general = std::holds_alternative<General6rGeometry>(*g);
    EXPECT_LE(failures, general ? 1 : 0) << name;
    // A branch the joint limits exclude entirely gets no configurations (none is drawn).
    for (int c : count) EXPECT_TRUE(c == 2000 || draws == 400000) << name;
  }
}

}  // namespace
}  // namespace robcal
