#pragma once
/// \file
/// Robot program filtering (docs/method/10-compensation.md §5): find every point of an ABB RAPID
/// module, a KUKA KRL .src/.dat file, a Fanuc LS program or a URScript program, hand it to a
/// corrector in the robot's base frame with the tool active at it, and write the corrected values
/// back into the text in text order, leaving every other byte (comments, spacing, line endings,
/// untouched numbers) exactly as it was. The rewritten text is parsed again and must give the
/// same points with exactly the values written (else nothing is returned).
///
/// Points recognised:
/// - RAPID: `CONST|PERS|VAR robtarget name[{dims}] := [[x,y,z],[q1..q4],[cf1,cf4,cf6,cfx],
///   [eax_a..eax_f]]` and robtarget literals written inline (MoveL/MoveJ/MoveC ...); with
///   `joints`, jointtarget declarations and inline `[[j1..j6],[eax...]]` (MoveAbsJ).
///   Quaternions are (q1..q4) = (w, x, y, z). Each target takes the tool and work object of
///   the Move instruction that uses it (MoveL/MoveJ/MoveC/MoveAbsJ and their variants: the
///   Tool argument, `\WObj:=`); their values come from the program's own literal `tooldata`
///   and `wobjdata` declarations or from ProgramFilterOptions::tools / frames. A declared
///   target used with two different tools or work objects is refused (one corrected value
///   cannot serve both); a target no instruction uses keeps the default tool and wobj0. A
///   target given to another instruction (ArcL, SpotL, a user routine: robcal does not know
///   which argument is its tool) is not corrected: refused, or left as written and listed
///   under keep_going.
/// - KRL: `[DECL] [GLOBAL] E6POS|POS name = {X,Y,Z,A,B,C,S,T,...}` (A, B, C = the ZYX Euler
///   angles in degrees), assignments to such declared names, and aggregates written after
///   PTP/LIN/CIRC (and SPTP/SLIN/SCIRC, SPL in SPLINE blocks); with `joints`, E6AXIS/AXIS
///   points (A1..A6).
///   Relative motions (PTP_REL, LIN_REL ...) are left alone; incomplete absolute points are
///   refused (their missing components come from the robot's state at run time). Tool and
///   base: TOOL_DATA[n] / BASE_DATA[n] of the last `BAS(#TOOL|#BASE, n)` or `$TOOL|$BASE =`
///   before an inline point, FDAT `F<name>` for a declared `X<name>` (inline forms); their
///   values from ProgramFilterOptions (a frames file: they live in $config.dat) or from the
///   program's literal FRAMEs (`DECL FRAME XTOOL={X ..}`, `TOOL_DATA[n]={X ..}`). A tool or
///   base whose value is known only at run time (`$TOOL` set to an expression or changed
///   component-wise, a FRAME given two values or assigned a component) refuses the points
///   under it, saying where.
/// - Fanuc LS: the /POS positions of group 1: X..R with CONFIG (Cartesian; W, P, R the
///   rotations about x, y, z) or J1..J6 (joint, with `joints`); tool UT[n] and user frame
///   UF[n] of the position itself. CONFIG is kept: a correction that needs another is refused.
/// - Yaskawa JBI: the C positions of //POS: Cartesian ones (X, Y, Z, Rx, Ry, Rz; R =
///   Rz·Ry·Rx) in the ROBOT/BASE frame or user frame USER[n], with tool TOOL[n] of the last
///   ///TOOL and configuration = the last ///RCONF (flags l..q, kept: a correction that needs
///   another is refused); with `joints`, pulse positions (pulses / pulses_per_degree). BC and EC
///   positions (base and station axes) stay as written; ///NPOS counts are checked.
/// - URScript: pose literals `p[x,y,z,rx,ry,rz]` (m, rotation vector) that are motion targets
///   or assigned to a variable; the tool of the last literal set_tcp (none: the installation's,
///   the corrector's default) before the motion, for a variable the motions naming it (one
///   pose under two tools is refused; one no motion names keeps the tool where it is assigned,
///   listed as assumed); with `joints`, `movej([q1..q6])` joint lists (rad); no frames.
///
/// A text that starts a program in another language (a RAPID `MODULE` in a .src, an LS
/// `/PROG` in a .script: require_program_language) is refused at that line.
///
/// Anything that looks like a point but is not a literal (an expression, a missing component)
/// is refused with an InputError naming the file, line and column.

#include <Eigen/Core>
#include <array>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/programs/program_language.hpp"

namespace robcal {

/// One point read from a program, in the controller's base frame (mm).
struct ProgramPoint {
  bool is_joint_target = false;
  std::string name;  ///< declared name (with "[i]" for array elements); empty when inline
  int line = 0;      ///< 1-based line and column of the point's literal
  int column = 0;
  Pose<double> base_T_tcp;  ///< Cartesian points only
  /// Configuration as the maker writes it: RAPID (cf1, cf4, cf6, cfx); KRL (S, T) or empty
  /// when the point has no S and T.
  std::vector<int> config;
  Vector6d joints_deg = Vector6d::Zero();  ///< joint targets only: controller joints, degrees
  /// The tool and frame (RAPID work object) active where the point is used, as named in the
  /// program; empty: the default tool, the robot's base frame.
  std::string tool;
  std::string frame;
  /// Set by filter_program for the corrector: the named tool's TCP in the flange frame (none:
  /// the corrector's default tool); `base_T_tcp` is then in the base frame, the frame applied.
  std::optional<Pose<double>> flange_T_tcp;
};

/// What the corrector returns for a point: new Cartesian pose and configuration, or new
/// joints (for joint targets); `failure` non-empty when the point cannot be corrected.
struct CorrectedPoint {
  Pose<double> base_T_tcp;
  std::vector<int> config;  ///< same layout as the input's; empty keeps the original
  Vector6d joints_deg = Vector6d::Zero();
  std::string failure;
  /// 95 % confidence radius of the corrected position (mm), when the model has a covariance.
  std::optional<double> confidence95_mm;
};

using PointCorrector = std::function<CorrectedPoint(const ProgramPoint&)>;

struct ProgramFilterOptions {
  bool joints = false;        ///< also correct joint targets (MoveAbsJ, E6AXIS)
  int position_decimals = 4;  ///< mm
  int quaternion_decimals = 9;
  int angle_decimals = 5;  ///< KRL A, B, C and joint values, degrees
  /// Tools (flange_T_tcp) and frames (base_T_frame) by name (case-insensitive), for those the
  /// program uses but does not define (a frames file); the program's own definitions must
  /// agree with them. RAPID tool0 and wobj0 are the flange and the base frame.
  std::map<std::string, Pose<double>> tools;
  std::map<std::string, Pose<double>> frames;
  /// Yaskawa: encoder pulses per degree of each joint (the robot file's pulses_per_degree); all
  /// zero: unknown, and a job with pulse positions is refused when joints are read.
  std::array<double, kJointCount> pulses_per_degree{};
  /// A point the corrector refuses is left as written and listed in the result instead of
  /// failing the whole program.
  bool keep_going = false;
};

/// A point left as written under keep_going, and why.
struct UncorrectedPoint {
  std::string where;  ///< file:line:column (name)
  std::string reason;
};

struct ProgramFilterResult {
  std::string text;  ///< the corrected program
  int cartesian_points = 0;
  int joint_points = 0;
  std::vector<UncorrectedPoint> uncorrected;
  /// Points corrected on an assumption the program does not confirm (RAPID: no instruction
  /// uses the target; KRL: no FDAT or BAS/$TOOL names its tool and base: the default tool in
  /// the robot's base frame; URScript: no motion names the variable: the tool where it is
  /// assigned). Same layout as `uncorrected`, the reason saying what to check.
  std::vector<UncorrectedPoint> assumed;
  /// One row per corrected point: `line,column,name,confidence95_mm` (empty radius when the
  /// corrector gives none): the side file of the per-target confidence.
  std::string confidence_csv;
  /// A KUKA module filtered as a pair (filter_krl_module): the corrected .dat, `text` being
  /// the .src; the confidence rows then start with their file: `file,line,column,name,...`.
  std::optional<std::string> dat_text;
};

/// Every point of a program (what the filter would hand to the corrector), in file order.
/// `file` names the program in errors.
std::vector<ProgramPoint> read_program_points(std::string_view text, ProgramLanguage language,
                                              const std::string& file,
                                              const ProgramFilterOptions& options = {});

/// Corrects every point of a program. Throws InputError (file, line, column) on text it
/// cannot parse or a point the corrector refuses; never returns a partially corrected text.
ProgramFilterResult filter_program(std::string_view text, ProgramLanguage language,
                                   const std::string& file, const ProgramFilterOptions& options,
                                   const PointCorrector& corrector);

/// Public parse entry point (also the fuzzing target): every point of `text` in `language`;
/// InputError (file, line, column) on text it cannot read.
inline std::vector<ProgramPoint> parse_program(std::string_view text, ProgramLanguage language,
                                               const std::string& file) {
  ProgramFilterOptions options;
  options.joints = true;
  return read_program_points(text, language, file, options);
}

/// A KUKA module: the .src and its .dat read together (docs: the file comment above). The
/// .dat's declarations, FDATs and FRAMEs are known in the .src; each declared point (in either
/// file) takes the tool and base active at the .src motions that use it (`LIN XP1` after
/// `BAS(#TOOL, n)`, `$TOOL = ...`, or an inline form's `FDAT_ACT = FP1` and
/// `BAS(#PTP_PARAMS|#CP_PARAMS, ...)`). A point used under two different tools or bases is
/// refused naming both uses (one corrected value cannot serve both: give each use its own
/// point), as is a motion to a name declared in neither file (under keep_going it is listed
/// with the uncorrected points); the home positions XHOME, XHOME1..5 of $config.dat and `$`
/// system positions are not the module's and are skipped. Literal FRAMEs (`DECL FRAME F={X ..,
/// Y .., Z .., A .., B .., C ..}`, `TOOL_DATA[n]={...}`, `BASE_DATA[n]={...}`, `$TOOL={...}`)
/// define tools and bases by their name; one given two different values, or whose component
/// is assigned (`XTOOL.Z = ...`), is left undefined, and a point under it is refused saying
/// where (which value is active depends on the run). The points are the .src's then the
/// .dat's, each in file order.
std::vector<ProgramPoint> read_krl_module_points(std::string_view src, std::string_view dat,
                                                 const std::string& src_file,
                                                 const std::string& dat_file,
                                                 const ProgramFilterOptions& options = {});

/// Corrects every point of a KUKA module: `text` is the corrected .src, `dat_text` the .dat;
/// InputError (file, line, column) as filter_program, nothing returned partially.
ProgramFilterResult filter_krl_module(std::string_view src, std::string_view dat,
                                      const std::string& src_file, const std::string& dat_file,
                                      const ProgramFilterOptions& options,
                                      const PointCorrector& corrector);

/// The other file of a KUKA module: x.src → x.dat, x.dat → x.src (X.SRC → X.DAT); "" when
/// `path` is neither.
std::string krl_companion_path(const std::string& path);

/// Filters the program file `in` into the new file `out` (written atomically, whole or not
/// at all), and the per-target confidence rows into `confidence_out` when given. `out` must
/// be the same kind of program, and no output may resolve to `in` (the original is never
/// overwritten): InputError otherwise. A KUKA .src or .dat whose companion
/// (krl_companion_path) exists beside it is filtered as a module (filter_krl_module): both
/// corrected files are written, `out` and its companion, both or none.
ProgramFilterResult filter_program_file(const std::string& in, const std::string& out,
                                        const ProgramFilterOptions& options,
                                        const PointCorrector& corrector,
                                        const std::string& confidence_out = "");

}  // namespace robcal
