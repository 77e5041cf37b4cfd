#include "robcal/compensate/closed_loop.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "robcal/core/units.hpp"

namespace robcal {
namespace {

void add(ToolErrorStats& s, std::vector<double>& all, const Pose<double>& wanted,
         const Pose<double>& reached) {
  const double mm = (reached.p - wanted.p).norm();
  const double deg = rad2deg(Eigen::AngleAxisd(reached.R.transpose() * wanted.R).angle());
  all.push_back(mm);
  ++s.count;
  s.mean_mm += mm;
  s.rms_mm += mm * mm;
  s.max_mm = std::max(s.max_mm, mm);
  s.mean_deg += deg;
  s.max_deg = std::max(s.max_deg, deg);
}

void finish(ToolErrorStats& s) {
  if (s.count == 0) return;
  s.mean_mm /= s.count;
  s.rms_mm = std::sqrt(s.rms_mm / s.count);
  s.mean_deg /= s.count;
}

}  // namespace

ClosedLoopReport closed_loop_check(const std::vector<const Compensator*>& comps,
                                   const TrueRobot& truth, const std::vector<WantedTarget>& wanted,
                                   const std::vector<CorrectedTarget>& corrected) {
  ClosedLoopReport report;
  for (size_t i = 0; i < wanted.size() && i < corrected.size(); ++i) {
    const Compensator& comp = *comps.at(i);
    const ReachCondition& condition = comp.condition;
    const Pose<double>& want = wanted[i].world_T_tcp;
    const Vector6d& joints = corrected[i].ik.joints;
    // The true robot in the target's condition: each joint arrives from the compensator's side,
    // as the program will move it, the arm at its temperature, carrying the named payload.
    MotionState motion;
    motion.from_below = false;
    // A warm-up time (§10) is the truth's own warm-up at that time; a bare fraction (or a fully
    // warm arm) its warm-up at that fraction.
    if (condition.warmup_time_s && std::isfinite(*condition.warmup_time_s))
      motion.time_s = *condition.warmup_time_s;
    else
      motion.temperature_rise_k = condition.warmup_fraction > 0
                                      ? truth.effects.temperature_rise_k * condition.warmup_fraction
                                      : condition.temperature_rise_k;
    motion.payload = truth.robot.tool.payload_index(condition.payload_name);
    motion.previous_joints = joints - deg2rad(5.0) * condition.approach;
    add(report.compensated, report.compensated_mm, want,
        true_flange_pose(truth, joints, motion) * comp.flange_T_tcp);
    const auto plain =
        nominal_solution(comp, comp.world_T_base.inverse() * want, corrected[i].config, joints);
    if (plain) {
      motion.previous_joints = *plain - deg2rad(5.0) * condition.approach;
      add(report.uncompensated, report.uncompensated_mm, want,
          true_flange_pose(truth, *plain, motion) * comp.flange_T_tcp);
    }
  }
  finish(report.compensated);
  finish(report.uncompensated);
  return report;
}

ClosedLoopReport closed_loop_check(const Compensator& comp, const TrueRobot& truth,
                                   const std::vector<WantedTarget>& wanted,
                                   const std::vector<CorrectedTarget>& corrected) {
  return closed_loop_check(std::vector<const Compensator*>(wanted.size(), &comp), truth, wanted,
                           corrected);
}

}  // namespace robcal
