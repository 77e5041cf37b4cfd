#include "robcal/identify/model_exchange.hpp"

#include <cmath>
#include <random>

#include "robcal/core/error.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/identify/parameter_csv.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"

namespace robcal {

ModelImportResult import_model(const ModelImportRequest& request) {
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
  if (request.format != "urdf")
    throw InputError(SourceLocation{"", 0, 0, "--format"},
                     "unknown format '" + request.format + "' (expected urdf or mdh-csv)");
  const Eigen::Isometry3d* tcp = robot.tool.tcp_given ? &robot.tool.flange_T_tcp : nullptr;
  UrdfExport urdf = robot_to_urdf(robot.model, robot.params, tcp);
  ModelExportResult out{std::move(urdf.xml), std::move(urdf.left_out)};
  // The cost of the rigid, unscaled URDF: what compliance, scales and periodic errors move the
  // tool centre point by (docs/method/03-error-model.md), on configurations within the limits.
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

}  // namespace robcal
