// "Realistic shop data": what a new user's first calibration files look like — one target on
// the tool axis, a payload-free tool, a robot file without masses, lengths in metres, Euler
// angles of three conventions, a 6D instrument with an unknown TCP, a moved base — generated
// from a known robot. Each case asserts the warning or error the user sees and that every
// reported parameter is within 3σ of the truth and physically sensible; a fit that cannot be
// trusted (model misfit, another robot's model) is flagged instead of written.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "refusal.hpp"
#include "robcal/compensate/calibrated_ik.hpp"
#include "robcal/identify/calibration_output.hpp"
#include "robcal/identify/calibration_run.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "test_compensate_support.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

/// The IRB 120 with errors of a few tenths of mm / degree, moved to an arbitrary place in the
/// tracker's frame. What no data can see stays nominal (link3.d beside link2.d; `hold`).
ParameterVector shop_truth(const RobotModel& model, std::mt19937_64& rng,
                           const std::vector<std::string>& hold, double compliance) {
  ParameterVector x = model.nominal();
  std::normal_distribution<double> n(0.0, 1.0);
  x.head<6>() << 1650 + 5 * n(rng), -420 + 5 * n(rng), -310 + 5 * n(rng), deg2rad(0.3 * n(rng)),
      deg2rad(0.3 * n(rng)), deg2rad(-57 + 3 * n(rng));
  for (int i = kLinkParamOffset; i < kComplianceOffset; ++i)
    x[i] += parameter_table()[i].kind == ParamKind::Angle ? deg2rad(0.05 * n(rng)) : 0.2 * n(rng);
  for (int j = 2; j <= 6; ++j) x[compliance_param(j)] = compliance * (1 + 0.3 * n(rng));
  x[link_param(3, 3)] = model.nominal()[link_param(3, 3)];
  for (const std::string& name : hold)
    x[parameter_index(name)] = model.nominal()[parameter_index(name)];
  return x;
}

std::vector<Vector6d> configurations(const RobotModel& model, int count, std::mt19937_64& rng) {
  std::vector<Vector6d> out(static_cast<size_t>(count));
  for (Vector6d& q : out)
    for (int j = 0; j < kJointCount; ++j) {
      const JointLimit& l = model.limits[static_cast<size_t>(j)];
      const double margin = 0.15 * (l.upper - l.lower);
      q[j] = std::uniform_real_distribution<double>(l.lower + margin, l.upper - margin)(rng);
    }
  return out;
}

std::string degrees(const Vector6d& q) {
  return fmt::format("{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}", rad2deg(q[0]), rad2deg(q[1]),
                     rad2deg(q[2]), rad2deg(q[3]), rad2deg(q[4]), rad2deg(q[5]));
}

/// A tracker's points file in metres of the truth's target `target_mm` (noise σ per axis).
std::string points_in_metres(const RobotModel& model, const PointMass& payload,
                             const ParameterVector& truth, const Eigen::Vector3d& target_mm,
                             const std::vector<Vector6d>& configs, double sigma,
                             std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, sigma);
  std::string text = "# tracker export\nconfig,target,j1,j2,j3,j4,j5,j6,x,y,z\n";
  for (size_t k = 0; k < configs.size(); ++k) {
    const Eigen::Vector3d p = flange_pose(model, payload, truth, configs[k]) * target_mm;
    text += fmt::format("P{},T1,{},{:.8f},{:.8f},{:.8f}\n", k + 1, degrees(configs[k]),
                        (p.x() + noise(rng)) / 1000, (p.y() + noise(rng)) / 1000,
                        (p.z() + noise(rng)) / 1000);
  }
  return text;
}

/// The identified model parameters agree with the truth: each within 3σ, physically sensible
/// (link angles within 0.5°, lengths within 2 mm of the truth), and — the check that does not
/// fail by chance once in twelve fits of 30 parameters — the whole error vector consistent with
/// the covariance: δᵀC⁻¹δ below the χ² 99.9 % quantile. A parameter past 3σ is reported; the fit
/// fails if one is past 4σ or the joint test fails.
void expect_within_3_sigma(const IdentificationResult& r, const ParameterVector& truth) {
  std::vector<Eigen::Index> model;
  for (size_t c = 0; c < r.free.size(); ++c)
    if (r.free[c] < kParameterCount) model.push_back(static_cast<Eigen::Index>(c));
  const auto n = static_cast<Eigen::Index>(model.size());
  Eigen::VectorXd delta(n);
  Eigen::MatrixXd C(n, n);
  int beyond_3_sigma = 0;
  for (Eigen::Index a = 0; a < n; ++a) {
    const int i = r.free[static_cast<size_t>(model[static_cast<size_t>(a)])];
    delta[a] = r.values[i] - truth[i];
    for (Eigen::Index b = 0; b < n; ++b) C(a, b) = r.covariance(model[a], model[b]);
    const UnknownEstimate& u = r.unknowns[static_cast<size_t>(i)];
    const double f = parameter_table()[static_cast<size_t>(i)].to_external();
    const double error = std::abs(delta[a]) * f;
    if (error > 3 * u.std_dev) {
      ++beyond_3_sigma;
      std::cout << "beyond 3σ: " << u.name << " error " << error << " σ " << u.std_dev << "\n";
    }
    EXPECT_LE(error, 4 * u.std_dev) << u.name << " = " << u.value << ", truth " << truth[i] * f;
    const ParamKind kind = parameter_table()[static_cast<size_t>(i)].kind;
    if (i >= kLinkParamOffset && kind == ParamKind::Angle) {
      EXPECT_LT(error, 0.5) << u.name;
    }
    if (i >= kLinkParamOffset && kind == ParamKind::Length) {
      EXPECT_LT(error, 2.0) << u.name;
    }
  }
  EXPECT_GT(n, 10);
  const double mahalanobis = delta.dot(C.ldlt().solve(delta));
  EXPECT_GT(chi_square_upper_tail(mahalanobis, static_cast<int>(n)), 1e-3)
      << "δᵀC⁻¹δ = " << mahalanobis << " for " << n << " parameters";
  EXPECT_LE(beyond_3_sigma, 2);
}

/// Compensation works with the fitted model (issue 13: a singular or absurd model must not be
/// written). At configurations ≥ 10° from singularities, the calibrated inverse converges for
/// the calibration's payload and for 5 kg (`compensate --payload-mass-kg 5`), and the true robot
/// at the compensated joints puts the TCP (`true_tcp`: the truth's flange_T_tcp) where it was
/// wanted, within 4 × the fit's own predicted maximum error against the true robot.
void expect_compensates(const IdentificationResult& r, const RobotModel& real,
                        const ParameterVector& truth, const Pose<double>& true_tcp,
                        std::mt19937_64& rng) {
  const Compensator as_calibrated = make_compensator(r.robot);
  const Compensator heavy = make_compensator(r.robot, PointMass{5.0, {0, 0, 80}});
  int solved = 0;
  for (const Vector6d& q : configurations(real, 30, rng)) {
    if (test::near_singular(real, q, 10)) continue;
    ++solved;
    const PointMass& payload = as_calibrated.condition.payload;
    const Pose<double> wanted = flange_pose(real, payload, truth, q) * true_tcp;
    const CalibratedIkResult ik = calibrated_ik(as_calibrated, wanted, arm_config(real, q), q);
    ASSERT_TRUE(ik.ok()) << to_string(ik.status);
    const Pose<double> reached = flange_pose(real, payload, truth, ik.joints) * true_tcp;
    // A floor of 1 µm for noise-free data: the inverse's own tolerance is 5e-7 mm.
    EXPECT_LT((reached.p - wanted.p).norm(), std::max(4 * r.predicted.max_mm, 1e-3));
    const Pose<double> wanted_heavy =
        flange_pose(real, heavy.condition.payload, truth, q) * true_tcp;
    const CalibratedIkResult ik_heavy = calibrated_ik(heavy, wanted_heavy, arm_config(real, q), q);
    EXPECT_TRUE(ik_heavy.ok()) << to_string(ik_heavy.status);
  }
  EXPECT_GE(solved, 15);
}

TEST(ShopData, ChiSquareTailMatchesTabulatedQuantiles) {
  // χ² quantiles (Abramowitz & Stegun table 26.8): P(χ²_ν ≥ x) for (ν, x, P).
  EXPECT_NEAR(chi_square_upper_tail(149.449, 100), 0.001, 0.0002);
  EXPECT_NEAR(chi_square_upper_tail(124.342, 100), 0.05, 0.002);
  EXPECT_NEAR(chi_square_upper_tail(29.588, 10), 0.001, 0.0003);
  EXPECT_NEAR(chi_square_upper_tail(99.334, 100), 0.5, 0.01);
}

/// The reference set's tool: three SMRs and a 2.6 kg payload.
Tool published_tool() {
  Tool tool;
  tool.payload = {2.6, {-23, 0, 100}};
  tool.targets = {
      {"1", {0, 0, 125}, true}, {"2", {75, 93.675, 215}, true}, {"3", {150, 0, 125}, true}};
  return tool;
}

bool has_warning(const IdentificationResult& r, const std::string& text) {
  for (const std::string& w : r.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

TEST(ShopData, OneTargetOnTheToolAxisPayloadFreeToolInMetres) {
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(1301);
  // The one SMR on the tool axis cannot see link6.theta, nor link6.a and link6.alpha apart
  // from link5.theta and link5.d: they stay at nominal in the truth.
  const ParameterVector truth =
      shop_truth(model, rng, {"link6.a", "link6.alpha", "link6.theta"}, 4e-7);
  Tool tool;  // payload-free
  tool.targets = {{"T1", {0, 0, 125}, true}};
  const std::string text = points_in_metres(model, tool.payload, truth, {0, 0, 125},
                                            configurations(model, 50, rng), 0.02, rng);
  // Undeclared metres are refused, with what to declare.
  try {
    (void)parse_measurements_csv(text, "shop.csv", tool);
    ADD_FAILURE() << "metres read as mm";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("shop.csv:2:9 (x): the positions span only"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("they look like metres"), std::string::npos);
  }
  const MeasurementFile file = parse_measurements_csv("# units: m\n" + text, "shop.csv", tool);
  EXPECT_NEAR(file.measurements.points[0].position_mm.norm(), 1000, 900);  // mm now

  CalibrationRequest request;
  request.options.instrument_sigma_mm = 0.02;
  const CalibrationRun run = run_calibration(model, tool, file.measurements, request);
  const IdentificationResult& r = run.result;
  for (const std::string& w : r.warnings) std::cout << "warning: " << w << "\n";
  EXPECT_TRUE(has_warning(r,
                          "joint4.compliance not identified: the gravity torque about axis 4 is "
                          "below 0.1 N·mm in every measured configuration"));
  EXPECT_TRUE(has_warning(r, "and the tool has no payload"));
  EXPECT_TRUE(has_warning(r,
                          "link5.theta, link6.a: only their combination is determined by "
                          "these measurements"));
  EXPECT_TRUE(has_warning(r, "link5.d, link6.alpha: only their combination"));
  EXPECT_TRUE(has_warning(r, "link6.theta: these measurements do not depend on it"));
  EXPECT_TRUE(has_warning(r, "every target lies on the tool axis"));
  for (const char* name : {"joint4.compliance", "link6.a", "link6.alpha", "link6.theta"}) {
    const auto i = static_cast<size_t>(parameter_index(name));
    EXPECT_EQ(r.robot.status[i], ParameterStatus::Dropped) << name;
    EXPECT_FALSE(r.robot.reason[i].empty()) << name;
  }
  // The model file records what was done.
  const std::string yaml = calibrated_robot_to_yaml(r.robot, statistics_writer(r));
  EXPECT_NE(yaml.find("the gravity torque about axis 4 is below"), std::string::npos);
  EXPECT_NE(yaml.find("link5.theta, link6.a: only their combination"), std::string::npos);
  EXPECT_TRUE(r.noise_test.consistent) << r.noise_test.p_value;
  EXPECT_TRUE(run.problems.empty());
  expect_within_3_sigma(r, truth);
  expect_compensates(r, model, truth, {}, rng);
}

TEST(ShopData, NearlyOnAxisTargetIsHeldAndNamedBeforeTheFit) {
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(1302);
  const ParameterVector truth = shop_truth(model, rng, {"link6.a", "link6.alpha"}, 4e-7);
  Tool tool;
  tool.payload = {1.5, {0, 40, 60}};
  // 0.02 mm off the axis: link6.a then moves by millimetres within its σ.
  tool.targets = {{"T1", {0.02, 0, 125}, true}};
  const std::string text = points_in_metres(model, tool.payload, truth, {0.02, 0, 125},
                                            configurations(model, 50, rng), 0.02, rng);
  const MeasurementFile file = parse_measurements_csv("# units: m\n" + text, "s.csv", tool);
  IdentifyOptions options;
  const IdentificationResult r = calibrate(model, tool, file.measurements, options);
  EXPECT_TRUE(has_warning(r,
                          "link5.theta, link6.a: only their combination is determined by "
                          "these measurements (correlation "));
  EXPECT_TRUE(has_warning(r, "link6.theta: these measurements barely see it"));
  EXPECT_TRUE(has_warning(r, "link6.a is held at its nominal value"));
  expect_within_3_sigma(r, truth);
  expect_compensates(r, model, truth, {}, rng);
  // Asked to keep them, the fit says so and the correlated pair is free.
  options.resolve_near_dependencies = false;
  const IdentificationResult kept = calibrate(model, tool, file.measurements, options);
  EXPECT_TRUE(has_warning(kept, "fitted anyway (--keep-near-dependent)"));
  EXPECT_EQ(kept.robot.status[static_cast<size_t>(parameter_index("link6.a"))],
            ParameterStatus::Identified);
}

TEST(ShopData, RobotFileWithoutMassesSaysSo) {
  RobotModel model = load_robot("abb-irb120");
  for (PointMass& m : model.link_masses) m = {};
  auto rng = test::seeded_rng(1303);
  const ParameterVector truth = shop_truth(model, rng, {}, 0.0);  // what this model can hold
  Tool tool = published_tool();
  tool.payload = {};
  MeasurementSet data;
  data.kind = MeasurementKind::Points;
  data.file = "nomass.csv";
  std::normal_distribution<double> noise(0.0, 0.02);
  const auto configs = configurations(model, 45, rng);
  for (size_t k = 0; k < configs.size(); ++k) {
    PointMeasurement m{std::to_string(k), static_cast<int>(k % 3), configs[k], {}, int(k) + 2};
    m.position_mm =
        flange_pose(model, tool.payload, truth, configs[k]) * tool.targets[k % 3].position_mm;
    for (int a = 0; a < 3; ++a) m.position_mm[a] += noise(rng);
    data.points.push_back(m);
  }
  const IdentificationResult r = calibrate(model, tool, data, IdentifyOptions{});
  EXPECT_TRUE(has_warning(r,
                          "the robot file of ABB IRB 120 gives no masses ('masses:' with each "
                          "link's mass_kg and cog_mm) and the tool no payload, so the joint "
                          "compliances (joint2.compliance, joint3.compliance, "
                          "joint4.compliance, joint5.compliance, joint6.compliance) cannot be "
                          "identified"));
  EXPECT_EQ(r.robot.reason[static_cast<size_t>(compliance_param(2))],
            "the robot file gives no masses ('masses:'), so the gravity torques that deflect the "
            "joint are unknown");
  expect_within_3_sigma(r, truth);
  expect_compensates(r, model, truth, {}, rng);
}

TEST(ShopData, RobotFileWithoutLinkMassesButAPayloadSaysTheCompliancesAreBiased) {
  // The real arm has its link masses; the user's robot file does not, the tool has 2.6 kg.
  const RobotModel real = load_robot("abb-irb120");
  RobotModel stripped = real;
  for (PointMass& m : stripped.link_masses) m = {};
  auto rng = test::seeded_rng(1307);
  const ParameterVector truth = shop_truth(real, rng, {}, 4e-7);
  const Tool tool = published_tool();
  MeasurementSet data;
  data.kind = MeasurementKind::Points;
  std::normal_distribution<double> noise(0.0, 0.02);
  const auto configs = configurations(real, 60, rng);
  for (size_t k = 0; k < configs.size(); ++k) {
    PointMeasurement m{std::to_string(k), static_cast<int>(k % 3), configs[k], {}, int(k) + 2};
    m.position_mm =
        flange_pose(real, tool.payload, truth, configs[k]) * tool.targets[k % 3].position_mm;
    for (int a = 0; a < 3; ++a) m.position_mm[a] += noise(rng);
    data.points.push_back(m);
  }
  const IdentificationResult r = calibrate(stripped, tool, data, IdentifyOptions{});
  EXPECT_TRUE(has_warning(r,
                          "the robot file of ABB IRB 120 gives no link masses ('masses:'), only "
                          "the tool's payload: the compliances (joint2.compliance, "
                          "joint3.compliance, joint4.compliance, joint5.compliance, "
                          "joint6.compliance) see the payload's torque alone and absorb the "
                          "deflection under the arm's own weight, so their values are biased. "
                          "Add each link's mass_kg and cog_mm to the robot file"));
  // The warning is warranted: joint 2 carries the arm, its compliance is far off the truth.
  const int j2 = compliance_param(2);
  const UnknownEstimate& c2 = r.unknowns[static_cast<size_t>(j2)];
  ASSERT_EQ(c2.status, ParameterStatus::Identified);
  const double truth_external =
      truth[j2] * parameter_table()[static_cast<size_t>(j2)].to_external();
  EXPECT_GT(std::abs(c2.value - truth_external), 3 * c2.std_dev)
      << c2.value << " ± " << c2.std_dev << ", truth " << truth_external;
  // With the masses in the robot file there is no such warning.
  EXPECT_FALSE(has_warning(calibrate(real, tool, data, IdentifyOptions{}), "no link masses"));
}

/// A 6D instrument's poses file of the truth's TCP frame, orientation in `convention`.
std::string pose_file(const RobotModel& model, const ParameterVector& truth,
                      const Eigen::Isometry3d& tcp, const std::vector<Vector6d>& configs,
                      const std::string& convention, std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, 1.0);
  const double sigma = 0.01, sigma_rad = sigma / kDefaultOrientationWeightMm;
  std::string text;
  if (convention == "abc") text = "config,j1,j2,j3,j4,j5,j6,x,y,z,a,b,c\n";
  if (convention == "wpr") text = "config,j1,j2,j3,j4,j5,j6,x,y,z,w,p,r\n";
  if (convention == "rxyz")
    text = "# euler: intrinsic XYZ\nconfig,j1,j2,j3,j4,j5,j6,x,y,z,rx,ry,rz\n";
  for (size_t k = 0; k < configs.size(); ++k) {
    const Pose<double> F = flange_pose(model, PointMass{}, truth, configs[k]);
    const Eigen::Vector3d p = F * Eigen::Vector3d(tcp.translation()) +
                              sigma * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    const Eigen::Vector3d turn = sigma_rad * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(turn.norm(), turn.normalized()).toRotationMatrix() * F.R * tcp.linear();
    // Angles by an independent route: Eigen's Euler extraction.
    Eigen::Vector3d e;
    if (convention == "rxyz")
      e = R.eulerAngles(0, 1, 2);  // R = Rx·Ry·Rz
    else
      e = R.eulerAngles(2, 1, 0);  // R = Rz(a)·Ry(b)·Rx(c)
    e = e.unaryExpr([](double v) { return rad2deg(v); });
    const Eigen::Vector3d columns = convention == "wpr" ? Eigen::Vector3d(e[2], e[1], e[0]) : e;
    text +=
        fmt::format("P{},{},{:.6f},{:.6f},{:.6f},{:.9f},{:.9f},{:.9f}\n", k + 1,
                    degrees(configs[k]), p.x(), p.y(), p.z(), columns[0], columns[1], columns[2]);
  }
  return text;
}

TEST(ShopData, UnknownTcpFromEulerPoseFilesOfThreeConventionsAndAMovedBase) {
  RobotModel model = load_robot("abb-irb120");
  for (PointMass& m : model.link_masses) m = {};  // a 6D instrument's file of a bare robot file
  auto rng = test::seeded_rng(1304);
  // The TCP takes link6.d and link6.theta's place along and about the flange axis.
  const ParameterVector truth = shop_truth(model, rng, {"link6.d", "link6.theta"}, 0.0);
  Eigen::Isometry3d tcp = Eigen::Isometry3d::Identity();
  tcp.translation() = Eigen::Vector3d(12, -25, 160);
  tcp.linear() = (Eigen::AngleAxisd(deg2rad(35), Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(deg2rad(-90), Eigen::Vector3d::UnitY()))
                     .toRotationMatrix();
  const auto configs = configurations(model, 40, rng);
  const Tool tool = parse_tool(yaml::parse("tcp: ~\n", "tool.yaml"));
  EXPECT_TRUE(tool.tcp_given);
  EXPECT_FALSE(tool.tcp_position_known || tool.tcp_orientation_known);
  for (const std::string convention : {"abc", "wpr", "rxyz"}) {
    SCOPED_TRACE(convention);
    const std::string text = pose_file(model, truth, tcp, configs, convention, rng);
    const MeasurementFile file = parse_measurements_csv(text, convention + ".csv", tool);
    CalibrationRequest request;
    request.options.level = CalibrationLevel::Kinematic;
    request.options.instrument_sigma_mm = 0.01;
    const CalibrationRun run = run_calibration(model, tool, file.measurements, request);
    const IdentificationResult& r = run.result;
    EXPECT_TRUE(r.status.converged);
    EXPECT_TRUE(run.problems.empty()) << (run.problems.empty() ? "" : run.problems[0]);
    EXPECT_TRUE(r.noise_test.consistent) << r.noise_test.chi_square << " / " << r.noise_test.dof;
    const Eigen::Isometry3d& got = r.robot.tool.flange_T_tcp;
    const Eigen::AngleAxisd rotation_error(got.linear().transpose() * tcp.linear());
    EXPECT_LT((got.translation() - tcp.translation()).norm(), 0.05);
    EXPECT_LT(rad2deg(rotation_error.angle()), 0.01);
    for (const UnknownEstimate& u : r.unknowns)
      if (u.name.starts_with("tcp.")) {
        EXPECT_EQ(u.status, ParameterStatus::Identified) << u.name;
      }
    expect_within_3_sigma(r, truth);
    expect_compensates(r, model, truth, {tcp.linear(), tcp.translation()}, rng);
  }
  // The same poses with a tool file that has no tcp: loudly taken as the flange.
  const MeasurementFile file =
      parse_measurements_csv(pose_file(model, truth, tcp, configs, "abc", rng), "p.csv", Tool{});
  const IdentificationResult flange = calibrate(model, Tool{}, file.measurements, {});
  EXPECT_TRUE(has_warning(flange, "POSES WITHOUT A TCP: the tool file has no 'tcp'"));
}

TEST(ShopData, TcpGivenInPartIdentifiesOnlyTheMissingPart) {
  RobotModel model = load_robot("abb-irb120");
  for (PointMass& m : model.link_masses) m = {};
  auto rng = test::seeded_rng(1308);
  const ParameterVector truth = shop_truth(model, rng, {"link6.d", "link6.theta"}, 0.0);
  Eigen::Isometry3d tcp = Eigen::Isometry3d::Identity();
  tcp.translation() = Eigen::Vector3d(-8, 30, 140);
  tcp.linear() =
      Eigen::AngleAxisd(deg2rad(25), Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Quaterniond q(tcp.linear());
  const std::string position = fmt::format("[{:.12f}, {:.12f}, {:.12f}]", tcp.translation().x(),
                                           tcp.translation().y(), tcp.translation().z());
  const std::string rotation =
      fmt::format("[{:.15f}, {:.15f}, {:.15f}, {:.15f}]", q.w(), q.x(), q.y(), q.z());
  const auto configs = configurations(model, 40, rng);
  const std::string text = pose_file(model, truth, tcp, configs, "abc", rng);
  for (const bool position_missing : {true, false}) {
    SCOPED_TRACE(position_missing ? "position_mm: ~" : "quaternion_wxyz: ~");
    const Tool tool = parse_tool(
        yaml::parse(position_missing ? "tcp: {position_mm: ~, quaternion_wxyz: " + rotation + "}\n"
                                     : "tcp: {position_mm: " + position + ", quaternion_wxyz: ~}\n",
                    "tool.yaml"));
    EXPECT_EQ(tool.tcp_position_known, !position_missing);
    EXPECT_EQ(tool.tcp_orientation_known, position_missing);
    const MeasurementFile file = parse_measurements_csv(text, "part.csv", tool);
    CalibrationRequest request;
    request.options.level = CalibrationLevel::Kinematic;
    request.options.instrument_sigma_mm = 0.01;
    const CalibrationRun run = run_calibration(model, tool, file.measurements, request);
    const IdentificationResult& r = run.result;
    EXPECT_TRUE(run.problems.empty()) << (run.problems.empty() ? "" : run.problems[0]);
    EXPECT_TRUE(r.noise_test.consistent) << r.noise_test.chi_square << " / " << r.noise_test.dof;
    std::vector<std::string> tcp_unknowns;
    for (const UnknownEstimate& u : r.unknowns)
      if (u.name.starts_with("tcp.")) {
        tcp_unknowns.push_back(u.name);
        EXPECT_EQ(u.status, ParameterStatus::Identified) << u.name;
      }
    const std::vector<std::string> expected =
        position_missing ? std::vector<std::string>{"tcp.x", "tcp.y", "tcp.z"}
                         : std::vector<std::string>{"tcp.rx", "tcp.ry", "tcp.rz"};
    EXPECT_EQ(tcp_unknowns, expected);
    // The missing part identified, the given part kept as written.
    const Eigen::Isometry3d& got = r.robot.tool.flange_T_tcp;
    const double rotation_error_deg =
        rad2deg(Eigen::AngleAxisd(got.linear().transpose() * tcp.linear()).angle());
    EXPECT_LT((got.translation() - tcp.translation()).norm(), position_missing ? 0.05 : 1e-9);
    EXPECT_LT(rotation_error_deg, position_missing ? 1e-9 : 0.01);
    expect_compensates(r, model, truth, {tcp.linear(), tcp.translation()}, rng);
  }
}

TEST(ShopData, TcpRotationJacobianMatchesFiniteDifferences) {
  const RobotModel model = load_robot("abb-irb120");
  Tool tool;
  tool.tcp_given = true;
  tool.tcp_position_known = tool.tcp_orientation_known = false;
  tool.flange_T_tcp.linear() =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  MeasurementSet data;
  data.kind = MeasurementKind::Poses;
  PoseMeasurement m;
  m.joints << 0.3, -0.4, 0.5, 1.1, -0.7, 2.0;
  m.world_T_tcp.R =
      Eigen::AngleAxisd(1.0, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  m.world_T_tcp.p = Eigen::Vector3d(400, 100, 500);
  data.poses.push_back(m);
  const UnknownLayout layout = make_unknown_layout(tool, MeasurementKind::Poses);
  ASSERT_EQ(layout.size(), kParameterCount + 6);
  const ResidualContext context{&model, &tool, &data, &layout, 80.0};
  Eigen::VectorXd u = Eigen::VectorXd::Zero(layout.size());
  u.head<kParameterCount>() = model.nominal();
  u.segment<3>(layout.tcp_position) << 5, -7, 140;
  u.segment<3>(layout.tcp_rotation) << 0.9, -1.3, 0.6;  // a large rotation: J_r matters
  Eigen::MatrixXd J;
  Eigen::Matrix<double, 6, 1> r0, rp, rm;
  row_residuals(context, u, 0, r0.data(), &J);
  for (int c = layout.tcp_position; c < layout.size(); ++c) {
    const double h = 1e-6;
    Eigen::VectorXd up = u, um = u;
    up[c] += h;
    um[c] -= h;
    row_residuals(context, up, 0, rp.data(), nullptr);
    row_residuals(context, um, 0, rm.data(), nullptr);
    const Eigen::Matrix<double, 6, 1> numeric = (rp - rm) / (2 * h);
    EXPECT_LT((J.col(c) - numeric).norm(), 1e-6 * std::max(1.0, numeric.norm()))
        << layout.names[static_cast<size_t>(c)] << "\n"
        << J.col(c).transpose() << "\n"
        << numeric.transpose();
  }
}

TEST(ShopData, MisfitIsReportedAndCrossValidatedAnotherRobotIsNotTrusted) {
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(1305);
  const ParameterVector truth = shop_truth(model, rng, {}, 4e-7);
  const Tool tool = published_tool();
  const auto configs = configurations(model, 50, rng);
  MeasurementSet data;
  data.kind = MeasurementKind::Points;
  std::normal_distribution<double> noise(0.0, 0.02);
  for (size_t k = 0; k < configs.size(); ++k) {
    // An effect the model does not contain: a 0.02° periodic error of joint 2.
    Vector6d q = configs[k];
    q[1] += deg2rad(0.02) * std::sin(3 * q[1] + 1.0);
    PointMeasurement m{fmt::format("c{}", k), static_cast<int>(k % 3), configs[k], {}, int(k) + 2};
    m.position_mm = flange_pose(model, tool.payload, truth, q) * tool.targets[k % 3].position_mm;
    for (int a = 0; a < 3; ++a) m.position_mm[a] += noise(rng);
    data.points.push_back(m);
  }
  CalibrationRequest request;
  request.options.instrument_sigma_mm = 0.02;
  const CalibrationRun run = run_calibration(model, tool, data, request);
  EXPECT_FALSE(run.result.noise_test.consistent) << run.result.noise_test.p_value;
  EXPECT_LT(run.result.noise_test.p_value, kNoiseTestLevel);
  ASSERT_TRUE(run.cross_validation.has_value());
  EXPECT_TRUE(run.cross_validation_for_misfit);
  EXPECT_EQ(run.cross_validation->folds, kMisfitFolds);
  // Like with like, on new configurations of the same robot: the calibrated model's error
  // against the true robot (the periodic error included) exceeds what the covariance predicts
  // against the truth, which counts the misfit as noise; against new measurements (the truth
  // plus the instrument's noise) the held-out error of the cross-validation predicts it.
  const CalibratedRobot& fitted = run.result.robot;
  double truth_error = 0, measurement_error = 0;
  const auto fresh = configurations(model, 300, rng);
  for (size_t k = 0; k < fresh.size(); ++k) {
    Vector6d q = fresh[k];
    q[1] += deg2rad(0.02) * std::sin(3 * q[1] + 1.0);
    const Eigen::Vector3d truth_mm =
        flange_pose(model, tool.payload, truth, q) * tool.targets[k % 3].position_mm;
    const Eigen::Vector3d model_mm = flange_pose(model, tool.payload, fitted.params, fresh[k]) *
                                     fitted.tool.targets[k % 3].position_mm;
    truth_error += (model_mm - truth_mm).norm() / static_cast<double>(fresh.size());
    measurement_error +=
        (model_mm - truth_mm - Eigen::Vector3d(noise(rng), noise(rng), noise(rng))).norm() /
        static_cast<double>(fresh.size());
  }
  std::cout << fmt::format(
      "misfit: mean error against the truth {:.4f} mm (covariance predicts {:.4f}), against new "
      "measurements {:.4f} mm (cross-validated {:.4f}, covariance {:.4f})\n",
      truth_error, run.result.predicted.mean_mm, measurement_error, run.cross_validation->mean_mm,
      run.result.predicted.mean_vs_measurements_mm);
  EXPECT_GT(truth_error, 1.5 * run.result.predicted.mean_mm)
      << "predicted " << run.result.predicted.mean_mm;
  EXPECT_NEAR(run.cross_validation->mean_mm, measurement_error, 0.25 * measurement_error);
  // Without the misfit the two agree (within the spread of 50 held-out rows).
  CalibrationRequest asked = request;
  asked.kfold = kMisfitFolds;
  // Consistent without the effect: no cross-validation unless asked.
  MeasurementSet clean = data;
  for (size_t k = 0; k < configs.size(); ++k)
    clean.points[k].position_mm =
        flange_pose(model, tool.payload, truth, configs[k]) * tool.targets[k % 3].position_mm +
        Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  const CalibrationRun fine = run_calibration(model, tool, clean, asked);
  EXPECT_TRUE(fine.result.noise_test.consistent) << fine.result.noise_test.p_value;
  ASSERT_TRUE(fine.cross_validation.has_value());
  EXPECT_FALSE(fine.cross_validation_for_misfit);
  EXPECT_NEAR(fine.cross_validation->mean_mm, fine.result.predicted.mean_vs_measurements_mm,
              0.3 * fine.result.predicted.mean_vs_measurements_mm);
  EXPECT_FALSE(run_calibration(model, tool, clean, request).cross_validation.has_value());
  EXPECT_TRUE(fine.problems.empty());
  // One residual definition: start and calibrated alike, mean ≤ rms ≤ max.
  EXPECT_LE(fine.result.mean_mm, fine.result.rms_mm);
  EXPECT_LE(fine.result.rms_mm, fine.result.max_mm);
  EXPECT_GT(fine.result.start_rms_mm, 10 * fine.result.rms_mm);
  expect_compensates(fine.result, model, truth, {}, rng);

  // The IRB 1600's model on the IRB 120's data (its joint limits hold the data; a KUKA's do
  // not, and its rows are refused by line): not trustworthy, says what to check.
  const CalibrationRun wrong =
      run_calibration(load_robot("abb-irb1600-6-12"), tool, clean, request);
  ASSERT_FALSE(wrong.problems.empty());
  EXPECT_NE(wrong.problems[0].find("check the robot (--robot: is it this arm's model?)"),
            std::string::npos)
      << wrong.problems[0];
}

TEST(ShopData, JointsOutsideTheLimitsAreWarnedWithTheirLines) {
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(1306);
  const ParameterVector truth = shop_truth(model, rng, {}, 4e-7);
  const Tool tool = published_tool();
  MeasurementSet data;
  data.kind = MeasurementKind::Points;
  data.file = "lim.csv";
  auto configs = configurations(model, 40, rng);
  configs[7][1] = model.limits[1].upper + deg2rad(5);
  for (size_t k = 0; k < configs.size(); ++k)
    data.points.push_back(
        {std::to_string(k), static_cast<int>(k % 2), configs[k],
         flange_pose(model, tool.payload, truth, configs[k]) * tool.targets[k % 2].position_mm,
         static_cast<int>(k) + 2});
  const IdentificationResult r = calibrate(model, tool, data, {});
  EXPECT_TRUE(has_warning(r, fmt::format("1 row with joints outside the limits of ABB IRB 120 "
                                         "(wrong robot file, or another joint convention?):\n"
                                         "  lim.csv:9: j2 = {:.3f}° outside [-110, 110]°",
                                         rad2deg(configs[7][1]))));
  expect_compensates(r, model, truth, {}, rng);
}

TEST(ShopData, AJointFarOutsideItsLimitsIsRefusedWithItsLine) {
  const RobotModel model = load_robot("abb-irb120");
  auto rng = test::seeded_rng(1307);
  const Tool tool = published_tool();
  MeasurementSet data;
  data.kind = MeasurementKind::Points;
  data.file = "far.csv";
  const auto configs = configurations(model, 12, rng);
  for (size_t k = 0; k < configs.size(); ++k)
    data.points.push_back({std::to_string(k), static_cast<int>(k % 2), configs[k],
                           Eigen::Vector3d(400, 0, 500), static_cast<int>(k) + 2});
  data.points[3].joints[0] = deg2rad(500);  // j1 of an IRB 120 turns ±165°
  EXPECT_REFUSED((void)calibrate(model, tool, data, {}), InputError,
                 "far.csv:5 (j1): 500.000° is more than 20° outside the joint's limits [-165, "
                 "165]° of ABB IRB 120");
}

}  // namespace
}  // namespace robcal
