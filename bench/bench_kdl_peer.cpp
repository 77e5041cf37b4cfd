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
//           tolerances, CalibratedIkOptions), measured by the solver's own chain's FK of the
//           returned joints (the chains agree to the counter chain_gap_rad, about 1e-15 rad),
//           and every joint inside its limits
//   KDL     ChainIkSolverPos_LMA with its stopping test set to the criterion: it stops when
//           E = |L·Δx|² ≤ eps, so the weights L = (1, 1, 1, w, w, w) with w = 5e-10 m /
//           8.7e-9 rad and eps = (5e-10 m)² make E ≤ eps mean position ≤ 5e-7 mm and
//           orientation ≤ 8.7e-9 rad (its default eps 1e-5 stops at a median 3e-4 mm and 7e-4 rad,
//           eps 1e-12 with the default weights up to 1 µm away); 500 iterations, eps_joints 1e-15
//           (its defaults). It reaches the position (median 3e-13 mm) but stalls at about 7e-8 rad
//           of orientation (median_error_rad) whatever the weights, eps_joints or iterations (all
//           weights 1, or eps_joints 0: still 1–4 % succeed), so it fails the orientation
//           tolerance on its own account. KdlLmaDefaults: KDL's defaults (weights
//           1,1,1,0.01,0.01,0.01, eps 1e-5), judged by the same criterion.
//           ChainIkSolverPos_NR_JL (pseudo-inverse velocity solver, eps 1e-12 on each twist
//           component, 500 iterations, the robot's joint limits).
// Each call is timed alone (manual time): the counters give the median and p99 per target and
// the success rate. Run: build/robcal_bench --benchmark_filter=KdlPeer --benchmark_repetitions=5

#include <benchmark/benchmark.h>
#include <fmt/format.h>
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

/// Millimetres and radians between two poses.
std::pair<double, double> pose_error(const Pose<double>& got, const Pose<double>& wanted) {
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
  double chain_gap_mm = 0, chain_gap_rad = 0;  ///< largest FK difference of the two chains

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
    while (cases.size() < 10000) {
      const Vector6d q = test::random_joints(calibrated.model, rng);
      if (test::near_singular(calibrated.model, q)) continue;
      const Pose<double> wanted = calibrated_tcp_pose(comp.chain, q);
      // The two FKs must agree, or the comparison would not be of the same chain.
      const auto [gap_mm, gap_rad] = pose_error(kdl_pose(q), wanted);
      if (gap_mm > 1e-9) throw std::runtime_error("KDL's FK differs from robcal's");
      chain_gap_mm = std::max(chain_gap_mm, gap_mm);
      chain_gap_rad = std::max(chain_gap_rad, gap_rad);
      const std::optional<Vector6d> seed =
          nominal_solution(comp, comp.base_T_world * wanted, arm_config(calibrated.model, q), q);
      if (seed) cases.push_back({wanted, *seed});
    }
  }

  [[nodiscard]] bool inside_limits(const Vector6d& joints) const {
    for (int i = 0; i < kJointCount; ++i)
      if (joints[i] < lower(i) || joints[i] > upper(i)) return false;
    return true;
  }

  /// The TCP pose of `joints` by KDL's FK of its chain (mm).
  [[nodiscard]] Pose<double> kdl_pose(const Vector6d& joints) const {
    KDL::ChainFkSolverPos_recursive fk(chain);
    KDL::JntArray kq(kJointCount);
    for (int i = 0; i < kJointCount; ++i) kq(i) = joints[i];
    KDL::Frame f;
    fk.JntToCart(kq, f);
    Pose<double> pose;
    for (int r = 0; r < 3; ++r) {
      pose.p[r] = f.p[r] * kMmPerM;
      for (int c = 0; c < 3; ++c) pose.R(r, c) = f.M(r, c);
    }
    return pose;
  }

  [[nodiscard]] Pose<double> robcal_pose(const Vector6d& joints) const {
    return calibrated_tcp_pose(comp.chain, joints);
  }
};

const PeerFixture& fixture() {
  static const PeerFixture f;
  return f;
}

using Clock = std::chrono::steady_clock;

/// Times `solve(case) -> joints` per target; counters: median and p99 µs, success %.
/// Each solver is judged on its own chain's FK (`pose_of`), so that no difference of the
/// chains (chain_gap_rad) counts against either.
template <typename Solve, typename PoseOf>
void peer_bench(benchmark::State& state, Solve&& solve, PoseOf&& pose_of) {
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
  long ok = 0, outside = 0;
  std::vector<double> mm, rad;  // what the solutions miss by, inside the limits or not
  for (const Case& c : f.cases) {
    const Vector6d joints = solve(c);
    const auto [e_mm, e_rad] = pose_error(pose_of(joints), c.wanted);
    const bool inside = f.inside_limits(joints);
    ok += inside && e_mm <= kCriterion.position_tolerance_mm &&
          e_rad <= kCriterion.orientation_tolerance_rad;
    outside += !inside;
    mm.push_back(e_mm);
    rad.push_back(e_rad);
  }
  std::sort(mm.begin(), mm.end());
  std::sort(rad.begin(), rad.end());
  state.counters["success_pct"] = 100.0 * static_cast<double>(ok) / f.cases.size();
  state.counters["outside_limits_pct"] = 100.0 * static_cast<double>(outside) / f.cases.size();
  state.counters["median_error_mm"] = mm[mm.size() / 2];
  state.counters["median_error_rad"] = rad[rad.size() / 2];
  state.counters["chain_gap_rad"] = f.chain_gap_rad;
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
  peer_bench(
      state, [&](const Case& c) { return calibrated_ik_newton(comp, c.wanted, c.seed).joints; },
      [&](const Vector6d& q) { return fixture().robcal_pose(q); });
}
BENCHMARK(KdlPeer_RobcalNewton)->UseManualTime();

/// A KDL position solver through the same timing and criterion, seeded as robcal is.
void kdl_bench(benchmark::State& state, KDL::ChainIkSolverPos& solver, const char* settings) {
  state.SetLabel(settings);
  peer_bench(
      state,
      [&](const Case& c) {
        KDL::JntArray out(kJointCount);
        solver.CartToJnt(to_kdl(c.seed), kdl_frame(c.wanted), out);
        return from_kdl(out);
      },
      [](const Vector6d& q) { return fixture().kdl_pose(q); });
}

void KdlPeer_KdlLma(benchmark::State& state) {
  // The stopping test matched to the success criterion (see the file comment), in metres.
  const double position_m = kCriterion.position_tolerance_mm / kMmPerM;
  const double w = position_m / kCriterion.orientation_tolerance_rad;
  Eigen::Matrix<double, 6, 1> weights;
  weights << 1, 1, 1, w, w, w;
  const double eps = position_m * position_m;
  KDL::ChainIkSolverPos_LMA solver(fixture().chain, weights, eps, 500, 1e-15);
  const std::string settings = fmt::format(
      "KDL LMA weights 1,1,1,{:.4g},{:.4g},{:.4g} eps {:.3g} (= the criterion), 500 iterations, "
      "eps_joints 1e-15",
      w, w, w, eps);
  kdl_bench(state, solver, settings.c_str());
}
BENCHMARK(KdlPeer_KdlLma)->UseManualTime();

/// KDL's own defaults (eps 1e-5 on E with the weights 1,1,1,0.01,0.01,0.01: about 3 mm): what
/// a user gets without tuning, judged by the same criterion.
void KdlPeer_KdlLmaDefaults(benchmark::State& state) {
  KDL::ChainIkSolverPos_LMA solver(fixture().chain);
  kdl_bench(state, solver,
            "KDL LMA defaults: weights 1,1,1,0.01,0.01,0.01, eps 1e-5, 500 "
            "iterations, eps_joints 1e-15");
}
BENCHMARK(KdlPeer_KdlLmaDefaults)->UseManualTime();

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
