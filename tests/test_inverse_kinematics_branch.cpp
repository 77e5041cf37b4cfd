// One configuration branch of the nominal closed-form IK (nominal_ik_branch, and nominal_ik with
// a branch mask) against the all-solution result on seeded random poses of every built-in
// robot, against FK and the geometric label definition (arm_config), and the nearest-turn
// choice on the IRB 120's ±400° J6.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>

#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/kinematics/orientation.hpp"

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

ArmConfig config_of(int index) {
  return ArmConfig{(index & 4) != 0, (index & 2) != 0, (index & 1) != 0};
}

/// The IRB 120 at joints (10°, 20°, −30°, 40°, 50°, 60°): one general pose, its closed form.
struct Irb120AtOnePose {
  RobotModel model = load_robot("abb-irb120");
  std::optional<OrthoParallelGeometry> geometry = analyze_ortho_parallel(model);
  Vector6d q =
      (Vector6d() << deg2rad(10), deg2rad(20), deg2rad(-30), deg2rad(40), deg2rad(50), deg2rad(60))
          .finished();
  Pose<double> target = nominal_fk(model, q);
};

class IkBranch : public ::testing::TestWithParam<std::string> {};

// For each pose and each of the 8 labels, the branch solver must return exactly the entry of
// the all-solution result with that label nearest an unrelated random seed (Euclidean, found by
// brute force over the full result), or report no solution exactly when the full result has
// none with that label; and the solution must reproduce the pose, carry the label the link
// frames give, and respect the limits.
TEST_P(IkBranch, AgreesWithTheAllSolutionResultOnRandomPoses) {
  const RobotModel model = load_robot(GetParam());
  const auto geometry = analyze_ortho_parallel(model);
  ASSERT_TRUE(geometry);
  const std::uint64_t kSeed = 20261123;
  std::mt19937_64 rng(kSeed);
  int solved = 0, absent = 0, mismatches = 0, label_mismatches = 0;
  double worst_joint = 0, worst_mm = 0, worst_rad = 0;
  for (int n = 0; n < 5000; ++n) {
    const Vector6d q = random_joints(model, rng);
    const Vector6d seed = random_joints(model, rng);
    const Pose<double> target = nominal_fk(model, q);
    const IkResult all = nominal_ik(*geometry, target, seed);
    for (int index = 0; index < 8; ++index) {
      const ArmConfig config = config_of(index);
      const IkSolution* expected = nullptr;
      double best = 0;
      for (const IkSolution& s : all) {
        if (!(s.config == config)) continue;
        const double d = (s.joints - seed).squaredNorm();
        if (!expected || d < best) {
          expected = &s;
          best = d;
        }
      }
      const IkBranchResult branch = nominal_ik_branch(*geometry, target, config, seed);
      if (!expected) {
        ++absent;
        if (branch.status == IkStatus::Solved) ++mismatches;
        continue;
      }
      if (branch.status != IkStatus::Solved) {
        ++mismatches;
        continue;
      }
      ++solved;
      const IkSolution& s = branch.solution;
      worst_joint = std::max(worst_joint, (s.joints - expected->joints).cwiseAbs().maxCoeff());
      if (!(s.config == config) || !(arm_config(model, s.joints) == config)) ++label_mismatches;
      EXPECT_TRUE(model.within_limits(s.joints)) << GetParam() << " sample " << n;
      const Pose<double> back = nominal_fk(model, s.joints);
      worst_mm = std::max(worst_mm, (back.p - target.p).norm());
      worst_rad = std::max(worst_rad, rotation_distance(back.R, target.R));
    }
  }
  std::printf(
      "[ %s ] seed %llu: %d branch solutions, %d labels without one; worst difference to the "
      "all-solution entry %.2e rad; pose %.2e mm / %.2e rad\n",
      GetParam().c_str(), static_cast<unsigned long long>(kSeed), solved, absent, worst_joint,
      worst_mm, worst_rad);
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(label_mismatches, 0);
  EXPECT_GT(solved, 5000);  // well over one branch per pose on average
  EXPECT_GT(absent, 0);     // and limits / reach do remove branches
  EXPECT_LT(worst_joint, 1e-12);
  EXPECT_LT(worst_mm, 1e-9);
  EXPECT_LT(worst_rad, 1e-11);
}

// nominal_ik with a mask returns exactly the full result's entries of the masked labels, in
// order.
TEST_P(IkBranch, MaskSelectsExactlyTheMaskedLabels) {
  const RobotModel model = load_robot(GetParam());
  const auto geometry = analyze_ortho_parallel(model);
  ASSERT_TRUE(geometry);
  std::mt19937_64 rng(11);
  for (int n = 0; n < 2000; ++n) {
    const Pose<double> target = nominal_fk(model, random_joints(model, rng));
    const IkResult all = nominal_ik(*geometry, target);
    const unsigned mask = std::uniform_int_distribution<unsigned>(1, 255)(rng);
    const IkResult some = nominal_ik(*geometry, target, Vector6d::Zero(), mask);
    int k = 0;
    for (const IkSolution& s : all) {
      if (!(mask & (1u << s.config.index()))) continue;
      ASSERT_LT(k, some.count) << "sample " << n;
      EXPECT_EQ(some.solutions[k].config, s.config);
      EXPECT_EQ(some.solutions[k].joints, s.joints);
      ++k;
    }
    EXPECT_EQ(k, some.count) << "sample " << n;
  }
}

INSTANTIATE_TEST_SUITE_P(BuiltinRobots, IkBranch,
                         ::testing::Values("abb-irb120", "fanuc-lrmate200ic", "kuka-kr6-r900-sixx"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

// With every joint free over one full turn, a regular pose has all 8 branches, one solution
// each: the branch solver returns each, labelled as asked and as its link frames say, and the
// 8 are distinct.
TEST(IkBranch, EveryLabelAtAPoseReachingAllEight) {
  RobotModel model = load_robot("abb-irb120");
  for (JointLimit& l : model.limits) l = {-kPi, kPi};
  const auto geometry = analyze_ortho_parallel(model);
  ASSERT_TRUE(geometry);
  Vector6d q;
  q << deg2rad(15), deg2rad(20), deg2rad(-35), deg2rad(30), deg2rad(40), deg2rad(-25);
  const Pose<double> target = nominal_fk(model, q);
  std::vector<Vector6d> found;
  for (int index = 0; index < 8; ++index) {
    const ArmConfig config = config_of(index);
    const IkBranchResult r = nominal_ik_branch(*geometry, target, config, q);
    ASSERT_EQ(r.status, IkStatus::Solved) << config.label();
    EXPECT_EQ(r.solution.config, config);
    EXPECT_EQ(arm_config(model, r.solution.joints), config) << config.label();
    const Pose<double> back = nominal_fk(model, r.solution.joints);
    EXPECT_LT((back.p - target.p).norm(), 1e-9) << config.label();
    EXPECT_LT(rotation_distance(back.R, target.R), 1e-12) << config.label();
    for (const Vector6d& other : found)
      EXPECT_GT((other - r.solution.joints).cwiseAbs().maxCoeff(), 1e-3) << config.label();
    found.push_back(r.solution.joints);
  }
  // The pose's own branch gives back q itself.
  const IkBranchResult own = nominal_ik_branch(*geometry, target, arm_config(model, q), q);
  ASSERT_EQ(own.status, IkStatus::Solved);
  EXPECT_LT((own.solution.joints - q).cwiseAbs().maxCoeff(), 1e-12);
}

// J6 of the IRB 120 spans ±400°: J6 = 60° is also −300°; the seed picks the nearer turn.
TEST(IkBranch, SeedPicksTheNearestTurn) {
  const Irb120AtOnePose f;
  ASSERT_TRUE(f.geometry);
  const RobotModel& model = f.model;
  const auto& geometry = f.geometry;
  const Vector6d& q = f.q;
  const Pose<double>& target = f.target;
  const ArmConfig config = arm_config(model, q);
  for (const auto& [seed_j6, expected_j6] :
       {std::pair{60.0, 60.0}, {-100.0, 60.0}, {-130.0, -300.0}, {-390.0, -300.0}, {390.0, 60.0}}) {
    Vector6d seed = q;
    seed[5] = deg2rad(seed_j6);
    const IkBranchResult r = nominal_ik_branch(*geometry, target, config, seed);
    ASSERT_EQ(r.status, IkStatus::Solved);
    EXPECT_NEAR(rad2deg(r.solution.joints[5]), expected_j6, 1e-9) << "seed J6 " << seed_j6;
    EXPECT_LT((r.solution.joints.head<5>() - q.head<5>()).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(IkBranch, StatusesAndSingularCases) {
  const RobotModel model = load_robot("abb-irb120");
  const auto geometry = analyze_ortho_parallel(model);
  ASSERT_TRUE(geometry);
  Pose<double> far;
  far.p << 2000, 0, 500;  // reach of the IRB 120 is 580 mm
  EXPECT_EQ(nominal_ik_branch(*geometry, far, ArmConfig{}, Vector6d::Zero()).status,
            IkStatus::Unreachable);
  // J1 restricted to ±10°: the pose at J1 = 90° is reachable by the front arm only at J1 = 90°.
  RobotModel narrow = model;
  narrow.limits[0] = {deg2rad(-10), deg2rad(10)};
  const auto narrow_geometry = analyze_ortho_parallel(narrow);
  ASSERT_TRUE(narrow_geometry);
  Vector6d q;
  q << deg2rad(90), deg2rad(30), deg2rad(10), 0, deg2rad(40), 0;
  EXPECT_EQ(
      nominal_ik_branch(*narrow_geometry, nominal_fk(model, q), arm_config(model, q), q).status,
      IkStatus::OutsideLimits);
  // Wrist singular (θ5 = 0): flip and no-flip coincide; both requests give the one solution
  // with θ4 from the seed, labelled as nominal_ik labels it.
  q << deg2rad(20), deg2rad(10), deg2rad(-20), deg2rad(30), 0.0, deg2rad(-40);
  const Pose<double> target = nominal_fk(model, q);
  Vector6d seed = q;
  seed[3] = deg2rad(75);
  for (const bool flip : {false, true}) {
    const IkBranchResult r =
        nominal_ik_branch(*geometry, target, ArmConfig{false, false, flip}, seed);
    ASSERT_EQ(r.status, IkStatus::Solved) << flip;
    EXPECT_TRUE(r.solution.wrist_singular);
    EXPECT_FALSE(r.solution.config.flip);
    EXPECT_NEAR(r.solution.joints[3], deg2rad(75), 1e-12);
    const Pose<double> back = nominal_fk(model, r.solution.joints);
    EXPECT_LT((back.p - target.p).norm(), 1e-9);
    EXPECT_LT(rotation_distance(back.R, target.R), 1e-12);
  }
}

// The solvers take the limits from the geometry's public `limits` at each call, so a caller
// may widen or narrow them (compensation seeds on widened limits).
TEST(IkBranch, EditedGeometryLimitsApply) {
  Irb120AtOnePose f;
  ASSERT_TRUE(f.geometry);
  const RobotModel& model = f.model;
  auto& geometry = f.geometry;
  const Vector6d& q = f.q;
  const Pose<double>& target = f.target;
  const ArmConfig config = arm_config(model, q);
  auto turns_of_q = [&](const OrthoParallelGeometry& g) {
    int n = 0;
    for (const IkSolution& s : nominal_ik(g, target, q))
      n += (s.joints.head<5>() - q.head<5>()).cwiseAbs().maxCoeff() < 1e-9;
    return n;
  };
  EXPECT_EQ(turns_of_q(*geometry), 2);  // J6 ±400°: 60° and −300°
  geometry->limits[5] = {-kPi, kPi};
  EXPECT_EQ(turns_of_q(*geometry), 1);
  Vector6d seed = q;
  seed[5] = deg2rad(-290);  // nearer −300°, which the narrowed J6 no longer has
  const IkBranchResult r = nominal_ik_branch(*geometry, target, config, seed);
  ASSERT_EQ(r.status, IkStatus::Solved);
  EXPECT_NEAR(rad2deg(r.solution.joints[5]), 60.0, 1e-9);
  // J5 narrowed below q's 50°: the branch is now outside the limits.
  geometry->limits[4] = {deg2rad(-45), deg2rad(45)};
  EXPECT_EQ(nominal_ik_branch(*geometry, target, config, q).status, IkStatus::OutsideLimits);
}

// A pose with NaN entries (R or p) yields a status and no NaN joints, in both solvers.
TEST(IkBranch, NanPoseGivesNoNanSolution) {
  const Irb120AtOnePose f;
  ASSERT_TRUE(f.geometry);
  const auto& geometry = f.geometry;
  const Vector6d& q = f.q;
  const Pose<double>& good = f.target;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int entry = 0; entry < 12; ++entry) {
    Pose<double> bad = good;
    if (entry < 9)
      bad.R.data()[entry] = nan;
    else
      bad.p[entry - 9] = nan;
    const IkResult all = nominal_ik(*geometry, bad, q);
    for (const IkSolution& s : all) EXPECT_TRUE(s.joints.allFinite()) << "entry " << entry;
    for (int index = 0; index < 8; ++index) {
      const IkBranchResult r = nominal_ik_branch(*geometry, bad, config_of(index), q);
      if (r.status == IkStatus::Solved) {
        EXPECT_TRUE(r.solution.joints.allFinite());
      }
    }
  }
}

}  // namespace
}  // namespace robcal
