// The peer comparison of calibrated IK (issue 21 item 6), in one binary, on the same poses,
// from the same seeds, judged by the same criterion:
//   robot   ABB IRB 120 with a random calibration (test_compensate_support.hpp, seed 2026),
//           compliance set to 0: KDL holds a rigid chain only, so both solve the same rigid
//           chain (robcal's calibrated model exported as URDF, io/urdf_file.hpp, read by
//           urdfdom, one KDL segment per URDF joint; its FK checked against robcal's to 1e-9 mm
//           before timing)
//   poses   10,000 TCP poses of joints drawn inside the limits, ≥ 5° from the singular labels
//   seed    the nominal closed-form solution in the configuration asked for (nominal_solution),
//           the same for every solver
//   success position error ≤ 5e-7 mm and orientation error ≤ 8.7e-9 rad (robcal's own
//           tolerances, CalibratedIkOptions), measured by robcal's FK of the returned joints,
//           and every joint inside its limits
//   KDL     ChainIkSolverPos_LMA (eps 1e-12, 500 iterations, eps_joints 1e-15, default weights
//           1,1,1,0.01,0.01,0.01) and ChainIkSolverPos_NR_JL (pseudo-inverse velocity solver,
//           eps 1e-12, 500 iterations, the robot's joint limits)
// Each call is timed alone (manual time): the counters give the median and p99 per target and
// the success rate. Run: build/robcal_bench --benchmark_filter=KdlPeer --benchmark_repetitions=5

#include <benchmark/benchmark.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <chrono>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>
#include <stdexcept>

#include "../tests/test_compensate_support.hpp"
#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/io/urdf_file.hpp"

namespace robcal {
namespace {

constexpr double kMmPerM = 1000.0;  // KDL and URDF work in metres
constexpr CalibratedIkOptions kCriterion{};

KDL::Frame kdl_frame(const urdf::Pose& p) {
  return {KDL::Rotation::Quaternion(p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w),
          KDL::Vector(p.position.x, p.position.y, p.position.z)};
}

KDL::Frame kdl_frame(const Pose<double>& p) {
  const Eigen::Matrix3d& R = p.R;
  return {KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1),
                        R(2, 2)),
          KDL::Vector(p.p.x() / kMmPerM, p.p.y() / kMmPerM, p.p.z() / kMmPerM)};
}

/// Millimetres and radians between the pose of `joints` (robcal's FK) and `wanted`.
std::pair<double, double> pose_error(const Compensator& comp, const Vector6d& joints,
                                     const Pose<double>& wanted) {
  const Pose<double> got = calibrated_tcp_pose(comp.chain, joints);
  return {(got.p - wanted.p).norm(), Eigen::AngleAxisd(got.R.transpose() * wanted.R).angle()};
}

struct Case {
  Pose<double> wanted;
  Vector6d seed;
};

/// The robot, its KDL chain (URDF root to "tcp") and the cases.
struct PeerFixture {
  CalibratedRobot calibrated;
  Compensator comp;
  KDL::Chain chain;
  KDL::JntArray lower{kJointCount}, upper{kJointCount};
  std::vector<Case> cases;

  PeerFixture() {
    std::mt19937_64 rng(2026);
    calibrated = test::random_calibrated("abb-irb120", rng);
    for (int link = 2; link <= 6; ++link) calibrated.params[compliance_param(link)] = 0;
    comp = make_compensator(calibrated);
    const Eigen::Isometry3d flange_T_tcp = calibrated.tool.flange_T_tcp;
    const UrdfExport exported = robot_to_urdf(calibrated.model, calibrated.params, &flange_T_tcp);
    const auto urdf = urdf::parseURDF(exported.xml);
    if (!urdf) throw std::runtime_error("the exported URDF does not parse");
    std::vector<urdf::JointConstSharedPtr> joints;
    for (auto link = urdf->getLink("tcp"); link->parent_joint; link = link->getParent())
      joints.insert(joints.begin(), link->parent_joint);
    for (const auto& j : joints) {
      const KDL::Frame origin = kdl_frame(j->parent_to_joint_origin_transform);
      const KDL::Joint joint =
          j->type == urdf::Joint::FIXED
              ? KDL::Joint(j->name, KDL::Joint::Fixed)
              : KDL::Joint(j->name, origin.p,
                           origin.M * KDL::Vector(j->axis.x, j->axis.y, j->axis.z),
                           KDL::Joint::RotAxis);
      chain.addSegment(KDL::Segment(j->child_link_name, joint, origin));
    }
    if (chain.getNrOfJoints() != kJointCount) throw std::runtime_error("not six joints");
    for (int i = 0; i < kJointCount; ++i) {
      lower(i) = calibrated.model.limits[i].lower;
      upper(i) = calibrated.model.limits[i].upper;
    }
    KDL::ChainFkSolverPos_recursive fk(chain);
    while (cases.size() < 10000) {
      const Vector6d q = test::random_joints(calibrated.model, rng);
      if (test::near_singular(calibrated.model, q)) continue;
      const Pose<double> wanted = calibrated_tcp_pose(comp.chain, q);
      // The two FKs must agree, or the comparison would not be of the same chain.
      KDL::JntArray kq(kJointCount);
      for (int i = 0; i < kJointCount; ++i) kq(i) = q[i];
      KDL::Frame f;
      fk.JntToCart(kq, f);
      const KDL::Vector gap = f.p - kdl_frame(wanted).p;
      if (gap.Norm() * kMmPerM > 1e-9) throw std::runtime_error("KDL's FK differs from robcal's");
      const std::optional<Vector6d> seed =
          nominal_solution(comp, comp.base_T_world * wanted, arm_config(calibrated.model, q), q);
      if (seed) cases.push_back({wanted, *seed});
    }
  }

  [[nodiscard]] bool success(const Vector6d& joints, const Pose<double>& wanted) const {
    for (int i = 0; i < kJointCount; ++i)
      if (joints[i] < lower(i) || joints[i] > upper(i)) return false;
    const auto [mm, rad] = pose_error(comp, joints, wanted);
    return mm <= kCriterion.position_tolerance_mm && rad <= kCriterion.orientation_tolerance_rad;
  }
};

const PeerFixture& fixture() {
  static const PeerFixture f;
  return f;
}

using Clock = std::chrono::steady_clock;

/// Times `solve(case) -> joints` per target; counters: median and p99 µs, success %.
template <typename Solve>
void peer_bench(benchmark::State& state, Solve&& solve) {
  const PeerFixture& f = fixture();
  std::vector<double> us;
  us.reserve(1 << 20);
  size_t i = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    const Vector6d joints = solve(f.cases[i]);
    const auto t1 = Clock::now();
    benchmark::DoNotOptimize(joints);
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
    if (us.size() < us.capacity())
      us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    i = (i + 1) % f.cases.size();
  }
  std::sort(us.begin(), us.end());
  state.counters["median_us"] = us[us.size() / 2];
  state.counters["p99_us"] = us[us.size() * 99 / 100];
  long ok = 0;
  for (const Case& c : f.cases) ok += f.success(solve(c), c.wanted);
  state.counters["success_pct"] = 100.0 * static_cast<double>(ok) / f.cases.size();
}

KDL::JntArray to_kdl(const Vector6d& q) {
  KDL::JntArray out(kJointCount);
  for (int i = 0; i < kJointCount; ++i) out(i) = q[i];
  return out;
}

Vector6d from_kdl(const KDL::JntArray& q) {
  Vector6d out;
  for (int i = 0; i < kJointCount; ++i) out[i] = q(i);
  return out;
}

void KdlPeer_RobcalNewton(benchmark::State& state) {
  const Compensator& comp = fixture().comp;
  state.SetLabel("robcal calibrated_ik_newton, default options (at most 12 iterations)");
  peer_bench(state,
             [&](const Case& c) { return calibrated_ik_newton(comp, c.wanted, c.seed).joints; });
}
BENCHMARK(KdlPeer_RobcalNewton)->UseManualTime();

/// A KDL position solver through the same timing and criterion, seeded as robcal is.
void kdl_bench(benchmark::State& state, KDL::ChainIkSolverPos& solver, const char* settings) {
  state.SetLabel(settings);
  peer_bench(state, [&](const Case& c) {
    KDL::JntArray out(kJointCount);
    solver.CartToJnt(to_kdl(c.seed), kdl_frame(c.wanted), out);
    return from_kdl(out);
  });
}

void KdlPeer_KdlLma(benchmark::State& state) {
  KDL::ChainIkSolverPos_LMA solver(fixture().chain, 1e-12, 500, 1e-15);
  kdl_bench(state, solver, "KDL LMA eps 1e-12, 500 iterations, eps_joints 1e-15, default weights");
}
BENCHMARK(KdlPeer_KdlLma)->UseManualTime();

void KdlPeer_KdlNrJl(benchmark::State& state) {
  const PeerFixture& f = fixture();
  KDL::ChainFkSolverPos_recursive fk(f.chain);
  KDL::ChainIkSolverVel_pinv velocity(f.chain);
  KDL::ChainIkSolverPos_NR_JL solver(f.chain, f.lower, f.upper, fk, velocity, 500, 1e-12);
  kdl_bench(state, solver, "KDL NR_JL pinv, eps 1e-12, 500 iterations, joint limits");
}
BENCHMARK(KdlPeer_KdlNrJl)->UseManualTime();

}  // namespace
}  // namespace robcal
