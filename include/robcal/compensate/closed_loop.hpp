#pragma once
/// \file
/// Closing the loop in simulation (issue 7 item 4): corrected joints commanded to the virtual
/// true robot (sim/true_robot.hpp), the error at the tool measured against the wanted pose,
/// beside the error without compensation (the wanted pose sent to the nominal controller in
/// the base frame the calibration located, so only the arm's own errors remain).

#include <vector>

#include "robcal/compensate/corrected_targets.hpp"
#include "robcal/sim/true_robot.hpp"

namespace robcal {

/// Position (mm) and orientation (deg) errors at the TCP over a set of targets.
struct ToolErrorStats {
  int count = 0;
  double mean_mm = 0, rms_mm = 0, max_mm = 0;
  double mean_deg = 0, max_deg = 0;
};

struct ClosedLoopReport {
  ToolErrorStats compensated;
  ToolErrorStats uncompensated;
  std::vector<double> compensated_mm;    ///< per target
  std::vector<double> uncompensated_mm;  ///< per target (NaN-free: unreachable targets skipped)
};

/// Commands `corrected[i].ik.joints` on `truth` in the condition of `comps[i]` (each joint
/// arriving from its approach side, the arm at its temperature rise, carrying the truth's
/// payload of the same name or its own) and compares with `wanted[i]`; the uncompensated joints
/// are the nominal solution of the wanted pose in the same configuration, in the same condition.
ClosedLoopReport closed_loop_check(const std::vector<const Compensator*>& comps,
                                   const TrueRobot& truth, const std::vector<WantedTarget>& wanted,
                                   const std::vector<CorrectedTarget>& corrected);
/// The same with one compensator for every target.
ClosedLoopReport closed_loop_check(const Compensator& comp, const TrueRobot& truth,
                                   const std::vector<WantedTarget>& wanted,
                                   const std::vector<CorrectedTarget>& corrected);

}  // namespace robcal
