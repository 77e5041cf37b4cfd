#pragma once
// Shared by the compensation tests and bench/bench_compensate.cpp: a calibrated robot with
// realistic errors, random joints, the singular labels of BENCHMARKS.md, and the round trip of
// issue 7.

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <random>
#include <string>
#include <variant>

#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/core/units.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"

namespace robcal::test {

inline constexpr const char* kRobots[] = {"abb-irb120", "fanuc-lrmate200ic", "kuka-kr6-r900-sixx"};

/// Compliance of the identified IRB 120 (tests/data/irb120-published/truth.yaml), rad/(N·mm).
inline constexpr double kPublishedCompliance[5] = {3.2e-8, 1.3e-7, 6.05e-7, 4.19e-7, 6.47e-7};

/// A calibrated robot: the nominal one placed in a tracker's world with the error magnitudes
/// of docs/method/11-published-results.md (links ±0.5 mm / ±0.1°, compliance of the published IRB
/// 120 order), a 2.6 kg payload and a TCP 150 mm out.
inline CalibratedRobot random_calibrated(const std::string& name, std::mt19937_64& rng) {
  const RobotModel model = load_robot(name);
  Tool tool;
  tool.payload = {2.6, Eigen::Vector3d(-23, 0, 100)};
  tool.flange_T_tcp.translation() = Eigen::Vector3d(10, -20, 150);
  tool.flange_T_tcp.linear() =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  CalibratedRobot robot = CalibratedRobot::nominal(model, tool);
  std::uniform_real_distribution<double> u(-1, 1);
  robot.params[0] = -812 + 5 * u(rng);
  robot.params[1] = 1503 + 5 * u(rng);
  robot.params[2] = -95 + 5 * u(rng);
  robot.params[3] = deg2rad(0.3 * u(rng));
  robot.params[4] = deg2rad(0.3 * u(rng));
  robot.params[5] = deg2rad(-57 + u(rng));
  for (int link = 2; link <= 6; ++link) {
    robot.params[link_param(link, 0)] += deg2rad(0.1 * u(rng));
    robot.params[link_param(link, 1)] += 0.5 * u(rng);
    robot.params[link_param(link, 2)] += deg2rad(0.1 * u(rng));
    robot.params[link_param(link, 3)] += 0.5 * u(rng);
    robot.params[compliance_param(link)] = kPublishedCompliance[link - 2] * (1 + 0.5 * u(rng));
  }
  robot.level = "full";
  return robot;
}

inline Vector6d random_joints(const RobotModel& model, std::mt19937_64& rng) {
  Vector6d j;
  for (int i = 0; i < kJointCount; ++i)
    j[i] =
        std::uniform_real_distribution<double>(model.limits[i].lower, model.limits[i].upper)(rng);
  return j;
}

/// BENCHMARKS.md singular labels on the nominal robot: θ5 within `margin_deg` (5°) of 0 or
/// 180°, elbow stretched or folded within `margin_deg`, or the wrist centre within 50 mm of
/// axis 1. On the UR family (offset wrist) the elbow is that of the planar arm (frame 4's
/// origin) and the shoulder's "wrist centre" the point P where axes 5 and 6 meet, 50 mm along
/// x1 from the plane of axis 1 (the two shoulder solutions meet there); on a spherical wrist
/// both are the wrist centre, as before.
inline bool near_singular(const RobotModel& model, const Vector6d& joints, double margin_deg = 5) {
  const auto frames = link_frames(model, PointMass{}, model.nominal().data(), joints.data());
  const auto q = model_joint_angles(model, joints.data());
  const double theta5 = q[4] + model.mdh[4].theta_offset;
  if (std::abs(std::sin(theta5)) < std::sin(deg2rad(margin_deg))) return true;
  // In the plane of the arm: offsets along axis 3 (the UR's d4) do not move the elbow.
  const Eigen::Vector3d z3 = frames[2].R.col(2);
  Eigen::Vector3d upper = frames[2].p - frames[1].p, fore = frames[3].p - frames[2].p;
  upper -= upper.dot(z3) * z3;
  fore -= fore.dot(z3) * z3;
  if (upper.normalized().cross(fore.normalized()).norm() < std::sin(deg2rad(margin_deg)))
    return true;
  const Eigen::Vector3d w = frames[4].p - frames[0].p;
  return std::abs(w.dot(frames[0].R.col(0))) < 50;
}

/// On a general arm (general_6r_ik.hpp) up to two solutions share a label, and near a fold of
/// the nominal map (the Fanuc CRX: two solutions of one label 4e-4 rad apart, or a pair about to
/// turn complex) the calibrated pose may have no nominal solution near the drawn joints: the
/// calibrated inverse then rightly returns the other solution of the label. True when the
/// nominal seed for `wanted` lies more than 0.1 rad from `joints`; always false on the closed
/// forms (one solution per label). Also true where the nominal joint Jacobian (rotation rows
/// × 500 mm) is conditioned worse than 100: next to such a fold Newton may not converge.
inline bool nominal_seed_elsewhere(const Compensator& comp, const Pose<double>& wanted,
                                   const ArmConfig& config, const Vector6d& joints) {
  if (!std::holds_alternative<General6rGeometry>(comp.geometry)) return false;
  const auto frames =
      link_frames(comp.model, PointMass{}, comp.model.nominal().data(), joints.data());
  Matrix6d J;
  for (int i = 0; i < kJointCount; ++i) {
    const Eigen::Vector3d z = frames[i].R.col(2);
    J.block<3, 1>(0, i) = z.cross(frames[5].p - frames[i].p);
    J.block<3, 1>(3, i) = 500.0 * z;
  }
  const Vector6d sv = Eigen::JacobiSVD<Matrix6d>(J).singularValues();
  if (sv[5] < 0.01 * sv[0]) return true;
  const IkBranchResult r = nominal_ik_branch(
      comp.geometry, comp.base_T_world * wanted * comp.tcp_T_flange, config, joints);
  return r.status != IkStatus::Solved || (r.solution.joints - joints).cwiseAbs().maxCoeff() > 0.1;
}

/// Newton and pose-shift joints further apart than this are different solutions: those of one
/// pose lie ≥ 0.1 rad apart, while two answers within the tolerance of one solution (≥ 5° from
/// singularities) differ by up to 5e-7 rad (BM_RoundTrip100k, Fanuc LR Mate 200iC: pose shift
/// converges linearly and stops just inside the tolerance, Newton far inside).
inline constexpr double kAgreementRad = 1e-6;

/// What the round trip found, per configuration index (ArmConfig::index()) and overall.
struct RoundTripStats {
  std::array<long, 8> poses{};     ///< poses drawn and solved by both iterations
  std::array<long, 8> failures{};  ///< poses where either iteration did not converge
  /// Poses where Newton left the configuration and calibrated_ik handed over to pose shift:
  /// no Newton answer of its own to compare.
  std::array<long, 8> handovers{};
  std::array<long, 8> disagreements{};          ///< Newton and pose shift > kAgreementRad apart
  std::array<double, 8> worst_agreement_rad{};  ///< Newton against pose shift, own answers
  long draws = 0;                               ///< joint vectors drawn, singular ones included
  double worst_mm = 0, worst_deg = 0;           ///< calibrated FK of the answers against the pose
  double worst_recovery_rad = 0;                ///< Newton against the drawn joints, same turn
  long other_turn = 0;      ///< answers a full turn of a wide-range joint from the drawn joints
  long seed_elsewhere = 0;  ///< draws skipped by nominal_seed_elsewhere (general arms)
  int max_newton = 0, max_shift = 0;  ///< iterations
  std::string first_failure, first_handover;
  [[nodiscard]] bool complete(long per_config) const {
    return std::all_of(poses.begin(), poses.end(), [&](long n) { return n >= per_config; });
  }
};

/// Round trip calibrated FK(calibrated IK(pose)) = pose over `per_config` random reachable
/// poses in each of the 8 configurations: joints drawn uniformly inside the limits (at most
/// `max_draws`), ≥ 5° from the singular labels (on a general arm, not nominal_seed_elsewhere),
/// their calibrated TCP pose solved by both iterations in the configuration of the drawn joints,
/// seeded near them, and the two answers compared. Inside the limits and away from singularities
/// the drawn joints are the answer.
inline RoundTripStats round_trip(const CalibratedRobot& robot, const Compensator& comp,
                                 long per_config, long max_draws, std::mt19937_64& rng) {
  RoundTripStats st;
  while (!st.complete(per_config) && st.draws < max_draws) {
    const Vector6d q = random_joints(robot.model, rng);
    ++st.draws;
    if (near_singular(robot.model, q)) continue;
    const ArmConfig config = arm_config(robot.model, q);
    const int index = config.index();
    if (st.poses[index] >= per_config) continue;
    ++st.poses[index];
    const Pose<double> wanted = calibrated_tcp_pose(comp.chain, q);
    if (nominal_seed_elsewhere(comp, wanted, config, q)) {
      --st.poses[index];
      ++st.seed_elsewhere;
      continue;
    }
    const CalibratedIkResult newton = calibrated_ik(comp, wanted, config, q, IkMethod::Newton);
    const CalibratedIkResult shift = calibrated_ik(comp, wanted, config, q, IkMethod::PoseShift);
    const auto where = [&] {
      std::string j = config.label() + " at joints (rad)";
      for (int i = 0; i < kJointCount; ++i) j += " " + std::to_string(q[i]);
      return j;
    };
    if (!newton.ok() || !shift.ok()) {
      if (st.failures[index]++ == 0 && st.first_failure.empty())
        st.first_failure = std::string("Newton ") + to_string(newton.status) + ", pose shift " +
                           to_string(shift.status) + ": " + where();
      continue;
    }
    for (const CalibratedIkResult* r : {&newton, &shift}) {
      const Pose<double> reached = calibrated_tcp_pose(comp.chain, r->joints);
      st.worst_mm = std::max(st.worst_mm, (reached.p - wanted.p).norm());
      st.worst_deg = std::max(st.worst_deg,
                              rad2deg(Eigen::AngleAxisd(reached.R.transpose() * wanted.R).angle()));
    }
    if (newton.method != IkMethod::Newton) {
      if (st.handovers[index]++ == 0 && st.first_handover.empty()) st.first_handover = where();
    } else {
      const double agreement = (newton.joints - shift.joints).cwiseAbs().maxCoeff();
      st.worst_agreement_rad[index] = std::max(st.worst_agreement_rad[index], agreement);
      st.disagreements[index] += agreement > kAgreementRad;
      st.max_newton = std::max(st.max_newton, newton.iterations);
    }
    // The drawn joints, or (near a limit of a joint of more than one turn) the same pose a
    // turn away: with joint scales ≠ 1 the calibrated turn differs from 2π by a little.
    const double recovery = (newton.joints - q).cwiseAbs().maxCoeff();
    if (recovery > 3.0)
      ++st.other_turn;
    else
      st.worst_recovery_rad = std::max(st.worst_recovery_rad, recovery);
    st.max_shift = std::max(st.max_shift, shift.iterations);
  }
  return st;
}

}  // namespace robcal::test
