#pragma once
/// \file
/// Corrected targets (docs/method/10-compensation.md §1–§5): for each wanted TCP pose in the world,
/// the joints that reach it on the calibrated model and the nominal-model Cartesian target
/// (controller base frame) that makes the controller command those joints, with a 95 % confidence
/// radius of the position from the model's parameter covariance; and the same as a corrector of
/// robot programs (RAPID / KRL configuration data mapped to arm branches and turns).

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/io/pose_list_file.hpp"
#include "robcal/programs/program_filter.hpp"

namespace robcal {

/// A wanted TCP pose: one row of a pose-list file (io/pose_list_file.hpp); without a
/// configuration, the branch nearest the previous row's joints (home for the first).
using WantedTarget = ListedPose;

struct CorrectedTarget {
  std::string name;
  ArmConfig config;
  CalibratedIkResult ik;
  Pose<double> base_T_tcp_nominal;  ///< send this (with `config`) to the controller
  /// 95 % radius (mm) of the TCP position predicted at `ik.joints`: √(χ²₃(0.95)·λmax(J·Σ·Jᵀ)),
  /// J the parameter Jacobian of the TCP position, Σ the model's covariance; nullopt when
  /// the model has none.
  std::optional<double> confidence95_mm;
  ReachCondition condition;  ///< the approach, temperature, warm-up and payload corrected for
};

/// Corrects every wanted target, target i with `comps[i]` (the compensator of the condition it is
/// reached under, docs/method/10-compensation.md §6). Throws InputError naming the file and line
/// of the first row that cannot be corrected (with the reason), so no partial result exists.
std::vector<CorrectedTarget> correct_targets(const std::vector<const Compensator*>& comps,
                                             const CalibratedRobot& robot,
                                             const std::vector<WantedTarget>& wanted,
                                             const std::string& file, IkMethod method);
/// The same with one compensator for every target.
std::vector<CorrectedTarget> correct_targets(const Compensator& comp, const CalibratedRobot& robot,
                                             const std::vector<WantedTarget>& wanted,
                                             const std::string& file, IkMethod method);

/// `name,config,j1..j6,x,y,z,qw,qx,qy,qz,<euler labels>,iterations,residual_mm,confidence95_mm`
/// (degrees and mm; the Euler angles in the maker's convention of `model`); `with_conditions`
/// adds `approach,temperature,payload`, each row's condition in the targets file's notation
/// (°C; the payload's name, empty for the tool's own or one given by mass), and `time_s` when a
/// row was corrected for a warm-up time (s, `warm` fully warm, empty cold).
std::string corrected_targets_csv(const std::vector<CorrectedTarget>& rows, const RobotModel& model,
                                  bool with_conditions = false);

/// 95 % confidence radius of the TCP position at `joints` (nullopt without covariance).
std::optional<double> position_confidence95_mm(const CalibratedRobot& robot,
                                               const PointMass& payload,
                                               const Pose<double>& flange_T_tcp,
                                               const Vector6d& joints);

/// A program corrector. A Cartesian point (controller base frame, frame applied) is
/// solved on the calibrated robot in the nominal solution whose configuration data (RAPID
/// cf1/cf4/cf6/cfx, KRL S/T) match the written ones (the branch must match; the turns are
/// the nearest to the written quadrants or signs); a KRL point without S/T takes the branch
/// nearest the previous point's joints. The corrected point is the nominal pose of the
/// calibrated joints, with the configuration data recomputed from them. A joint target j is
/// read as the pose the nominal model gives it: the corrected joints reach that pose on the
/// calibrated robot, in the same configuration.
/// A point with its own tool (ProgramPoint::flange_T_tcp) is corrected for that tool (the
/// payload stays the compensator's). With `robot`, each corrected point carries its 95 %
/// confidence radius. `comp` and `robot` must outlive the corrector.
/// With `by_approach`, each point is corrected under the side each joint reaches it from, the
/// sign of its move from the previous point (a joint that does not move stays on its side; the
/// first point takes the run's approach): the compensator it returns for that side (the backlash
/// group, docs/method/03-error-model.md §6); the references it returns must outlive the corrector.
using ApproachCompensators = std::function<const Compensator&(const Vector6d& approach)>;
PointCorrector make_program_corrector(const Compensator& comp, ProgramLanguage language,
                                      const CalibratedRobot* robot = nullptr,
                                      ApproachCompensators by_approach = {});

/// Configuration data as the maker writes it for controller joints (rad): RAPID (cf1, cf4,
/// cf6, cfx) with cfx = ArmConfig index; KRL (S, T) with S bit 0 = back, bit 1 = up,
/// bit 2 = A5 ≤ 0, T bit i = (A_{i+1} < 0); Fanuc (flip, down, back, t4, t5, t6), CONFIG's
/// letters F/N, D/U, B/T and the turn numbers of J4..J6; Yaskawa ///RCONF (no-flip, lower,
/// rear, |R| ≥ 180°, |T| ≥ 180°, |S| ≥ 180°).
std::vector<int> maker_configuration(const Compensator& comp, ProgramLanguage language,
                                     const Vector6d& joints);

}  // namespace robcal
