// The UR family's closed form (parallel_axes_ik.hpp) against an independent analytic solution
// written here in UR's own standard-DH frames (the textbook derivation: θ1 from the point P5
// by arccos, since P5·z1 = d4; θ5 from the flange position, cos θ5 = (p·z1 − d4)/d6; θ6 from
// z1 seen from the flange, (sin θ5·cos θ6, −sin θ5·sin θ6, cos θ5); θ2, θ3 from the planar arm
// of T14 = A1⁻¹·T·A6⁻¹·A5⁻¹ and θ4 from T34), sharing no formula with the library's (which
// works in MDH frames from the axis direction n, parallel_axes_ik.hpp); the robot files
// against UR's published DH table; and round trips FK → IK on random configurations of every
// branch of every UR robot in data/robots, with the labels from the link frames (arm_config).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/closed_form_ik.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/nominal_chain.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "test_compensate_support.hpp"

namespace robcal {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2 * kPi;

/// UR's published standard DH (mm), as printed on UR's "DH parameters" page.
struct UrDh {
  const char* file;
  double d1, a2, a3, d4, d5, d6;
};
constexpr std::array<UrDh, 6> kUrRobots{{
    {"universal-robots-ur3e", 151.85, -243.55, -213.2, 131.05, 85.35, 92.1},
    {"universal-robots-ur5e", 162.5, -425, -392.2, 133.3, 99.7, 99.6},
    {"universal-robots-ur10e", 180.7, -612.7, -571.55, 174.15, 119.85, 116.55},
    {"universal-robots-ur16e", 180.7, -478.4, -360, 174.15, 119.85, 116.55},
    {"universal-robots-ur5", 89.159, -425, -392.25, 109.15, 94.65, 82.3},
    {"universal-robots-ur10", 127.3, -612, -572.3, 163.941, 115.7, 92.2},
}};

using Matrix4 = Eigen::Matrix4d;

/// Standard DH link transform Rz(θ)·Tz(d)·Tx(a)·Rx(α).
Matrix4 dh(double theta, double d, double a, double alpha) {
  const double ct = std::cos(theta), st = std::sin(theta), ca = std::cos(alpha),
               sa = std::sin(alpha);
  Matrix4 A;
  A << ct, -st * ca, st * sa, a * ct, st, ct * ca, -ct * sa, a * st, 0, sa, ca, d, 0, 0, 0, 1;
  return A;
}

struct TextbookUr {
  std::array<double, 6> d, a, alpha;
  explicit TextbookUr(const UrDh& p)
      : d{p.d1, 0, 0, p.d4, p.d5, p.d6}, a{0, p.a2, p.a3, 0, 0, 0}, alpha{kPi / 2, 0,        0,
                                                                          kPi / 2, -kPi / 2, 0} {}
  [[nodiscard]] Matrix4 link(int i, double theta) const { return dh(theta, d[i], a[i], alpha[i]); }
  [[nodiscard]] Matrix4 fk(const Vector6d& q) const {
    Matrix4 T = Matrix4::Identity();
    for (int i = 0; i < 6; ++i) T = T * link(i, q[i]);
    return T;
  }
  /// Every solution (up to 8) of the textbook derivation, angles in (−π, π].
  [[nodiscard]] std::vector<Vector6d> ik(const Matrix4& T) const {
    std::vector<Vector6d> out;
    const Eigen::Vector4d P5 = T * Eigen::Vector4d(0, 0, -d[5], 1);
    const double r = std::hypot(P5.x(), P5.y());
    if (r < std::abs(d[3])) return out;
    const double psi = std::atan2(P5.y(), P5.x()), phi = std::acos(d[3] / r);
    for (const double t1 : {psi + phi + kPi / 2, psi - phi + kPi / 2}) {
      const double s1 = std::sin(t1), c1 = std::cos(t1);
      const double c5 = (T(0, 3) * s1 - T(1, 3) * c1 - d[3]) / d[5];
      if (std::abs(c5) > 1) continue;
      for (const double t5 : {std::acos(c5), -std::acos(c5)}) {
        const double s5 = std::sin(t5);
        const double t6 =
            std::atan2((-T(0, 1) * s1 + T(1, 1) * c1) / s5, (T(0, 0) * s1 - T(1, 0) * c1) / s5);
        const Matrix4 T14 =
            link(0, t1).inverse() * T * link(5, t6).inverse() * link(4, t5).inverse();
        // Frame 4's origin in frame 1: (a2·c2 + a3·c23, a2·s2 + a3·s23, d4).
        const double px = T14(0, 3), py = T14(1, 3);
        const double c3 = (px * px + py * py - a[1] * a[1] - a[2] * a[2]) / (2 * a[1] * a[2]);
        if (std::abs(c3) > 1) continue;
        for (const double t3 : {std::acos(c3), -std::acos(c3)}) {
          const double t2 =
              std::atan2(py, px) - std::atan2(a[2] * std::sin(t3), a[1] + a[2] * std::cos(t3));
          const Matrix4 T34 = (link(1, t2) * link(2, t3)).inverse() * T14;
          const double t4 = std::atan2(T34(1, 0), T34(0, 0));
          Vector6d q;
          q << t1, t2, t3, t4, t5, t6;
          for (int i = 0; i < 6; ++i) q[i] = std::remainder(q[i], kTwoPi);
          out.push_back(q);
        }
      }
    }
    return out;
  }
};

using test::random_joints;

Matrix4 to_matrix(const Pose<double>& pose) {
  Matrix4 T = Matrix4::Identity();
  T.topLeftCorner<3, 3>() = pose.R;
  T.topRightCorner<3, 1>() = pose.p;
  return T;
}

/// Largest joint difference modulo full turns (rad).
double turn_distance(const Vector6d& a, const Vector6d& b) {
  double worst = 0;
  for (int i = 0; i < kJointCount; ++i)
    worst = std::max(worst, std::abs(std::remainder(a[i] - b[i], kTwoPi)));
  return worst;
}

TEST(UrFamily, RobotFilesReproduceThePublishedDhTable) {
  std::mt19937_64 rng(20261124);
  for (const UrDh& ur : kUrRobots) {
    const RobotModel model = load_robot(ur.file);
    const TextbookUr textbook(ur);
    double worst_mm = 0, worst_rad = 0;
    for (int n = 0; n < 10000; ++n) {
      const Vector6d q = random_joints(model, rng);
      const Pose<double> ours = flange_pose(model, PointMass{}, model.nominal(), q);
      const Matrix4 T = textbook.fk(q);
      worst_mm = std::max(worst_mm, (ours.p - T.topRightCorner<3, 1>()).norm());
      worst_rad = std::max(worst_rad, rotation_distance(ours.R, T.topLeftCorner<3, 3>()));
    }
    EXPECT_LT(worst_mm, 1e-9) << ur.file;
    EXPECT_LT(worst_rad, 1e-12) << ur.file;
  }
}

TEST(UrFamily, DispatchPicksTheParallelAxesClosedForm) {
  for (const UrDh& ur : kUrRobots) {
    const RobotModel model = load_robot(ur.file);
    std::string why;
    EXPECT_FALSE(analyze_ortho_parallel(model, &why)) << ur.file;
    const auto g = analyze_closed_form(model, &why);
    ASSERT_TRUE(g) << ur.file << ": " << why;
    EXPECT_TRUE(std::holds_alternative<ParallelAxesGeometry>(*g)) << ur.file;
  }
  const auto irb = analyze_closed_form(load_robot("abb-irb120"));
  ASSERT_TRUE(irb);
  EXPECT_TRUE(std::holds_alternative<OrthoParallelGeometry>(*irb));
  // A spherical wrist is not of the UR shape, and says why.
  std::string why;
  EXPECT_FALSE(analyze_parallel_axes(load_robot("abb-irb120"), &why));
  EXPECT_NE(why.find("link"), std::string::npos) << why;
}

// Every textbook solution is one of ours modulo full turns, and every class of ours mod 2π is
// a textbook one; every solution of ours carries the labels its link frames give, reproduces
// the pose, is inside the limits, and the 8 labels are all different.
TEST(UrFamily, AgreesWithTheTextbookSolutionOnRandomPoses) {
  std::mt19937_64 rng(7150);
  for (const UrDh& ur : kUrRobots) {
    const RobotModel model = load_robot(ur.file);
    const auto g = analyze_parallel_axes(model);
    ASSERT_TRUE(g);
    const TextbookUr textbook(ur);
    int poses = 0, textbook_total = 0, textbook_checked_fk = 0, missed = 0, extra = 0,
        label_mismatch = 0, outside = 0, duplicate_labels = 0;
    double worst_mm = 0, worst_rad = 0, worst_textbook_mm = 0;
    for (int n = 0; n < 500; ++n) {
      const Vector6d q = random_joints(model, rng);
      const Pose<double> target = flange_pose(model, PointMass{}, model.nominal(), q);
      const Matrix4 T = to_matrix(target);
      const std::vector<Vector6d> expected = textbook.ik(T);
      const IkResult ours = nominal_ik(*g, target, q);
      ++poses;
      ASSERT_EQ(ours.status, IkStatus::Solved);
      textbook_total += static_cast<int>(expected.size());
      for (const Vector6d& e : expected) {
        worst_textbook_mm =
            std::max(worst_textbook_mm, (textbook.fk(e).topRightCorner<3, 1>() - target.p).norm());
        ++textbook_checked_fk;
        bool found = false;
        for (const IkSolution& s : ours) found = found || turn_distance(s.joints, e) < 1e-9;
        if (!found) ++missed;
      }
      unsigned labels = 0;
      for (const IkSolution& s : ours) {
        bool known = false;
        for (const Vector6d& e : expected) known = known || turn_distance(s.joints, e) < 1e-9;
        if (!known) ++extra;
        if (!model.within_limits(s.joints)) ++outside;
        // Each class mod 2π once: its representative in [−π, π).
        if ((s.joints.array().abs() > kPi).any()) continue;
        if (!(arm_config(model, s.joints) == s.config)) ++label_mismatch;
        if (labels & (1u << s.config.index())) ++duplicate_labels;
        labels |= 1u << s.config.index();
        const Pose<double> back = flange_pose(model, PointMass{}, model.nominal(), s.joints);
        worst_mm = std::max(worst_mm, (back.p - target.p).norm());
        worst_rad = std::max(worst_rad, rotation_distance(back.R, target.R));
      }
    }
    std::printf(
        "[ %s ] %d poses, %d textbook solutions (FK worst %.1e mm), %d missed, %d extra, "
        "%d label mismatches, FK of ours worst %.1e mm / %.1e rad\n",
        ur.file, poses, textbook_total, worst_textbook_mm, missed, extra, label_mismatch, worst_mm,
        worst_rad);
    EXPECT_LT(worst_textbook_mm, 1e-8) << "the test's own solution must be right";
    EXPECT_GT(textbook_total, 4 * poses);
    EXPECT_EQ(missed, 0) << ur.file;
    EXPECT_EQ(extra, 0) << ur.file;
    EXPECT_EQ(label_mismatch, 0) << ur.file;
    EXPECT_EQ(outside, 0) << ur.file;
    EXPECT_EQ(duplicate_labels, 0) << ur.file;
    EXPECT_LT(worst_mm, 1e-9) << ur.file;
    EXPECT_LT(worst_rad, 1e-12) << ur.file;
  }
}

// Random configurations until every branch (by the link-frame labels) has `per_branch` of
// them: the branch solver, seeded with q itself, returns q (every joint within 1e-9 rad,
// turns included; the pose to 1e-9 mm when |sin θ5| < 1e-4), and the
// all-solution result contains q, on every 50th.
void round_trip_every_branch(const std::string& file, int per_branch) {
  const RobotModel model = load_robot(file);
  const auto g = analyze_parallel_axes(model);
  ASSERT_TRUE(g);
  const NominalChain chain = make_nominal_chain(model);
  std::mt19937_64 rng(42 + per_branch);
  std::array<int, 8> count{};
  int total = 0, failures = 0, all_checked = 0, all_failures = 0, near_wrist_singular = 0;
  double worst = 0;
  while (*std::min_element(count.begin(), count.end()) < per_branch) {
    const Vector6d q = random_joints(model, rng);
    const ArmConfig config = arm_config(model, q);
    if (count[config.index()] >= per_branch) continue;
    ++count[config.index()];
    ++total;
    const Pose<double> target = nominal_flange_pose(chain, q);
    const IkBranchResult r = nominal_ik_branch(*g, target, config, q);
    const double d =
        r.status == IkStatus::Solved ? (r.solution.joints - q).cwiseAbs().maxCoeff() : 1e9;
    // Near the wrist singularity the pose fixes θ4 and θ6 apart only to about 1e-16/|sin θ5|
    // times the arm's lever ratios (their sum is exact; 2e-9 rad measured at |sin θ5| = 1.4e-5):
    // within |sin θ5| < 1e-4, as in the OPW oracle test, the pose is checked instead.
    const bool singular = std::abs(std::sin(link_angles_from_controller(*g, q)[4])) < 1e-4;
    if (singular) {
      ++near_wrist_singular;
      const Pose<double> back = nominal_flange_pose(chain, r.solution.joints);
      if (r.status != IkStatus::Solved || (back.p - target.p).norm() > 1e-9 ||
          rotation_distance(back.R, target.R) > 1e-12)
        ++failures;
    } else {
      worst = std::max(worst, d);
      if (d > 1e-9) ++failures;
    }
    if (!singular && total % 50 == 0) {
      ++all_checked;
      const IkResult all = nominal_ik(*g, target, q);
      bool found = false;
      for (const IkSolution& s : all) found = found || (s.joints - q).cwiseAbs().maxCoeff() < 1e-9;
      if (!found) ++all_failures;
    }
  }
  std::printf(
      "[ %s ] %d configurations (%d per branch): worst |q − IK(FK(q))| %.1e rad, "
      "%d failures (%d with |sin θ5| < 1e-4, checked by the pose); "
      "all-solution result contains q in %d of %d\n",
      file.c_str(), total, per_branch, worst, failures, near_wrist_singular,
      all_checked - all_failures, all_checked);
  EXPECT_EQ(failures, 0);
  EXPECT_EQ(all_failures, 0);
}

TEST(UrFamily, RoundTripUr10e100kPerBranch) {
  round_trip_every_branch("universal-robots-ur10e", 100000);
}

TEST(UrFamily, RoundTripEveryUrRobotEveryBranch) {
  for (const UrDh& ur : kUrRobots) round_trip_every_branch(ur.file, 10000);
}

TEST(UrFamily, WristSingularityTakesTheSeedAndStillReachesThePose) {
  const RobotModel model = load_robot("universal-robots-ur5e");
  const auto g = analyze_parallel_axes(model);
  ASSERT_TRUE(g);
  Vector6d q;
  q << 0.3, -1.2, 1.1, -0.4, 0.0, 0.7;  // θ5 = 0: axis 6 parallel to axes 2–4
  const Pose<double> target = flange_pose(model, PointMass{}, model.nominal(), q);
  const IkResult r = nominal_ik(*g, target, q);
  ASSERT_EQ(r.status, IkStatus::Solved);
  bool found = false;
  for (const IkSolution& s : r) {
    const Pose<double> back = flange_pose(model, PointMass{}, model.nominal(), s.joints);
    EXPECT_LT((back.p - target.p).norm(), 1e-9);
    EXPECT_LT(rotation_distance(back.R, target.R), 1e-12);
    if ((s.joints - q).cwiseAbs().maxCoeff() > 1e-9) continue;
    found = true;
    EXPECT_TRUE(s.wrist_singular);  // θ6 kept at the seed's value
  }
  EXPECT_TRUE(found);
}

TEST(UrFamily, UnreachablePoseIsReported) {
  const RobotModel model = load_robot("universal-robots-ur5e");
  const auto g = analyze_parallel_axes(model);
  ASSERT_TRUE(g);
  Pose<double> far;
  far.p << 2000, 0, 500;
  EXPECT_EQ(nominal_ik(*g, far).status, IkStatus::Unreachable);
  Pose<double> inside;  // flange pointing down, P = p + d6·ẑ within |δ| of axis 1
  inside.R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  inside.p << 10, 10, 300;
  EXPECT_EQ(nominal_ik(*g, inside).status, IkStatus::Unreachable);
}

}  // namespace
}  // namespace robcal
