#pragma once
/// \file
/// Measurement programs: the robot program that visits the planned configurations while the
/// instrument measures, in the controller's own language. Every configuration q is approached
/// from q − 5° on every joint (backlash cancellation, docs/method/05-observability.md §4), or
/// from q + 5° on the joints the plan approaches from above (backlash identification), with
/// joint moves to exact stops (fine points), then the program waits for the arm to settle and runs
/// the measurement hook; a comment with the configuration's name and joints precedes each one, so
/// that the instrument's export can be joined to the plan. Long plans are split into several
/// programs (each standalone, run one after the other) below the controllers' size limits, and
/// where the plan changes payload (the operator mounts it between programs).

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "robcal/model/robot_model.hpp"
#include "robcal/programs/program_language.hpp"

namespace robcal {

/// What the program does once the arm has settled at a configuration.
enum class MeasurementHook {
  WaitInput,    ///< wait until a digital input is on (instrument or operator confirms)
  PulseOutput,  ///< pulse a digital output (triggers the instrument), then wait the settle time
  LogLine,      ///< print the configuration's name and joints on the pendant / log
};

/// How one configuration is visited (MeasurementProgramRequest::visits).
struct ConfigurationVisit {
  bool approach = true;  ///< first a joint move to q − side·approach_deg (backlash cancellation)
  /// Per joint +1: approached from below (q − approach_deg), −1: from above (q + approach_deg),
  /// as the plan asks for the backlash group (docs/method/03-error-model.md §6).
  Vector6d side = Vector6d::Ones();
  /// Then the settle wait and the measurement hook; false: the arm only passes through q (an
  /// ISO 9283 vAP pre-pose, a via point), nothing is measured there.
  bool measure = true;
  /// The payload to carry (a name under the tool file's `payloads:`; empty: the tool's own):
  /// a program part never changes payload, its header says which one to mount (§7).
  std::string payload;
};

struct MeasurementProgramRequest {
  ProgramLanguage language = ProgramLanguage::Rapid;
  /// Configurations in visiting order: names and controller joints (rad).
  std::vector<std::string> names;
  std::vector<Vector6d> joints;
  /// Per configuration, in the same order; empty: every configuration approached and measured.
  std::vector<ConfigurationVisit> visits;
  /// Program name: a letter, then letters, digits or '_', at most 6 characters (parts append
  /// two digits; 8 characters is the shortest name limit of the five controllers, INFORM's).
  std::string name = "RCMEAS";
  double approach_deg = 5.0;  ///< docs/method/05-observability.md §4
  double settle_s = 1.0;      ///< wait at each configuration before the hook
  MeasurementHook hook = MeasurementHook::WaitInput;
  int signal = 1;            ///< input or output number (KRL $IN/$OUT, LS DI/DO, JBI, UR)
  std::string rapid_signal;  ///< RAPID signal name; default diRobcalMeasured / doRobcalMeasure
  double joint_speed_percent = 10;
  /// Configurations per program; 0 = the language's default (see program_size_limit).
  int max_configs_per_file = 0;
  /// Yaskawa only: encoder pulses per degree of each axis (the robot's parameters S1CxG...).
  std::optional<std::array<double, kJointCount>> pulses_per_degree;
  /// Joint limits to check q and its approach against (controller joints, rad); none: no check.
  std::optional<std::array<JointLimit, kJointCount>> limits;
  int tool_number = 1;  ///< Fanuc UT / KRL and Yaskawa tool number stored with the points
  /// Yaskawa ///DATE line, "YYYY/MM/DD HH:MM" (the caller's clock; fixed in tests).
  std::string date = "2000/01/01 00:00";
};

/// "wait", "pulse" or "log"; InputError (key `key`) otherwise.
MeasurementHook measurement_hook_from_name(const std::string& name,
                                           const std::string& key = "--hook");

/// One file of the program.
struct ProgramFile {
  std::string name;  ///< file name (program name + extension)
  std::string text;
};

/// The configurations per program each language is split at by default: RAPID 500 and KRL
/// 500 (program memory, inline points), Fanuc 250 (500 P[] per TP program), Yaskawa 400 (800
/// C variables; the job file format numbers them C00000..C09999), URScript 1000 (the
/// controller compiles the whole script before it starts).
int program_size_limit(ProgramLanguage language);

/// Writes the measurement program. InputError (key = the configuration's name) for a name or
/// joint the language cannot carry, a configuration or approach outside `limits`, a missing
/// pulses-per-degree for Yaskawa, a hook the language has no instruction for.
std::vector<ProgramFile> write_measurement_program(const MeasurementProgramRequest& request);

/// Writes the program's files into the folder `out_dir` (created if missing), each whole or
/// not at all, after every file has been generated (a bad configuration writes nothing).
/// Returns the paths written.
std::vector<std::string> write_measurement_program_files(const MeasurementProgramRequest& request,
                                                         const std::string& out_dir);

/// `robcal program` as one library call: the plan's configurations CSV read, the robot file's
/// joint limits and pulses per degree applied, the program written into a folder.
struct MeasurementProgramFilesRequest {
  /// Language, hook, names of the program...; its names and joints are replaced by the CSV's,
  /// its limits by the robot's, its pulses per degree completed from the robot's when unset.
  MeasurementProgramRequest program;
  /// CSV config,target,j1..j6 (degrees) with optional approach and payload columns: what
  /// `robcal plan` writes
  std::string configs;
  std::string robot;    ///< built-in robot name or robot file; "": no limit check
  std::string tool;     ///< tool file, needed when the CSV names targets instead of joints
  std::string out_dir;  ///< folder of the program's files
};

struct MeasurementProgramFilesResult {
  MeasurementProgramRequest program;  ///< what was written (configurations, limits, pulses)
  std::vector<std::string> paths;     ///< the files written
};

/// Reads the configurations (sim/simulator.hpp read_configurations_csv: InputError naming the
/// file, line and column), then write_measurement_program_files: every file whole or none.
MeasurementProgramFilesResult write_measurement_program_from_files(
    const MeasurementProgramFilesRequest& request);

/// One joint move read back from a program: controller joints in degrees and where it is.
struct JointMove {
  Vector6d joints_deg = Vector6d::Zero();
  int line = 0;
};

/// Every absolute joint position of a program: RAPID jointtarget literals and KRL E6AXIS/AXIS
/// points in text order; Fanuc `J P[n]` moves to joint-representation positions, Yaskawa
/// `MOVJ Cnnnnn` (converted with `pulses_per_degree`) and URScript `movej([...])` in the
/// order of the instructions. InputError (file, line, column) on text
/// it cannot read. What write_measurement_program writes reads back to its joints.
std::vector<JointMove> read_joint_moves(
    const std::string& text, ProgramLanguage language, const std::string& file,
    const std::optional<std::array<double, kJointCount>>& pulses_per_degree = std::nullopt);

}  // namespace robcal
