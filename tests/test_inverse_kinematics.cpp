// Nominal closed-form IK and numeric IK: round trips FK(q) → IK ∋ q on 100,000 seeded random
// configurations per built-in robot, configuration labels recomputed from the link frames,
// singular and unreachable cases, equivalent turns, and DLS on a calibrated (compliant) model.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>

#include "../src/kinematics/fast_atan2.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/kinematics/nominal_chain.hpp"
#include "robcal/kinematics/numeric_ik.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

constexpr double kPi = std::numbers::pi;

Pose<double> nominal_fk(const RobotModel& model, const Vector6d& joints) {
  return flange_pose(model, PointMass{}, model.nominal(), joints);
}

Vector6d random_joints(const RobotModel& model, std::mt19937_64& rng) {
  Vector6d q;
  for (int i = 0; i < kJointCount; ++i)
    q[i] =
        std::uniform_real_distribution<double>(model.limits[i].lower, model.limits[i].upper)(rng);
  return q;
}

/// Near-singular per BENCHMARKS §5: within 5° of θ5 = 0 (or 180°), an elbow within 5° of
/// stretched or folded, or the wrist centre within 50 mm of axis 1. Computed from link frames.
bool near_singular(const RobotModel& model, const Vector6d& joints) {
  const auto frames = link_frames(model, PointMass{}, model.nominal().data(), joints.data());
  const double limit = std::sin(deg2rad(5.0));
  // θ5: angle between axes 4 and 6.
  const double sin5 = frames[3].R.col(2).cross(frames[5].R.col(2)).norm();
  // Elbow: angle at axis 3 between the upper arm (S→E) and the forearm (E→W), seen in the
  // arm plane.
  const Eigen::Vector3d S = frames[1].p, E = frames[2].p, W = frames[3].p;
  const double sin_elbow = (E - S).normalized().cross((W - E).normalized()).norm();
  const double radial = std::hypot(W.x(), W.y());
  return sin5 < limit || sin_elbow < limit || radial < 50.0;
}

double max_angle_difference(const Vector6d& a, const Vector6d& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

struct RoundTripStats {
  int regular = 0, regular_found = 0, singular = 0, singular_pose_found = 0;
  double worst_joint_error = 0, worst_pose_error_mm = 0, worst_rotation_error = 0;
  int label_mismatches = 0;
};

RoundTripStats round_trip(const std::string& robot, int samples, std::uint64_t seed) {
  const RobotModel model = load_robot(robot);
  const auto geometry = analyze_ortho_parallel(model);
  EXPECT_TRUE(geometry.has_value()) << robot;
  RoundTripStats stats;
  if (!geometry) return stats;
  std::mt19937_64 rng(seed);
  for (int n = 0; n < samples; ++n) {
    const Vector6d q = random_joints(model, rng);
    const Pose<double> target = nominal_fk(model, q);
    const IkResult result = nominal_ik(*geometry, target, q);
    for (const IkSolution& s : result) {  // every solution must reproduce the pose
      const Pose<double> back = nominal_fk(model, s.joints);
      stats.worst_pose_error_mm = std::max(stats.worst_pose_error_mm, (back.p - target.p).norm());
      stats.worst_rotation_error =
          std::max(stats.worst_rotation_error, rotation_distance(back.R, target.R));
      EXPECT_TRUE(model.within_limits(s.joints)) << robot << " sample " << n;
    }
    const bool singular = near_singular(model, q);
    const IkSolution* nearest = nearest_solution(result, q);
    if (singular) {
      ++stats.singular;
      if (nearest) ++stats.singular_pose_found;
      continue;
    }
    ++stats.regular;
    EXPECT_EQ(result.status, IkStatus::Solved) << robot << " sample " << n;
    // Far poses can leave the back (or front) arm short of the wrist centre: 4 or 8 branches.
    EXPECT_TRUE(result.branches_reached == 4 || result.branches_reached == 8)
        << robot << " sample " << n;
    if (!nearest) continue;
    const double error = max_angle_difference(nearest->joints, q);
    stats.worst_joint_error = std::max(stats.worst_joint_error, error);
    if (error < 1e-9) ++stats.regular_found;
    // The closed form's labels (from its angles) against the geometric definition (frames).
    if (!(nearest->config == arm_config(model, q))) ++stats.label_mismatches;
  }
  return stats;
}

class IkRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(IkRoundTrip, HundredThousandRandomConfigurations) {
  const int kSamples = 100000;
  const std::uint64_t kSeed = 20261122;
  const RoundTripStats s = round_trip(GetParam(), kSamples, kSeed);
  std::printf(
      "[ %s ] seed %llu: %d regular, %d found to 1e-9 rad (worst %.2e rad); %d near-singular "
      "(BENCHMARKS §5), %d with a solution; every solution reproduces the pose to %.2e mm / "
      "%.2e rad; %d label mismatches\n",
      GetParam().c_str(), static_cast<unsigned long long>(kSeed), s.regular, s.regular_found,
      s.worst_joint_error, s.singular, s.singular_pose_found, s.worst_pose_error_mm,
      s.worst_rotation_error, s.label_mismatches);
  EXPECT_EQ(s.regular + s.singular, kSamples);
  EXPECT_EQ(s.regular_found, s.regular);
  EXPECT_LT(s.worst_joint_error, 1e-9);
  EXPECT_EQ(s.singular_pose_found, s.singular);
  EXPECT_LT(s.worst_pose_error_mm, 1e-9);
  EXPECT_LT(s.worst_rotation_error, 1e-11);
  EXPECT_EQ(s.label_mismatches, 0);
  EXPECT_GT(s.singular, 0);  // the sampling does reach the singular regions
}

INSTANTIATE_TEST_SUITE_P(BuiltinRobots, IkRoundTrip,
                         ::testing::Values("abb-irb120", "fanuc-lrmate200ic", "kuka-kr6-r900-sixx"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

TEST(InverseKinematics, Irb120HomeHasEightDistinctLabelledBranches) {
  const RobotModel model = load_robot("abb-irb120");
  const auto geometry = analyze_ortho_parallel(model);
  ASSERT_TRUE(geometry);
  // Home with the wrist turned and bent (θ4 = θ5 = 30°) so no joint sits at a singularity and
  // the flip (θ4 − 180° = −150°) stays inside J4's ±160°.
  Vector6d q;
  q << 0, 0, 0, deg2rad(30), deg2rad(30), 0;
  const IkResult result = nominal_ik(*geometry, nominal_fk(model, q), q);
  // All 8 branches exist geometrically; the limits of the IRB 120 (J2 ±110, J3 −110..70)
  // remove the back and some down branches, and J6 ±400° adds turns.
  EXPECT_EQ(result.branches_reached, 8);
  const IkSolution* home = nearest_solution(result, q);
  ASSERT_NE(home, nullptr);
  EXPECT_LT(max_angle_difference(home->joints, q), 1e-12);
  EXPECT_EQ(home->config.label(), "front-up-noflip");
  // The flip of home: J4 ± 180°, J5 = −30°, J6 ± 180°.
  bool found_flip = false;
  for (const IkSolution& s : result)
    if (s.config.label() == "front-up-flip" && std::abs(s.joints[4] + deg2rad(30)) < 1e-12)
      found_flip = true;
  EXPECT_TRUE(found_flip);
}

TEST(InverseKinematics, WideRangeJointReturnsEveryTurn) {
  const RobotModel model = load_robot("abb-irb120");  // J6 −400°..400°
  const auto geometry = analyze_ortho_parallel(model);
  ASSERT_TRUE(geometry);
  Vector6d q;
  q << deg2rad(10), deg2rad(20), deg2rad(-30), deg2rad(40), deg2rad(50), deg2rad(60);
  const IkResult result = nominal_ik(*geometry, nominal_fk(model, q), q);
  // J6 = 60° also appears as 420° (outside) and −300°: two turns; the branch's other joints equal.
  int turns = 0;
  for (const IkSolution& s : result)
    if ((s.joints.head<5>() - q.head<5>()).cwiseAbs().maxCoeff() < 1e-9) {
      ++turns;
      EXPECT_NEAR(std::remainder(s.joints[5] - q[5], 2 * kPi), 0.0, 1e-9);
    }
  EXPECT_EQ(turns, 2);
}

TEST(InverseKinematics, WristSingularKeepsSeedTheta4) {
  const RobotModel model = load_robot("abb-irb120");
  const auto geometry = analyze_ortho_parallel(model);
  ASSERT_TRUE(geometry);
  Vector6d q;
  q << deg2rad(20), deg2rad(10), deg2rad(-20), deg2rad(30), 0.0, deg2rad(-40);
  const Pose<double> target = nominal_fk(model, q);
  Vector6d seed = q;
  seed[3] = deg2rad(75);
  const IkResult result = nominal_ik(*geometry, target, seed);
  ASSERT_EQ(result.status, IkStatus::Solved);
  const IkSolution* s = nearest_solution(result, seed);
  ASSERT_NE(s, nullptr);
  EXPECT_TRUE(s->wrist_singular);
  EXPECT_NEAR(s->joints[3], deg2rad(75), 1e-12);
  // θ4 + θ6 is what the pose fixes (α5 = −α6 on the IRB 120): 30 − 40 = 75 + θ6.
  EXPECT_NEAR(s->joints[5], deg2rad(30 - 40 - 75), 1e-9);
  const Pose<double> back = nominal_fk(model, s->joints);
  EXPECT_LT((back.p - target.p).norm(), 1e-9);
  EXPECT_LT(rotation_distance(back.R, target.R), 1e-12);
}

TEST(InverseKinematics, UnreachableAndOutsideLimitsAreStatuses) {
  const RobotModel model = load_robot("abb-irb120");
  const auto geometry = analyze_ortho_parallel(model);
  ASSERT_TRUE(geometry);
  Pose<double> far;
  far.p << 2000, 0, 500;  // reach of the IRB 120 is 580 mm
  const IkResult unreachable = nominal_ik(*geometry, far);
  EXPECT_EQ(unreachable.status, IkStatus::Unreachable);
  EXPECT_EQ(unreachable.count, 0);
  // J1 restricted to ±10°: a pose at J1 = 90° needs J1 = 90° (front) or −90° (back).
  RobotModel narrow = model;
  narrow.limits[0] = {deg2rad(-10), deg2rad(10)};
  const auto narrow_geometry = analyze_ortho_parallel(narrow);
  ASSERT_TRUE(narrow_geometry);
  Vector6d q;
  q << deg2rad(90), deg2rad(30), deg2rad(10), 0, deg2rad(40), 0;
  const IkResult limited = nominal_ik(*narrow_geometry, nominal_fk(model, q));
  EXPECT_EQ(limited.status, IkStatus::OutsideLimits) << to_string(limited.status);
  EXPECT_EQ(limited.count, 0);
  EXPECT_GT(limited.branches_reached, 0);
}

TEST(InverseKinematics, RejectsRobotsThatAreNotOrthoParallel) {
  RobotModel model = load_robot("abb-irb120");
  std::string why;
  model.mdh[4].d = 5.0;  // offset wrist: not spherical
  EXPECT_FALSE(analyze_ortho_parallel(model, &why));
  EXPECT_NE(why.find("link 5"), std::string::npos) << why;
  model = load_robot("abb-irb120");
  model.mdh[2].alpha = deg2rad(1.0);
  EXPECT_FALSE(analyze_ortho_parallel(model, &why));
  EXPECT_NE(why.find("link 3"), std::string::npos) << why;
  model = load_robot("abb-irb120");
  model.joint_map.matrix(2, 1) = 0.5;
  EXPECT_FALSE(analyze_ortho_parallel(model, &why));
  EXPECT_NE(why.find("joint map"), std::string::npos) << why;
}

TEST(InverseKinematics, FastAtan2AgreesWithTheLibrary) {
  // Every octant, magnitudes over the whole exponent range with tiny and huge ratios, and the
  // breakpoints of the table. Measured worst: 4.4e-16 rad, 2 ulp of the result.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-300.0, 300.0);
  double worst = 0, worst_ulp = 0;
  auto check = [&](double y, double x) {
    const double expected = std::atan2(y, x), error = std::abs(fast_atan2(y, x) - expected);
    worst = std::max(worst, error);
    if (expected != 0)
      worst_ulp = std::max(worst_ulp,
                           error / (std::nextafter(std::abs(expected), 4.0) - std::abs(expected)));
  };
  for (int n = 0; n < 1000000; ++n) {
    const double y = u(rng) * std::pow(10.0, e(rng));
    check(y, u(rng) * std::pow(10.0, n % 2 == 0 ? e(rng) : e(rng) / 100));
  }
  for (double t : {0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0})
    for (double sy : {1.0, -1.0})
      for (double sx : {1.0, -1.0}) {
        check(sy * t, sx);
        check(sy, sx * t);
      }
  EXPECT_LT(worst, 5e-16);
  EXPECT_LE(worst_ulp, 2.0);
  // Signed zeros, subnormals, the largest double, infinities and NaN: the library's value
  // (sign of zero included) or NaN.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  constexpr double kMax = std::numeric_limits<double>::max();
  constexpr double kSub = std::numeric_limits<double>::denorm_min();
  const double special[] = {0.0, -0.0, kSub, -kSub, 1.0, -1.0, kMax, -kMax, kInf, -kInf, kNan};
  for (double y : special)
    for (double x : special) {
      const double expected = std::atan2(y, x), got = fast_atan2(y, x);
      if (std::isnan(expected)) {
        EXPECT_TRUE(std::isnan(got)) << y << ", " << x;
        continue;
      }
      EXPECT_NEAR(got, expected, 5e-16) << y << ", " << x;
      EXPECT_EQ(std::signbit(got), std::signbit(expected)) << y << ", " << x;
      if (expected == 0 || std::isinf(x) || std::isinf(y)) {
        EXPECT_EQ(got, expected);
      }
    }
}

TEST(NominalChain, MatchesTheErrorModelFkAtNominalParameters) {
  for (const std::string name : {"abb-irb120", "fanuc-lrmate200ic", "kuka-kr6-r900-sixx"}) {
    const RobotModel model = load_robot(name);
    const NominalChain chain = make_nominal_chain(model);
    std::mt19937_64 rng(5);
    double worst_mm = 0, worst_rad = 0;
    for (int n = 0; n < 2000; ++n) {
      const Vector6d q = random_joints(model, rng);
      const Pose<double> fast = nominal_flange_pose(chain, q), ref = nominal_fk(model, q);
      worst_mm = std::max(worst_mm, (fast.p - ref.p).norm());
      worst_rad = std::max(worst_rad, rotation_distance(fast.R, ref.R));
    }
    EXPECT_LT(worst_mm, 1e-11) << name;
    EXPECT_LT(worst_rad, 1e-13) << name;
  }
  // And against the independent home pose of the IRB 120.
  const NominalChain irb = make_nominal_chain(load_robot("abb-irb120"));
  const Pose<double> home = nominal_flange_pose(irb, Vector6d::Zero());
  EXPECT_LT((home.p - Eigen::Vector3d(374, 0, 630)).norm(), 1e-12);
}

TEST(InverseKinematics, LabelsParseBack) {
  for (int i = 0; i < 8; ++i) {
    const ArmConfig c{(i & 4) != 0, (i & 2) != 0, (i & 1) != 0};
    const auto parsed = parse_arm_config(c.label());
    ASSERT_TRUE(parsed);
    EXPECT_EQ(parsed->index(), i);
  }
  EXPECT_FALSE(parse_arm_config("front-sideways-noflip"));
}

TEST(NumericIk, ConvergesOnTheCalibratedCompliantRobot) {
  // The reference data set's true robot (errors + gravity compliance) is not ortho-parallel:
  // seed the DLS with the nominal analytic solution and check the pose is met exactly.
  const test::ReferenceTruth truth = test::load_reference_truth();
  const Tool tool = load_tool(test::data_path("irb120-published/tool.yaml"));
  const auto geometry = analyze_ortho_parallel(truth.model);
  ASSERT_TRUE(geometry);
  std::mt19937_64 rng(7);
  int converged = 0, tried = 0, well_conditioned = 0;
  double worst_joint = 0;
  for (int n = 0; n < 200; ++n) {
    const Vector6d q = random_joints(truth.model, rng);
    if (near_singular(truth.model, q)) continue;
    const Pose<double> target = flange_pose(truth.model, tool.payload, truth.params, q);
    // The nominal solver works in the robot's base frame: remove the fitted base transform.
    const Pose<double> world_T_base = detail::base_transform(truth.params.data(), 0.0, 0.0);
    const IkResult nominal = nominal_ik(*geometry, world_T_base.inverse() * target, q);
    const IkSolution* seed = nearest_solution(nominal, q);
    if (!seed) continue;  // the nominal pose of a sample at a joint limit may lie just outside
    ++tried;
    const NumericIkResult r =
        numeric_ik(truth.model, tool.payload, truth.params, target, seed->joints);
    if (r.status != NumericIkStatus::Converged) continue;
    ++converged;
    const Pose<double> back = flange_pose(truth.model, tool.payload, truth.params, r.joints);
    EXPECT_LT((back.p - target.p).norm(), 1e-6);
    EXPECT_LT(rotation_distance(back.R, target.R), 1e-9);
    // Where the nominal seed is within 1° of q the problem is well conditioned and the DLS
    // must land on q itself; near a singularity it may find the neighbouring branch.
    if (max_angle_difference(seed->joints, q) < deg2rad(1.0)) {
      ++well_conditioned;
      worst_joint = std::max(worst_joint, max_angle_difference(r.joints, q));
    }
  }
  EXPECT_EQ(converged, tried);
  EXPECT_GT(tried, 150);
  EXPECT_GT(well_conditioned, tried / 2);
  std::printf("%d converged of %d; %d with a nominal seed within 1°, worst joint error %.2e rad\n",
              converged, tried, well_conditioned, worst_joint);
  EXPECT_LT(worst_joint, 1e-8);  // the same branch as q, the truth's own joints
}

TEST(NumericIk, ReportsAnUnreachablePose) {
  const RobotModel model = load_robot("abb-irb120");
  Pose<double> far;
  far.p << 2000, 0, 500;
  const NumericIkResult r = numeric_ik(model, PointMass{}, model.nominal(), far, Vector6d::Zero());
  EXPECT_NE(r.status, NumericIkStatus::Converged);
  EXPECT_GT(r.position_error_mm, 1000.0);
}

TEST(NumericIk, AgreesWithTheAnalyticSolutionOnTheNominalRobot) {
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  std::mt19937_64 rng(11);
  for (int n = 0; n < 50; ++n) {
    const Vector6d q = random_joints(model, rng);
    if (near_singular(model, q)) continue;
    const Pose<double> target = nominal_fk(model, q);
    Vector6d seed = q;
    for (int i = 0; i < kJointCount; ++i) seed[i] += 0.05 * ((i % 2) ? 1 : -1);
    const NumericIkResult r = numeric_ik(model, PointMass{}, model.nominal(), target, seed);
    ASSERT_EQ(r.status, NumericIkStatus::Converged) << "sample " << n;
    EXPECT_LT(max_angle_difference(r.joints, q), 1e-8) << "sample " << n;
  }
}

}  // namespace
}  // namespace robcal
