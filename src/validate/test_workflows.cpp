#include "robcal/validate/test_workflows.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/programs/measurement_program.hpp"
#include "robcal/programs/program_language.hpp"

namespace robcal {
namespace {

nlohmann::json vector_json(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

CalibratedRobot load_model_of(const std::string& path, const RobotModel& robot,
                              const std::string& key) {
  CalibratedRobot model = load_calibrated_robot(path);
  if (model.model.name != robot.name)
    throw InputError({path, 0, 0, key}, fmt::format("this is a model of the {}, not of the {}",
                                                    model.model.name, robot.name));
  return model;
}

Eigen::Matrix3d iso9283_default_orientation() {
  return pose_from_position_quaternion(Eigen::Vector3d::Zero(), Eigen::Vector4d(0, 0, 1, 0)).R;
}

Iso9283PlanFiles iso9283_plan_files(const Iso9283PlanFilesRequest& r) {
  Iso9283PlanRequest request = r.test;
  const RobotModel model = load_robot(r.robot);
  const Tool tool = r.tool.empty() ? Tool{} : load_tool(r.tool);
  request.robot = CalibratedRobot::nominal(model, tool);
  if (!r.model.empty()) {
    request.robot = load_model_of(r.model, model, "--model");
    // The tool file names the TCP of this test; the model keeps its identified targets.
    if (!r.tool.empty()) request.robot.tool.flange_T_tcp = tool.flange_T_tcp;
  }
  Iso9283PlanFiles out{request, iso9283_plan(request), {}};
  const Iso9283Plan& plan = out.plan;
  // Every program generated before any file is written: a refusal writes nothing.
  std::vector<MeasurementProgramRequest> programs;
  if (!r.program.empty()) {
    MeasurementProgramRequest base;
    base.language = program_language_from_name(r.program, "--program");
    if (base.language == ProgramLanguage::Jbi)
      throw InputError({"", 0, 0, "--program"},
                       "a Yaskawa job needs the axes' pulses per degree, which iso9283 does not "
                       "take: choose rapid, krl, ls or urscript");
    base.limits = model.limits;
    base.approach_deg = 0;  // the cycle's own approach, as the standard prescribes
    for (const bool multidirectional : {false, true}) {
      if (multidirectional && plan.vap_sequence.empty()) break;
      programs.push_back(iso9283_program_request(plan, base, multidirectional));
      programs.back().name = multidirectional ? "ISOVAP" : "ISOCYC";
      (void)write_measurement_program(programs.back());
    }
  }
  out.files = {r.out_poses, r.out_cycles};
  write_file_atomically(r.out_poses, iso9283_pose_list_csv(plan, request.config));
  write_file_atomically(r.out_cycles, iso9283_cycles_csv(plan));
  if (!plan.vap_sequence.empty()) {
    write_file_atomically(r.out_vap_cycles, iso9283_vap_cycles_csv(plan));
    out.files.push_back(r.out_vap_cycles);
  }
  for (const MeasurementProgramRequest& program : programs)
    for (const std::string& path : write_measurement_program_files(program, r.program_dir))
      out.files.push_back(path);
  return out;
}

nlohmann::json iso9283_plan_json(const Iso9283PlanFiles& files) {
  const Iso9283Plan& plan = files.plan;
  nlohmann::json out;
  out["cube_centre_mm"] = vector_json(plan.cube_centre_mm);
  out["cube_edge_mm"] = plan.cube_edge_mm;
  for (const Iso9283PlannedPose& p : plan.poses) {
    std::vector<double> joints;
    joints.reserve(kJointCount);
    for (int j = 0; j < kJointCount; ++j) joints.push_back(rad2deg(p.joints[j]));
    out["poses"].push_back(
        {{"name", p.name}, {"position_mm", vector_json(p.world_T_tcp.p)}, {"joints_deg", joints}});
  }
  out["cycles"] = files.test.cycles;
  out["vap_approach_mm"] = files.test.vap_approach_mm;
  out["files"] = files.files;
  return out;
}

Iso9283Result iso9283_analyse_files(const std::string& poses_path,
                                    const std::string& measurements_path, int min_cycles) {
  return iso9283_analyse(read_iso9283_request(poses_path, measurements_path, min_cycles));
}

std::vector<AxisTestMove> axis_test_plan_file(const AxisTestPlanRequest& request,
                                              const std::string& out) {
  std::vector<AxisTestMove> moves = axis_test_moves(request);
  write_file_atomically(out, axis_test_moves_csv(moves));
  return moves;
}

AxisTestResult axis_test_analyse_file(const std::string& path) {
  return axis_test_analyse(read_axis_test_samples(path));
}

nlohmann::json axis_test_json(const AxisTestResult& r) {
  const auto stats = [](const ErrorStatistics& s, double sigma) {
    return nlohmann::json{{"mean_abs_mm", s.mean}, {"max_abs_mm", s.max}, {"sigma_mm", sigma}};
  };
  return {{"samples", r.samples},
          {"axis_direction", vector_json(r.axis_direction)},
          {"axis_point_mm", vector_json(r.axis_point_mm)},
          {"radius_mm", r.radius_mm},
          {"scale", r.scale},
          {"backlash_deg", r.backlash_deg},
          {"backlash_sigma_deg", r.backlash_sigma_deg},
          {"axis_sigma_deg", r.tilt_sigma_deg},
          {"tangential_mm", stats(r.tangential_mm, r.tangential_sigma_mm)},
          {"radial_mm", stats(r.radial_mm, r.radial_sigma_mm)},
          {"axial_mm", stats(r.axial_mm, r.axial_sigma_mm)}};
}

BallbarPathFiles ballbar_path_files(const BallbarPathFilesRequest& r) {
  const RobotModel model = load_robot(r.robot);
  const Tool tool = load_tool(r.tool);
  // A model file without targets (an older one) carries the ball on the tool file's.
  const auto model_of = [&](const std::string& path) {
    CalibratedRobot robot = load_model_of(path, model, "");
    if (robot.tool.targets.empty()) robot.tool = tool;
    return robot;
  };
  BallbarPathRequest request = r.path;
  request.robot = r.model.empty() ? CalibratedRobot::nominal(model, tool) : model_of(r.model);
  if (!r.reading_model.empty()) request.reading_model = model_of(r.reading_model);
  request.target = request.robot.tool.target_index(r.target);
  if (request.target < 0)
    throw InputError({r.tool, 0, 0, "--target"},
                     fmt::format("no target '{}' in the tool", r.target));
  BallbarPathFiles out{ballbar_path(request), 0, r.out, {}};
  const BallbarPath& path = out.path;
  if (path.problems() > 0) {
    std::string list;
    for (const BallbarPathPoint& p : path.points)
      if (!p.problem.empty())
        list += fmt::format("\n  elevation {:g}°, azimuth {:g}° at ({:.3f}, {:.3f}, {:.3f}) mm: {}",
                            p.elevation_deg, p.azimuth_deg, p.position_mm.x(), p.position_mm.y(),
                            p.position_mm.z(), p.problem);
    throw InputError({"", 0, 0, "--centre"},
                     fmt::format("{} of {} path points fail the checks (nothing written):{}",
                                 path.problems(), path.points.size(), list));
  }
  write_file_atomically(r.out, ballbar_path_csv(path, r.target));
  for (const BallbarPathPoint& p : path.points)
    out.largest_offset_mm = std::max(out.largest_offset_mm, std::abs(p.predicted_offset_mm));
  // The commanding model predicts its own readings exactly: nothing about the real robot's error
  // (millimetres before calibration) was checked against the bar's range.
  if (r.reading_model.empty())
    out.notes.push_back(
        "no --reading-model: the readings were predicted with the commanding model itself, so "
        "they equal the bar's length and the range check cannot see the real robot's error "
        "(millimetres before calibration); give a calibrated or preliminary model with "
        "--reading-model to check the range");
  return out;
}

nlohmann::json ballbar_path_json(const BallbarPathFiles& files) {
  return {{"points", files.path.points.size()},
          {"largest_predicted_offset_mm", files.largest_offset_mm},
          {"out", files.out},
          {"notes", files.notes}};
}

}  // namespace robcal
