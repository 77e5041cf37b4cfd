// The workflows behind validate, fk, ik and the robot listing (validate_workflow.hpp,
// kinematics_workflow.hpp, robot_catalogue.hpp): the file request gives what the loaded call
// gives, the results equal the pieces they are made of, refusals name their key, and FK/IK
// against hand-known poses.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_catalogue.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/kinematics_workflow.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/validate/base_fit.hpp"
#include "robcal/validate/class_statistics.hpp"
#include "robcal/validate/validate_workflow.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

/// The key of the InputError `work` throws ("" when it throws none).
template <typename Work>
std::string refusal_key(const Work& work) {
  try {
    work();
  } catch (const InputError& e) {
    return e.where().key;
  }
  return "";
}

struct Reference {
  std::string tool_file = test::data_path("irb120-published/tool.yaml");
  std::string validation = test::data_path("irb120-published/validation.csv");
  std::string calibration = test::data_path("irb120-published/calibration.csv");
  Tool tool = load_tool(tool_file);
  CalibratedRobot nominal = CalibratedRobot::nominal(load_robot("abb-irb120"), tool);
  MeasurementSet rows = read_measurements_csv(validation, tool).measurements;
};

TEST(ValidateWorkflow, FileRequestEqualsTheLoadedCallAndItsPieces) {
  const Reference ref;
  ValidateRequest request{"abb-irb120", ref.tool_file, "", ref.validation, ref.calibration, {}};
  request.options.fit_base = true;
  const ValidateResult from_files = validate(request);

  ValidateOptions options;
  options.fit_base = true;
  options.calibration_mm =
      measured_positions(read_measurements_csv(ref.calibration, ref.tool).measurements);
  const ValidateResult loaded = validate(ref.nominal, ref.rows, options, ref.validation);
  EXPECT_EQ(validate_json(from_files), validate_json(loaded));
  EXPECT_EQ(from_files.frame, ValidationFrame::Fitted);
  EXPECT_TRUE(from_files.region_classes);

  // The workflow is the base fit followed by validate_model.
  const ValidationReport direct =
      validate_model(fit_base(ref.nominal, ref.rows), ref.rows, 2, kDefaultOrientationWeightMm,
                     options.calibration_mm);
  const nlohmann::json j = validate_json(from_files);
  EXPECT_EQ(j.at("points"), 1000);
  EXPECT_DOUBLE_EQ(j.at("position_error_mm").at("mean_mm").get<double>(),
                   direct.positions.position_mm.mean);
  EXPECT_DOUBLE_EQ(j.at("position_error_mm").at("mean_plus_3std_mm").get<double>(),
                   direct.positions.position_mm.mean + 3 * direct.positions.position_mm.std);
  EXPECT_DOUBLE_EQ(j.at("distance_error_mm").at("max_mm").get<double>(),
                   direct.distances.stats.max);
  EXPECT_EQ(j.at("distance_error_mm").at("pairs"), 1000 * 999 / 2);
  EXPECT_EQ(j.at("classes").back().at("table"), "region");
}

TEST(ValidateWorkflow, RefusalsNameTheirKey) {
  const Reference ref;
  ValidateOptions options;
  // The nominal robot has no world frame: the way out is named.
  try {
    validate(ref.nominal, ref.rows, options, "v.csv");
    FAIL() << "no refusal";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "--fit-base");
    EXPECT_NE(std::string(e.what()).find("--level base"), std::string::npos) << e.what();
  }
  options.fit_base = true;
  options.threads = 0;
  EXPECT_EQ(refusal_key([&] { validate(ref.nominal, ref.rows, options, "v.csv"); }), "--threads");
  options.threads = 2;
  options.orientation_weight_mm = 0;
  EXPECT_EQ(refusal_key([&] { validate(ref.nominal, ref.rows, options, "v.csv"); }),
            "--orientation-weight");
  options.orientation_weight_mm = kDefaultOrientationWeightMm;
  options.ballbar_centre_mm = Eigen::Vector3d(400, 0, 300);
  EXPECT_EQ(refusal_key([&] { validate(ref.nominal, ref.rows, options, "v.csv"); }),
            "--ballbar-centre");
  options.ballbar_centre_mm.reset();
  options.ballbar_length_mm = 150;
  EXPECT_EQ(refusal_key([&] { validate(ref.nominal, ref.rows, options, "v.csv"); }),
            "--ballbar-length");
  options.ballbar_length_mm.reset();
  options.ballbar_range_mm = 1;
  EXPECT_EQ(refusal_key([&] { validate(ref.nominal, ref.rows, options, "v.csv"); }),
            "--ballbar-range");
}

TEST(KinematicsWorkflow, HomePoseAndLimits) {
  const RobotModel irb120 = load_robot("abb-irb120");
  const FkReport home = forward_kinematics({irb120, Vector6d::Zero(), true});
  // The IRB 120 data sheet: flange at (374, 0, 630) mm, its z along the base x.
  EXPECT_NEAR((home.flange.p - Eigen::Vector3d(374, 0, 630)).norm(), 0, 1e-9);
  EXPECT_NEAR(home.flange.R.col(2).dot(Eigen::Vector3d::UnitX()), 1, 1e-12);
  const nlohmann::json j = fk_json(home);
  EXPECT_EQ(j["position_mm"], nlohmann::json({374.0, 0.0, 630.0}));
  Vector6d outside = Vector6d::Zero();
  outside[1] = deg2rad(200);
  try {
    forward_kinematics({irb120, outside, true});
    FAIL() << "no refusal";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "--joints");
    EXPECT_NE(std::string(e.what()).find("J2=200.000 outside"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(forward_kinematics({irb120, outside, false}));
}

TEST(KinematicsWorkflow, IkFindsTheJointsAndRefusesTheUnreachable) {
  const RobotModel irb120 = load_robot("abb-irb120");
  Vector6d q;
  q << 0.3, -0.4, 0.5, 0.6, 0.7, -0.8;
  const Pose<double> pose = forward_kinematics({irb120, q, true}).flange;
  const IkReport report = inverse_kinematics({irb120, pose, Vector6d::Zero(), true});
  double best = 1e9;
  for (const IkSolution& s : report.ik.solutions) best = std::min(best, (s.joints - q).norm());
  EXPECT_LT(best, 1e-9);
  EXPECT_EQ(ik_json(report)["solutions"].size(), report.ik.solutions.size());
  Pose<double> far = pose;
  far.p = Eigen::Vector3d(3000, 0, 400);
  EXPECT_EQ(refusal_key([&] {
              inverse_kinematics({irb120, far, Vector6d::Zero(), true});
            }),
            "--pose");
  const IkReport unreachable = inverse_kinematics({irb120, far, Vector6d::Zero(), false});
  EXPECT_EQ(unreachable.ik.status, IkStatus::Unreachable);
  EXPECT_EQ(ik_json(unreachable)["status"], to_string(IkStatus::Unreachable));
}

TEST(RobotCatalogue, EveryBuiltInRobotWithItsLimitsInDegrees) {
  const std::vector<RobotEntry> entries = robot_catalogue();
  ASSERT_EQ(entries.size(), builtin_robot_names().size());
  const nlohmann::json list = robot_catalogue_json(entries);
  EXPECT_EQ(list[0]["name"], entries[0].name);
  const RobotModel irb120 = load_robot("abb-irb120");
  const nlohmann::json d = robot_description_json(irb120);
  for (int i = 0; i < kJointCount; ++i) {
    EXPECT_NEAR(d["joint_limits_deg"][i][0].get<double>(), rad2deg(irb120.limits[i].lower), 1e-9);
    EXPECT_NEAR(d["joint_limits_deg"][i][1].get<double>(), rad2deg(irb120.limits[i].upper), 1e-9);
  }
  EXPECT_EQ(d["mdh"].size(), 6u);
}

}  // namespace
}  // namespace robcal
