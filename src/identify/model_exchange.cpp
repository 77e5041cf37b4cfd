#include "robcal/identify/model_exchange.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <random>

#include "robcal/core/error.hpp"
#include "robcal/core/rounding.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/identify/parameter_csv.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"

namespace robcal {

namespace {

/// A UR calibration.conf on its nominal robot: a nominal model file whose parameters hold
/// nominal + deltas (its world is the robot's DH base frame: base_fitted stays false).
ModelImportResult import_ur_calibration(const ModelImportRequest& request) {
  if (request.calibration_path.empty())
    throw InputError(SourceLocation{"", 0, 0, "--calibration"},
                     "format ur-calibration reads a calibration.conf: give it with --calibration");
  if (request.robot.empty())
    throw InputError(SourceLocation{"", 0, 0, "--robot"},
                     "a calibration.conf holds deltas: give its nominal robot with --robot "
                     "(e.g. universal-robots-ur10e)");
  ModelImportResult out;
  out.ur_calibration = load_ur_calibration(request.calibration_path);
  CalibratedRobot robot = CalibratedRobot::nominal(load_robot(request.robot), Tool{});
  robot.params = params_from_ur_calibration(robot.model, out.ur_calibration);
  robot.level = "ur-calibration";  // imported from UR's factory calibration.conf
  out.model_file = true;
  out.yaml = calibrated_robot_to_yaml(robot);
  return out;
}

/// The base placement off axis 1, the tool and the non-rigid parameters of `robot`, which a
/// calibration.conf cannot hold, by name with their values.
std::vector<std::string> left_out_of_ur_calibration(const CalibratedRobot& robot) {
  const auto& table = parameter_table();
  std::vector<std::string> out;
  for (int k : {0, 1, 3, 4})
    if (robot.params[k] != 0)
      out.push_back(fmt::format(
          "{} = {:.6g} {} (calibration.conf's base frame is on axis 1: set the robot's placement "
          "on the controller)",
          table[k].name, robot.params[k] * table[k].to_external(), table[k].unit));
  for (int k = kComplianceOffset; k < kParameterCount; ++k) {
    const double neutral = k >= kScaleOffset && k < kPeriodicOffset ? 1.0 : 0.0;
    if (robot.params[k] != neutral)
      out.push_back(fmt::format("{} = {:.6g} {} (calibration.conf joints are rigid and unscaled)",
                                table[k].name, robot.params[k] * table[k].to_external(),
                                table[k].unit));
  }
  if (robot.tool.tcp_given) {
    const Eigen::Vector3d t = robot.tool.flange_T_tcp.translation();
    out.push_back(fmt::format(
        "tool tcp at ({:.4f}, {:.4f}, {:.4f}) mm from the flange (set it as the controller's TCP)",
        t.x(), t.y(), t.z()));
  }
  return out;
}

}  // namespace

ModelImportResult import_model(const ModelImportRequest& request) {
  if (request.format == "ur-calibration") return import_ur_calibration(request);
  if (request.format != "urdf")
    throw InputError(SourceLocation{"", 0, 0, "--format"},
                     "unknown format '" + request.format + "' (expected urdf or ur-calibration)");
  if (request.urdf_path.empty())
    throw InputError(SourceLocation{"", 0, 0, "--urdf"},
                     "format urdf reads a URDF: give it with --urdf");
  ModelImportResult out;
  out.imported = load_urdf_robot(request.urdf_path, {request.tip_link});
  const UrdfImport& u = out.imported;
  out.model_file = u.has_base_placement() || u.has_tip_offset();
  if (!out.model_file) {
    out.yaml = robot_to_yaml(u.model);
    return out;
  }
  Tool tool;
  tool.flange_T_tcp = u.flange_T_tip;
  tool.tcp_given = true;
  CalibratedRobot robot = CalibratedRobot::nominal(u.model, tool);
  robot.params = u.params;
  robot.base_fitted = u.has_base_placement();  // the URDF's root link is the world frame
  out.yaml = calibrated_robot_to_yaml(robot);
  return out;
}

ModelExportResult export_model(const ModelExportRequest& request) {
  if (request.robot.empty() == request.model.empty())
    throw InputError(SourceLocation{"", 0, 0, "--robot/--model"},
                     "give either a robot (--robot) or a calibrated model (--model)");
  const CalibratedRobot robot = request.model.empty()
                                    ? CalibratedRobot::nominal(load_robot(request.robot), Tool{})
                                    : load_calibrated_robot(request.model);
  if (request.format == "mdh-csv") return {parameter_table_csv(robot), {}};
  ModelExportResult out;
  if (request.format == "ur-calibration") {
    out.text = ur_calibration_text(ur_calibration_from_params(robot.model, robot.params));
    out.left_out = left_out_of_ur_calibration(robot);
  } else if (request.format == "urdf") {
    const Eigen::Isometry3d* tcp = robot.tool.tcp_given ? &robot.tool.flange_T_tcp : nullptr;
    UrdfExport urdf = robot_to_urdf(robot.model, robot.params, tcp);
    out = {std::move(urdf.xml), std::move(urdf.left_out)};
  } else {
    throw InputError(
        SourceLocation{"", 0, 0, "--format"},
        "unknown format '" + request.format + "' (expected urdf, ur-calibration or mdh-csv)");
  }
  // The cost of the rigid, unscaled export: what compliance, scales and periodic errors move the
  // tool centre point by (docs/method/03-error-model.md §1, §3, §5), on configurations within the
  // limits.
  ParameterVector rigid = robot.params;
  rigid.segment<kScaleOffset - kComplianceOffset>(kComplianceOffset).setZero();
  rigid.segment<kJointCount>(kScaleOffset).setOnes();
  rigid.segment<kParameterCount - kPeriodicOffset>(kPeriodicOffset).setZero();
  if (rigid == robot.params) return out;
  std::mt19937_64 rng(request.seed);
  const Eigen::Vector3d point = robot.tool.flange_T_tcp.translation();
  double sum = 0;
  for (int k = 0; k < request.configurations; ++k) {
    Vector6d j;
    for (int i = 0; i < kJointCount; ++i)
      j[i] = std::uniform_real_distribution<double>(robot.model.limits[i].lower,
                                                    robot.model.limits[i].upper)(rng);
    const double e = (flange_pose(robot.model, robot.tool.payload, robot.params, j) * point -
                      flange_pose(robot.model, robot.tool.payload, rigid, j) * point)
                         .norm();
    sum += e * e;
    out.left_out_max_mm = std::max(out.left_out_max_mm, e);
  }
  out.left_out_rms_mm = std::sqrt(sum / request.configurations);
  return out;
}

nlohmann::json model_import_json(const ModelImportRequest& request, const ModelImportResult& r,
                                 const std::string& written_to) {
  nlohmann::json out{{"format", request.format}, {"model_file", r.model_file}};
  if (request.format == "ur-calibration") {
    static constexpr std::array<const char*, 3> kStatus{"not initialized", "not linearised",
                                                        "linearised"};
    const int status = r.ur_calibration.calibration_status;
    out["source"] = request.calibration_path;
    out["robot"] = request.robot;
    out["calibration_status"] = status;
    out["calibration_status_name"] =
        status < 0 ? "not given" : kStatus.at(static_cast<size_t>(status));
    out["calibrated"] = status != 0;
  } else {
    const UrdfImport& u = r.imported;
    out["source"] = request.urdf_path;
    out["joints"] = u.joint_names;
    out["root_link"] = u.root_link;
    out["tip_link"] = u.tip_link;
    out["base_placement"] = u.has_base_placement();
    out["tip_offset"] = u.has_tip_offset();
  }
  out["out"] = written_to;
  return out;
}

nlohmann::json model_export_json(const ModelExportRequest& request, const ModelExportResult& r,
                                 const std::string& written_to) {
  return {{"format", request.format},
          {"left_out", r.left_out},
          {"left_out_rms_mm", rounded(r.left_out_rms_mm)},
          {"left_out_max_mm", rounded(r.left_out_max_mm)},
          {"configurations", request.configurations},
          {"seed", request.seed},
          {"out", written_to}};
}

}  // namespace robcal
