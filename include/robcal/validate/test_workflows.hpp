#pragma once
/// \file
/// The workflows behind `robcal iso9283 plan|analyse`, `robcal axis-test plan|analyse` and
/// `robcal ballbar-path`, and their Python functions: robot, tool and model files read and
/// checked against each other, the test computed (validate/iso9283.hpp, axis_test.hpp,
/// ballbar_path.hpp), every output generated before the first file is written, the files
/// written, and one JSON serializer per result.

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "robcal/validate/axis_test.hpp"
#include "robcal/validate/ballbar_path.hpp"
#include "robcal/validate/iso9283.hpp"

namespace robcal {

/// The calibrated model file `path`, checked to be a model of `robot`. \throws InputError at
/// `key` (and the file) naming both robots otherwise.
CalibratedRobot load_model_of(const std::string& path, const RobotModel& robot,
                              const std::string& key);

// ---- ISO 9283 -------------------------------------------------------------------------------

/// The tool orientation of the tests' poses unless asked otherwise: pointing down (the
/// quaternion 0,0,1,0, a half turn about the world y axis).
Eigen::Matrix3d iso9283_default_orientation();

struct Iso9283PlanFilesRequest {
  std::string robot;  ///< built-in name or robot file
  std::string tool;   ///< tool file (its TCP); empty: the flange
  std::string model;  ///< calibrated model (joint targets compensated); empty: the nominal robot
  /// Region, orientation (default pointing down), configuration, cycles, vAP approach; its
  /// robot is the one the files give.
  Iso9283PlanRequest test = [] {
    Iso9283PlanRequest t;
    t.world_R_tcp = iso9283_default_orientation();
    return t;
  }();
  std::string out_poses = "iso9283-poses.csv";
  std::string out_cycles = "iso9283-cycles.csv";
  std::string out_vap_cycles = "iso9283-vap-cycles.csv";
  std::string program;  ///< also the cycles as robot programs: rapid, krl, ls, urscript
  std::string program_dir = "iso9283-programs";
};

struct Iso9283PlanFiles {
  Iso9283PlanRequest test;  ///< as planned (with the robot of the files)
  Iso9283Plan plan;
  std::vector<std::string> files;  ///< every file written, in order
};

/// Plans the test and writes the pose list, the cycles (and the vAP cycles, the programs).
/// Every program is generated before any file is written: a refusal writes nothing.
/// \throws InputError for a model of another robot (--model), a Yaskawa job (--program), and
///   what iso9283_plan refuses
Iso9283PlanFiles iso9283_plan_files(const Iso9283PlanFilesRequest& request);

/// {cube_centre_mm, cube_edge_mm, poses: [{name, position_mm, joints_deg}], cycles,
/// vap_approach_mm, files}.
nlohmann::json iso9283_plan_json(const Iso9283PlanFiles& files);

/// The analysis of a test from its files (read_iso9283_request, iso9283_analyse).
Iso9283Result iso9283_analyse_files(const std::string& poses_path,
                                    const std::string& measurements_path, int min_cycles);

// ---- Axis test --------------------------------------------------------------------------------

/// The moves of the test written to `out` (CSV, degrees); returns them.
std::vector<AxisTestMove> axis_test_plan_file(const AxisTestPlanRequest& request,
                                              const std::string& out);

/// The analysis of a measurements file (read_axis_test_samples, axis_test_analyse).
AxisTestResult axis_test_analyse_file(const std::string& path);

/// {samples, axis_direction, axis_point_mm, radius_mm, scale, backlash_deg,
/// backlash_sigma_deg, axis_sigma_deg, tangential_mm|radial_mm|axial_mm: {mean_abs_mm, max_abs_mm,
/// sigma_mm}}.
nlohmann::json axis_test_json(const AxisTestResult& result);

// ---- Ballbar path -----------------------------------------------------------------------------

struct BallbarPathFilesRequest {
  std::string robot;          ///< built-in name or robot file
  std::string tool;           ///< tool file; the ball is one of its targets
  std::string target;         ///< the target carrying the ball
  std::string model;          ///< commands the path; empty: the nominal robot
  std::string reading_model;  ///< predicts the readings; empty: the commanding model
  /// Centre, length, range, axis, rings, orientation (default pointing down), configuration;
  /// its robot, reading model and target are the ones the files give.
  BallbarPathRequest path = [] {
    BallbarPathRequest p;
    p.world_R_tcp = iso9283_default_orientation();
    return p;
  }();
  std::string out;  ///< configurations CSV
};

struct BallbarPathFiles {
  BallbarPath path;
  double largest_offset_mm = 0;  ///< largest |predicted reading − length| over the points
  std::string out;
  /// What the checks could not see (no reading model: the range check is vacuous).
  std::vector<std::string> notes;
};

/// The path, checked, written to `out`. \throws InputError (key --centre) listing every point
/// that fails the checks (nothing written), for a model of another robot, an unknown target.
BallbarPathFiles ballbar_path_files(const BallbarPathFilesRequest& request);

/// {points, largest_predicted_offset_mm, out, notes}.
nlohmann::json ballbar_path_json(const BallbarPathFiles& files);

}  // namespace robcal
