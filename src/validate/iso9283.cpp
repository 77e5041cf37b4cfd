#include "robcal/validate/iso9283.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal {
namespace {

/// Deviations (deg) of an attained orientation from the commanded one about the commanded
/// tool axes: the rotation vector of R_cᵀ·R_j (see the header).
Eigen::Vector3d orientation_deviation_deg(const Eigen::Matrix3d& commanded,
                                          const Eigen::Matrix3d& attained) {
  const Eigen::AngleAxisd rotation(commanded.transpose() * attained);
  return rotation.axis() * rad2deg(rotation.angle());
}

/// Sample standard deviation √(Σ (v − v̄)² / (n − 1)) of the columns' rows (n ≥ 2).
template <int Rows>
Eigen::Matrix<double, Rows, 1> sample_std(const Eigen::Matrix<double, Rows, Eigen::Dynamic>& v) {
  const auto mean = v.rowwise().mean();
  return ((v.colwise() - mean).rowwise().squaredNorm() / static_cast<double>(v.cols() - 1))
      .cwiseSqrt();
}

struct PoseSamples {
  Eigen::Matrix3Xd positions;
  Eigen::Matrix3Xd deviations_deg;  ///< empty without orientation
  std::vector<int> cycles;
};

PoseSamples collect(const std::vector<const Iso9283Sample*>& samples,
                    const Pose<double>& commanded) {
  PoseSamples out;
  const auto n = static_cast<Eigen::Index>(samples.size());
  out.positions.resize(3, n);
  if (samples.front()->world_R_tcp) out.deviations_deg.resize(3, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Iso9283Sample& s = *samples[static_cast<size_t>(j)];
    out.positions.col(j) = s.position_mm;
    if (s.world_R_tcp)
      out.deviations_deg.col(j) = orientation_deviation_deg(commanded.R, *s.world_R_tcp);
    out.cycles.push_back(s.cycle);
  }
  return out;
}

Iso9283PoseFigures pose_figures(int pose, const PoseSamples& s, const Pose<double>& commanded) {
  Iso9283PoseFigures f;
  f.pose = pose;
  f.cycles = static_cast<int>(s.positions.cols());
  // Clause 7.2.1: AP from the barycentre of the attained positions.
  f.mean_mm = s.positions.rowwise().mean();
  f.ap_xyz_mm = f.mean_mm - commanded.p;
  f.ap_mm = f.ap_xyz_mm.norm();
  // Clause 7.2.2: RP_l = l̄ + 3 S_l.
  const Eigen::RowVectorXd l = (s.positions.colwise() - f.mean_mm).colwise().norm();
  f.l_mean_mm = l.mean();
  f.s_l_mm = sample_std<1>(l)(0);
  f.rp_mm = f.l_mean_mm + 3 * f.s_l_mm;
  if (s.deviations_deg.cols() > 0) {
    f.has_orientation = true;
    f.ap_abc_deg = s.deviations_deg.rowwise().mean();
    f.rp_abc_deg = 3 * sample_std<3>(s.deviations_deg);
  }
  return f;
}

/// A cycle visits P1 → P5 → P4 → P3 → P2 (indices into the plan's poses).
constexpr std::array<int, 5> kCycleOrder = {0, 4, 3, 2, 1};
/// The multi-directional test's approach directions h = 1..3.
constexpr std::array<const char*, 3> kApproachAxis = {"+x", "+y", "+z"};

std::string joints_csv(const Vector6d& joints) {
  std::string out;
  for (int j = 0; j < kJointCount; ++j) out += fmt::format(",{:.9f}", rad2deg(joints[j]));
  return out;
}

[[noreturn]] void fail(const Iso9283AnalysisRequest& r, int line, const std::string& what) {
  throw InputError({r.file, line, 0, ""}, what);
}

}  // namespace

Iso9283Plan iso9283_plan(const Iso9283PlanRequest& request) {
  const Eigen::Vector3d extent = request.region_max_mm - request.region_min_mm;
  if (!extent.allFinite() || extent.minCoeff() <= 0)
    throw InputError({"", 0, 0, "--region"},
                     "the workspace region must be a box min < max on every axis (mm)");
  if (request.cycles < kIso9283MinimumCycles)
    throw InputError({"", 0, 0, "--cycles"},
                     fmt::format("at least {} cycles (ISO 9283 asks for {})", kIso9283MinimumCycles,
                                 kIso9283Cycles));
  Iso9283Plan plan;
  plan.cube_centre_mm = (request.region_min_mm + request.region_max_mm) / 2;
  plan.cube_edge_mm = extent.minCoeff();
  const double h = plan.cube_edge_mm / 2;
  // C1..C4 below (z −), C5..C8 above, each Ck+4 over Ck.
  const std::array<Eigen::Vector2d, 4> square = {Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, -1),
                                                 Eigen::Vector2d(1, 1), Eigen::Vector2d(-1, 1)};
  for (int k = 0; k < 8; ++k)
    plan.corners_mm[static_cast<size_t>(k)] =
        plan.cube_centre_mm + h * Eigen::Vector3d(square[static_cast<size_t>(k % 4)].x(),
                                                  square[static_cast<size_t>(k % 4)].y(),
                                                  k < 4 ? -1 : 1);
  // Clause 6.8: P1 at the centre; P2..P5 towards C1, C2, C7, C8, 10 % of the diagonal
  // (half-diagonal × 0.2) from the corner.
  std::vector<Eigen::Vector3d> positions = {plan.cube_centre_mm};
  for (const int corner : {0, 1, 6, 7})
    positions.push_back(plan.cube_centre_mm +
                        0.8 * (plan.corners_mm[static_cast<size_t>(corner)] - plan.cube_centre_mm));

  if (!(request.vap_approach_mm >= 0 && request.vap_approach_mm <= 1000))
    throw InputError({"", 0, 0, "--vap-approach"},
                     fmt::format("expected 0 (no multi-directional test) to 1000 mm, found {}",
                                 request.vap_approach_mm));

  const Compensator compensator = make_compensator(request.robot);
  const auto planned = [&](std::string name, const Eigen::Vector3d& position,
                           const Vector6d& near) {
    Iso9283PlannedPose pose;
    pose.name = std::move(name);
    pose.world_T_tcp.R = request.world_R_tcp;
    pose.world_T_tcp.p = position;
    const CalibratedIkResult ik =
        calibrated_ik(compensator, pose.world_T_tcp, request.config, near);
    if (!ik.ok())
      throw InputError({"", 0, 0, "--region"},
                       fmt::format("{} at ({:.3f}, {:.3f}, {:.3f}) mm is not reachable in the "
                                   "{} configuration with this orientation: {}. Choose a region "
                                   "well inside the workspace, or another orientation or "
                                   "configuration",
                                   pose.name, position.x(), position.y(), position.z(),
                                   request.config.label(), to_string(ik.status)));
    pose.joints = ik.joints;
    return pose;
  };
  Vector6d near = Vector6d::Zero();
  for (size_t k = 0; k < positions.size(); ++k) {
    plan.poses.push_back(planned(fmt::format("P{}", k + 1), positions[k], near));
    near = plan.poses.back().joints;  // P2..P5 on the turn of P1's joints
  }
  for (int cycle = 1; cycle <= request.cycles; ++cycle)
    for (const int pose : kCycleOrder) plan.sequence.emplace_back(cycle, pose);

  if (request.vap_approach_mm == 0) return plan;
  for (const Iso9283PlannedPose& pose : plan.poses) {
    std::array<Iso9283PlannedPose, 3>& from = plan.approaches.emplace_back();
    for (int h = 0; h < 3; ++h)
      from[static_cast<size_t>(h)] = planned(
          fmt::format("{} approach {}", pose.name, kApproachAxis[h]),
          pose.world_T_tcp.p - request.vap_approach_mm * Eigen::Vector3d::Unit(h), pose.joints);
  }
  for (int direction = 1; direction <= 3; ++direction)
    for (int cycle = 1; cycle <= request.cycles; ++cycle)
      for (const int pose : kCycleOrder) {
        plan.vap_sequence.push_back({cycle, pose, direction, true});
        plan.vap_sequence.push_back({cycle, pose, direction, false});
      }
  return plan;
}

std::string iso9283_pose_list_csv(const Iso9283Plan& plan, const ArmConfig& config) {
  std::string out = "name,x,y,z,qw,qx,qy,qz,config\n";
  for (const Iso9283PlannedPose& p : plan.poses) {
    const Eigen::Quaterniond q = to_quaternion(p.world_T_tcp.R);
    out += fmt::format("{},{:.6f},{:.6f},{:.6f},{:.12f},{:.12f},{:.12f},{:.12f},{}\n", p.name,
                       p.world_T_tcp.p.x(), p.world_T_tcp.p.y(), p.world_T_tcp.p.z(), q.w(), q.x(),
                       q.y(), q.z(), config.label());
  }
  return out;
}

std::string iso9283_cycles_csv(const Iso9283Plan& plan) {
  std::string out = "cycle,pose,j1,j2,j3,j4,j5,j6\n";
  for (const auto& [cycle, pose] : plan.sequence) {
    const Iso9283PlannedPose& p = plan.poses[static_cast<size_t>(pose)];
    out += fmt::format("{},{}", cycle, p.name) + joints_csv(p.joints) + "\n";
  }
  return out;
}

std::string iso9283_vap_cycles_csv(const Iso9283Plan& plan) {
  if (plan.vap_sequence.empty()) return {};
  std::string out = "cycle,pose,direction,move,j1,j2,j3,j4,j5,j6\n";
  for (const Iso9283Move& m : plan.vap_sequence) {
    const auto pose = static_cast<size_t>(m.pose);
    const Iso9283PlannedPose& p =
        m.approach ? plan.approaches[pose][static_cast<size_t>(m.direction - 1)] : plan.poses[pose];
    out += fmt::format("{},{},{},{}", m.cycle, plan.poses[pose].name, m.direction,
                       m.approach ? "approach" : "measure") +
           joints_csv(p.joints) + "\n";
  }
  return out;
}

MeasurementProgramRequest iso9283_program_request(const Iso9283Plan& plan,
                                                  MeasurementProgramRequest base,
                                                  bool multidirectional) {
  base.names.clear();
  base.joints.clear();
  base.visits.clear();
  ConfigurationVisit straight;  // no backlash approach: the ISO test moves straight to the pose
  straight.approach = false;
  if (!multidirectional) {
    for (const auto& [cycle, pose] : plan.sequence) {
      const Iso9283PlannedPose& p = plan.poses[static_cast<size_t>(pose)];
      base.names.push_back(fmt::format("C{:02}-{}", cycle, p.name));
      base.joints.push_back(p.joints);
      base.visits.push_back(straight);
    }
    return base;
  }
  if (plan.vap_sequence.empty())
    throw InputError({"", 0, 0, "--vap-approach"},
                     "the plan has no multi-directional test: give the approach distance (mm)");
  for (const Iso9283Move& m : plan.vap_sequence) {
    const auto pose = static_cast<size_t>(m.pose);
    base.names.push_back(fmt::format("V{:02}-{}-D{}{}", m.cycle, plan.poses[pose].name, m.direction,
                                     m.approach ? "-from" : ""));
    base.joints.push_back(m.approach
                              ? plan.approaches[pose][static_cast<size_t>(m.direction - 1)].joints
                              : plan.poses[pose].joints);
    straight.measure = !m.approach;
    base.visits.push_back(straight);
  }
  return base;
}

Iso9283Result iso9283_analyse(const Iso9283AnalysisRequest& request) {
  if (request.min_cycles < kIso9283MinimumCycles)
    throw InputError({"", 0, 0, "--min-cycles"},
                     fmt::format("at least {} cycles are needed for a standard deviation",
                                 kIso9283MinimumCycles));
  if (request.samples.empty()) fail(request, 0, "no measured cycles");
  const bool with_orientation = request.samples.front().world_R_tcp.has_value();
  // (pose, direction) → samples. Pose accuracy and repeatability: direction 0 (the
  // unidirectional cycles) when the pose has it, direction 1 otherwise.
  std::map<std::pair<int, int>, std::vector<const Iso9283Sample*>> groups;
  std::set<std::tuple<int, int, int>> seen;
  for (const Iso9283Sample& s : request.samples) {
    if (s.pose < 1 || s.pose > 5)
      fail(request, s.line, fmt::format("pose {} is not one of P1..P5", s.pose));
    if (static_cast<size_t>(s.pose) > request.commanded.size())
      fail(request, s.line, fmt::format("P{} has no commanded pose", s.pose));
    if (s.direction < 0 || s.direction > 3)
      fail(request, s.line, fmt::format("direction {} is not 0 (one) or 1..3", s.direction));
    if (s.world_R_tcp.has_value() != with_orientation)
      fail(request, s.line, "some rows have an orientation and others not");
    if (!seen.insert({s.pose, s.direction, s.cycle}).second)
      fail(request, s.line,
           fmt::format("cycle {} of P{} (direction {}) is given twice", s.cycle, s.pose,
                       s.direction));
    groups[{s.pose, s.direction}].push_back(&s);
  }
  Iso9283Result result;
  std::map<int, PoseSamples> unidirectional;
  for (int pose = 1; pose <= 5; ++pose) {
    const Pose<double>& commanded = request.commanded[static_cast<size_t>(pose - 1)];
    auto unidirectional_group = groups.find({pose, 0});
    if (unidirectional_group == groups.end()) unidirectional_group = groups.find({pose, 1});
    if (unidirectional_group == groups.end()) continue;
    std::vector<const Iso9283Sample*> samples = unidirectional_group->second;
    if (static_cast<int>(samples.size()) < request.min_cycles)
      fail(request, samples.front()->line,
           fmt::format("P{} has {} cycles: at least {} are needed (ISO 9283 clause 6.9 asks for "
                       "{}; --min-cycles lowers the demand, down to {})",
                       pose, samples.size(), request.min_cycles, kIso9283Cycles,
                       kIso9283MinimumCycles));
    std::vector<Eigen::Vector3d> direction_means, direction_orientation;
    for (int direction = 1; direction <= 3; ++direction) {
      const auto it = groups.find({pose, direction});
      if (it == groups.end()) continue;
      // A barycentre of fewer cycles is no better than one reading: the same demand as AP.
      if (static_cast<int>(it->second.size()) < request.min_cycles)
        fail(request, it->second.front()->line,
             fmt::format("P{} has {} cycles from direction {}: at least {} are needed for vAP "
                         "(ISO 9283 clause 6.9 asks for {}; --min-cycles lowers the demand, "
                         "down to {})",
                         pose, it->second.size(), direction, request.min_cycles, kIso9283Cycles,
                         kIso9283MinimumCycles));
      const PoseSamples d = collect(it->second, commanded);
      direction_means.push_back(d.positions.rowwise().mean());
      if (with_orientation) direction_orientation.push_back(d.deviations_deg.rowwise().mean());
    }
    std::sort(samples.begin(), samples.end(),
              [](const Iso9283Sample* a, const Iso9283Sample* b) { return a->cycle < b->cycle; });
    const PoseSamples s = collect(samples, commanded);
    Iso9283PoseFigures f = pose_figures(pose, s, commanded);
    // Clause 7.2.3: the largest distance between the barycentres of two approach directions.
    f.directions = static_cast<int>(direction_means.size());
    if (f.directions >= 2) {
      double vap = 0;
      Eigen::Vector3d vap_abc = Eigen::Vector3d::Zero();
      for (size_t h = 0; h < direction_means.size(); ++h)
        for (size_t k = h + 1; k < direction_means.size(); ++k) {
          vap = std::max(vap, (direction_means[h] - direction_means[k]).norm());
          if (with_orientation)
            vap_abc =
                vap_abc.cwiseMax((direction_orientation[h] - direction_orientation[k]).cwiseAbs());
        }
      f.vap_mm = vap;
      if (with_orientation) f.vap_abc_deg = vap_abc;
    }
    result.poses.push_back(f);
    unidirectional.emplace(pose, s);
  }
  // Clause 7.3: distance between P2 and P4, cycle by cycle.
  if (unidirectional.count(2) && unidirectional.count(4)) {
    const PoseSamples& a = unidirectional.at(2);
    const PoseSamples& b = unidirectional.at(4);
    if (a.cycles != b.cycles)
      fail(request, 0, "P2 and P4 must be measured in the same cycles for the distance figures");
    Iso9283DistanceFigures d;
    d.cycles = static_cast<int>(a.cycles.size());
    d.commanded_mm = (request.commanded[1].p - request.commanded[3].p).norm();
    const Eigen::RowVectorXd D = (a.positions - b.positions).colwise().norm();
    d.mean_mm = D.mean();
    d.ad_mm = d.mean_mm - d.commanded_mm;
    d.s_d_mm = sample_std<1>(D)(0);
    d.rd_mm = 3 * d.s_d_mm;
    if (with_orientation) {
      d.has_orientation = true;
      const Eigen::Matrix3Xd Da = a.deviations_deg - b.deviations_deg;
      d.ad_abc_deg = Da.rowwise().mean();
      d.rd_abc_deg = 3 * sample_std<3>(Da);
    }
    result.distance = d;
  }
  return result;
}

}  // namespace robcal
