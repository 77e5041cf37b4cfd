// Identification on synthetic data from known parameters: exact recovery without noise for every
// measurement kind (points with a target to identify, poses, ballbar distances), standard
// deviations consistent with the actual errors under noise (Monte Carlo), robust loss against a
// blunder, and clear errors for designs that cannot work.

#include <gtest/gtest.h>

#include "robcal/identify/identification.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

/// A true robot: the IRB 120 with random errors of a few tenths of mm / degree, compliance of the
/// published size, placed arbitrarily in the world.
ParameterVector random_truth(const RobotModel& model, std::mt19937_64& rng) {
  ParameterVector x = model.nominal();
  std::normal_distribution<double> n(0.0, 1.0);
  x[0] = 800 + 10 * n(rng);
  x[1] = -300 + 10 * n(rng);
  x[2] = 50 + 10 * n(rng);
  x[3] = deg2rad(0.5 * n(rng));
  x[4] = deg2rad(0.5 * n(rng));
  x[5] = deg2rad(30 + 5 * n(rng));
  for (int i = kLinkParamOffset; i < kComplianceOffset; ++i)
    x[i] += parameter_table()[i].kind == ParamKind::Angle ? deg2rad(0.05 * n(rng)) : 0.2 * n(rng);
  for (int j = 2; j <= 6; ++j) x[compliance_param(j)] = 3e-7 * (1 + 0.5 * n(rng));
  // link3.d is not identifiable (axes 2 and 3 parallel): it stays at its nominal value, or no
  // model with it held there could fit the data exactly.
  x[link_param(3, 3)] = model.nominal()[link_param(3, 3)];
  return x;
}

std::vector<Vector6d> random_configurations(int count, std::mt19937_64& rng) {
  const double lo[6] = {-90, 0, -80, -150, -90, -180}, hi[6] = {90, 90, 70, 150, 90, 180};
  std::vector<Vector6d> out(static_cast<size_t>(count));
  for (Vector6d& q : out)
    for (int j = 0; j < 6; ++j)
      q[j] = deg2rad(std::uniform_real_distribution<double>(lo[j], hi[j])(rng));
  return out;
}

Tool three_target_tool() {
  Tool tool;
  tool.payload = {2.6, Eigen::Vector3d(-23, 0, 100)};
  tool.targets = {
      {"1", {0, 0, 125}, true}, {"2", {75, 93.675, 215}, true}, {"3", {150, 0, 125}, true}};
  return tool;
}

MeasurementSet point_data(const RobotModel& model, const Tool& truth_tool,
                          const ParameterVector& truth, const std::vector<Vector6d>& configs,
                          double noise, std::mt19937_64& rng) {
  MeasurementSet set;
  set.kind = MeasurementKind::Points;
  std::normal_distribution<double> n(0.0, noise);
  for (size_t k = 0; k < configs.size(); ++k) {
    PointMeasurement m;
    m.config = std::to_string(k + 1);
    m.target = static_cast<int>(k % truth_tool.targets.size());
    m.joints = configs[k];
    m.position_mm = flange_pose(model, truth_tool.payload, truth, m.joints) *
                    truth_tool.targets[static_cast<size_t>(m.target)].position_mm;
    for (int a = 0; a < 3; ++a) m.position_mm[a] += noise > 0 ? n(rng) : 0.0;
    m.line = static_cast<int>(k) + 2;
    set.points.push_back(m);
  }
  return set;
}

/// Largest error over the identified model parameters in external units (mm, deg), with
/// link2.d + link3.d compared as one sum, and relative error of the compliances.
std::pair<double, double> recovery_error(const IdentificationResult& r,
                                         const ParameterVector& truth) {
  double geometric = 0, compliance = 0;
  for (int i = 0; i < kParameterCount; ++i) {
    if (r.robot.status[static_cast<size_t>(i)] != ParameterStatus::Identified) continue;
    double got = r.robot.params[i], expected = truth[i];
    if (i == link_param(2, 3)) {
      got += r.robot.params[link_param(3, 3)];
      expected += truth[link_param(3, 3)];
    }
    if (parameter_table()[i].kind == ParamKind::Compliance)
      compliance = std::max(compliance, std::abs(got / expected - 1));
    else
      geometric =
          std::max(geometric, std::abs(got - expected) * parameter_table()[i].to_external());
  }
  return {geometric, compliance};
}

TEST(IdentifySynthetic, NoiseFreePointsRecoverEveryIdentifiableParameterAndAnUnknownTarget) {
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(101);
  const ParameterVector truth = random_truth(model, rng);
  const Tool truth_tool = three_target_tool();
  const MeasurementSet data =
      point_data(model, truth_tool, truth, random_configurations(60, rng), 0, rng);
  Tool tool = truth_tool;
  tool.targets[1].known = false;  // target 2 is identified
  tool.targets[1].position_mm.setZero();
  IdentifyOptions options;
  options.level = CalibrationLevel::Full;
  const IdentificationResult r = calibrate(model, tool, data, options);
  EXPECT_TRUE(r.status.converged) << r.status.message;
  EXPECT_EQ(r.identified_count, 30 + 3);
  const auto [geometric, compliance] = recovery_error(r, truth);
  EXPECT_LT(geometric, 1e-6);
  EXPECT_LT(compliance, 1e-6);
  EXPECT_LT((r.robot.tool.targets[1].position_mm - truth_tool.targets[1].position_mm).norm(), 1e-6);
  EXPECT_TRUE(r.robot.tool.targets[1].known);
  std::cout << "noise-free points: max error " << geometric << " (mm, deg), compliance "
            << compliance << " relative\n";
}

TEST(IdentifySynthetic, NoiseFreePosesRecoverEveryParameter) {
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(202);
  const ParameterVector truth = random_truth(model, rng);
  Tool tool = three_target_tool();
  tool.flange_T_tcp.translation() = Eigen::Vector3d(20, -10, 150);
  tool.flange_T_tcp.linear() =
      rotation_from_euler_deg(Eigen::Vector3d(10, 20, 30), EulerConvention::ZyxABC);
  MeasurementSet data;
  data.kind = MeasurementKind::Poses;
  for (const Vector6d& q : random_configurations(40, rng)) {
    PoseMeasurement m;
    m.joints = q;
    const Pose<double> F = flange_pose(model, tool.payload, truth, q);
    m.world_T_tcp.R = F.R * tool.flange_T_tcp.linear();
    m.world_T_tcp.p = F * Eigen::Vector3d(tool.flange_T_tcp.translation());
    data.poses.push_back(m);
  }
  IdentifyOptions options;
  options.level = CalibrationLevel::Full;
  const IdentificationResult r = calibrate(model, tool, data, options);
  EXPECT_TRUE(r.status.converged) << r.status.message;
  EXPECT_EQ(r.identified_count, 30);
  const auto [geometric, compliance] = recovery_error(r, truth);
  EXPECT_LT(geometric, 1e-6);
  EXPECT_LT(compliance, 1e-6);
}

TEST(IdentifySynthetic, NoiseFreeBallbarDistancesRecoverTheRelativeModelAndTheCentre) {
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(303);
  ParameterVector truth = random_truth(model, rng);
  for (int j = 2; j <= 6; ++j) truth[compliance_param(j)] = 0;  // a kinematic robot
  const Tool tool = three_target_tool();
  const Eigen::Vector3d centre(1100, -250, 350);  // world frame
  MeasurementSet data;
  data.kind = MeasurementKind::Distances;
  int k = 0;
  for (const Vector6d& q : random_configurations(120, rng)) {
    DistanceMeasurement m;
    m.joints = q;
    m.target = k++ % 3;
    m.length_mm = (flange_pose(model, tool.payload, truth, q) *
                       tool.targets[static_cast<size_t>(m.target)].position_mm -
                   centre)
                      .norm();
    data.distances.push_back(m);
  }
  IdentifyOptions options;
  options.level = CalibrationLevel::Kinematic;
  const IdentificationResult r = calibrate(model, tool, data, options);
  EXPECT_TRUE(r.status.converged) << r.status.message;
  // Distances cannot see the base: all six are dropped, named after the centre they trade with.
  for (int i = 0; i < kBaseParamCount; ++i) {
    EXPECT_EQ(r.robot.status[static_cast<size_t>(i)], ParameterStatus::Dropped) << i;
    EXPECT_NE(r.robot.reason[static_cast<size_t>(i)].find("ballbar.centre"), std::string::npos)
        << r.robot.reason[static_cast<size_t>(i)];
  }
  EXPECT_FALSE(r.robot.base_fitted);
  EXPECT_LT(r.rms_mm, 1e-6);
  // The relative model is right: every distance between two configurations matches the truth.
  // (The link parameters themselves trade with the base the ballbar cannot see.)
  const std::vector<Vector6d> probe = random_configurations(50, rng);
  double worst = 0;
  for (size_t a = 0; a + 1 < probe.size(); ++a) {
    const Eigen::Vector3d pt =
        flange_pose(model, tool.payload, truth, probe[a]) * tool.targets[0].position_mm;
    const Eigen::Vector3d qt =
        flange_pose(model, tool.payload, truth, probe[a + 1]) * tool.targets[0].position_mm;
    const Eigen::Vector3d pm =
        flange_pose(model, tool.payload, r.robot.params, probe[a]) * tool.targets[0].position_mm;
    const Eigen::Vector3d qm = flange_pose(model, tool.payload, r.robot.params, probe[a + 1]) *
                               tool.targets[0].position_mm;
    worst = std::max(worst, std::abs((pt - qt).norm() - (pm - qm).norm()));
  }
  EXPECT_LT(worst, 1e-5);
}

TEST(IdentifySynthetic, StandardDeviationsMatchTheActualErrorsMonteCarlo) {
  // 100 noisy calibrations of the same robot and design: the errors of the estimates divided by
  // their reported standard deviations must have an RMS near 1 for every parameter group.
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(404);
  const ParameterVector truth = random_truth(model, rng);
  const Tool tool = three_target_tool();
  const std::vector<Vector6d> configs = random_configurations(50, rng);
  IdentifyOptions options;
  options.level = CalibrationLevel::Full;
  options.prediction_configurations = 0;
  double sum_sq = 0;
  int count = 0;
  for (int trial = 0; trial < 100; ++trial) {
    auto noise_rng = test::seeded_rng(1000 + static_cast<uint64_t>(trial));
    const MeasurementSet data = point_data(model, tool, truth, configs, 0.05, noise_rng);
    const IdentificationResult r = calibrate(model, tool, data, options);
    for (size_t c = 0; c < r.free.size(); ++c) {
      const int i = r.free[c];
      if (i == link_param(2, 3)) continue;  // compared as a sum with the dropped link3.d
      const double sd =
          std::sqrt(r.covariance(static_cast<Eigen::Index>(c), static_cast<Eigen::Index>(c)));
      const double z = (r.values[i] - truth[i]) / sd;
      sum_sq += z * z;
      ++count;
    }
  }
  const double rms = std::sqrt(sum_sq / count);
  EXPECT_GT(rms, 0.9);
  EXPECT_LT(rms, 1.1);
  std::cout << "Monte Carlo: RMS of normalised errors " << rms << " over " << count << "\n";
}

TEST(IdentifySynthetic, HuberLossResistsABlunderAndListsIt) {
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(505);
  const ParameterVector truth = random_truth(model, rng);
  const Tool tool = three_target_tool();
  MeasurementSet data = point_data(model, tool, truth, random_configurations(50, rng), 0.02, rng);
  data.points[17].position_mm += Eigen::Vector3d(1.5, -1.0, 0.5);  // a blunder (wrong SMR nest)
  IdentifyOptions options;
  options.level = CalibrationLevel::Full;
  options.prediction_configurations = 0;
  const IdentificationResult plain = calibrate(model, tool, data, options);
  options.huber = true;
  const IdentificationResult robust = calibrate(model, tool, data, options);
  ASSERT_FALSE(robust.outliers.empty());
  EXPECT_EQ(robust.outliers[0].config, "18");
  EXPECT_EQ(robust.outliers.size(), 1u);
  EXPECT_GT(robust.huber_scale_mm, 0);
  // Model error on fresh configurations: the robust fit is much closer to the truth.
  const auto model_error = [&](const ParameterVector& x) {
    double sum = 0;
    auto probe_rng = test::seeded_rng(9);
    const auto probe = random_configurations(200, probe_rng);
    for (const Vector6d& q : probe)
      sum +=
          (flange_pose(model, tool.payload, x, q).p - flange_pose(model, tool.payload, truth, q).p)
              .norm();
    return sum / 200;
  };
  const double plain_error = model_error(plain.robot.params);
  const double robust_error = model_error(robust.robot.params);
  EXPECT_LT(robust_error, 0.5 * plain_error);
  std::cout << "blunder: least squares error " << plain_error << " mm, Huber " << robust_error
            << " mm\n";
}

TEST(IdentifySynthetic, PatternsRefineTheLevel) {
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(606);
  const ParameterVector truth = random_truth(model, rng);
  const Tool tool = three_target_tool();
  const MeasurementSet data =
      point_data(model, tool, truth, random_configurations(40, rng), 0.01, rng);
  IdentifyOptions options;
  options.level = CalibrationLevel::Kinematic;
  options.fix = {"link6.*"};
  options.identify = {"joint2.compliance"};
  options.prediction_configurations = 0;
  const IdentificationResult r = calibrate(model, tool, data, options);
  EXPECT_EQ(r.identified_count, 25 - 4 + 1);
  EXPECT_EQ(r.robot.status[static_cast<size_t>(link_param(6, 1))], ParameterStatus::Fixed);
  EXPECT_EQ(r.robot.reason[static_cast<size_t>(link_param(6, 1))], "held by --fix");
  EXPECT_EQ(r.robot.status[static_cast<size_t>(compliance_param(2))], ParameterStatus::Identified);
  EXPECT_EQ(r.robot.status[static_cast<size_t>(compliance_param(3))], ParameterStatus::Fixed);
}

template <typename F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(IdentifySynthetic, BadInputGivesClearErrors) {
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(707);
  const ParameterVector truth = random_truth(model, rng);
  const Tool tool = three_target_tool();
  IdentifyOptions options;
  options.level = CalibrationLevel::Full;

  // Too few rows: 30 unknowns need 11 point rows.
  MeasurementSet few = point_data(model, tool, truth, random_configurations(8, rng), 0.0, rng);
  few.file = "few.csv";
  std::string message = input_error([&] { calibrate(model, tool, few, options); });
  EXPECT_NE(message.find("too few measurements"), std::string::npos) << message;
  EXPECT_NE(message.find("at least 11 rows"), std::string::npos) << message;
  EXPECT_NE(message.find("few.csv"), std::string::npos) << message;

  // Rank-deficient design: joint 6 never moves, so its offset trades with the base/targets...
  auto configs = random_configurations(40, rng);
  for (Vector6d& q : configs) {
    q[5] = 0.3;
    q[4] = 0.7;
  }
  const MeasurementSet frozen = point_data(model, tool, truth, configs, 0.0, rng);
  message = input_error([&] { calibrate(model, tool, frozen, options); });
  EXPECT_NE(message.find("rank-deficient design"), std::string::npos) << message;
  EXPECT_NE(message.find("link6"), std::string::npos) << message;
  EXPECT_NE(message.find("depends on"), std::string::npos) << message;

  // Unknown pattern.
  const MeasurementSet data =
      point_data(model, tool, truth, random_configurations(40, rng), 0.0, rng);
  options.fix = {"link7.*"};
  message = input_error([&] { calibrate(model, tool, data, options); });
  EXPECT_NE(message.find("'link7.*' matches no parameter"), std::string::npos) << message;
  EXPECT_NE(message.find("--fix"), std::string::npos) << message;
  options.fix.clear();

  // Unknown level.
  message = input_error([&] { parse_calibration_level("everything"); });
  EXPECT_NE(message.find("unknown level 'everything'"), std::string::npos) << message;

  // No rows.
  MeasurementSet empty;
  empty.file = "empty.csv";
  message = input_error([&] { calibrate(model, tool, empty, options); });
  EXPECT_NE(message.find("no rows"), std::string::npos) << message;
}

}  // namespace
}  // namespace robcal
