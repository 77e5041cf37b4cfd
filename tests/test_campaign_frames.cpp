// Frames as the published method sets them up (issue 16 item 3): circle fits of single-joint
// sweeps give the base and the tool target, poses give a tool point, nests give a frame; each
// estimate's reported σ is checked by Monte Carlo on simulated readings (seeded), and the
// nominal model with the circle-fit base is validated against the simulated truth.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <random>

#include "refusal.hpp"
#include "robcal/campaign/cell.hpp"
#include "robcal/campaign/frames.hpp"
#include "robcal/campaign/frames_file.hpp"
#include "robcal/campaign/text_table.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/simulator.hpp"
#include "robcal/validate/base_fit.hpp"
#include "test_external_data.hpp"
#include "test_support.hpp"

namespace robcal::campaign {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;

Vector6d deg(double a, double b, double c, double d, double e, double f) {
  Vector6d q;
  q << a, b, c, d, e, f;
  return q * kDegToRad;
}

/// The readings of `target` while joint `joint` goes from `from` to `to` degrees in `steps`
/// steps, the other joints at `start`; `position` gives the true target position.
template <typename Position>
JointSweep sweep(int joint, const Vector6d& start, double from, double to, int steps,
                 const Position& position, double sigma, std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, sigma > 0 ? sigma : 1.0);
  JointSweep s;
  s.joint = joint;
  for (int k = 0; k <= steps; ++k) {
    Vector6d q = start;
    q[joint - 1] = deg2rad(from + (to - from) * k / steps);
    Eigen::Vector3d p = position(q);
    if (sigma > 0)
      for (int i = 0; i < 3; ++i) p[i] += noise(rng);
    s.joints.push_back(q);
    s.points_mm.push_back(p);
  }
  return s;
}

/// A rigid nominal robot placed at the simulator's base: no link errors, so the circle-fit
/// frames are unbiased and the Monte Carlo spread is the estimator's alone.
struct NominalCell {
  RobotModel model = load_robot("abb-irb120");
  ParameterVector params = model.nominal();
  Eigen::Vector3d target{75, 93.675, 215};
  NominalCell() {
    const auto b = default_base_placement();
    for (int i = 0; i < 6; ++i)
      params[i] = i < 3 ? b[static_cast<size_t>(i)] : deg2rad(b[static_cast<size_t>(i)]);
  }
  [[nodiscard]] Pose<double> flange(const Vector6d& q) const {
    return flange_pose(model, PointMass{}, params, q);
  }
  [[nodiscard]] Eigen::Vector3d position(const Vector6d& q) const { return flange(q) * target; }
};

TEST(CampaignFrames, CircleFitExactOnNoiseFreeArcsAndOrientedByTheAngles) {
  const Eigen::Vector3d centre(100, -50, 300), axis = Eigen::Vector3d(1, 2, 3).normalized();
  Eigen::Vector3d u = axis.cross(Eigen::Vector3d::UnitX()).normalized(), v = axis.cross(u);
  std::vector<Eigen::Vector3d> points;
  std::vector<double> angles;
  for (int k = 0; k < 7; ++k) {
    const double a = deg2rad(-20.0 + 10.0 * k);  // a 60° arc
    points.push_back(centre + 250 * (std::cos(a) * u + std::sin(a) * v));
    angles.push_back(a);
  }
  const CircleFit fit = fit_circle(points, angles);
  EXPECT_LT((fit.centre_mm - centre).norm(), 1e-9);
  EXPECT_LT((fit.axis - axis).norm(), 1e-12);  // counter-clockwise about +axis
  EXPECT_NEAR(fit.radius_mm, 250, 1e-9);
  EXPECT_LT(fit.rms_mm, 1e-9);
  // The same points with the angles running the other way give the opposite axis.
  std::vector<double> reversed = angles;
  for (double& a : reversed) a = -a;
  EXPECT_LT((fit_circle(points, reversed).axis + axis).norm(), 1e-12);
  // Collinear points are refused.
  EXPECT_REFUSED(fit_circle({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}, {0, 1, 2, 3}), InputError,
                 "the points lie on one line: a circle needs an arc that spans a plane");
}

TEST(CampaignFrames, CircleFitAgreesWithTheNeuebotIrb140Recording) {
  // Cross-check on public data (read in place, never copied): neuebot/Kinematic-Calibration's
  // ABB IRB 140 joint-2 sweep, t,x,y,z in metres, whose centre lies on the nominal geometry
  // (a1 = 0.070, d1 = 0.352 m) and whose axis is the base y axis.
  const test::ExternalFile file =
      test::find_external_data("neuebot__Kinematic-Calibration/ABB/j2.csv");
  if (!file.path)
    GTEST_SKIP() << "the read-only reference is not beside the source tree; looked at:"
                 << file.searched;
  const std::string path = file.path->string();
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const TextTable table = read_text_table(text, path);
  std::vector<Eigen::Vector3d> points;
  std::vector<double> angles;
  for (const TextRow& row : table.rows) {
    if (row.fields.size() != 4) continue;
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k)
      p[k] = 1000 * parse_number(row.fields[static_cast<size_t>(k + 1)], '.', {}, "mm");
    points.push_back(p);
    angles.push_back(static_cast<double>(angles.size()));  // recorded in time order
  }
  ASSERT_GT(points.size(), 10u);
  const CircleFit fit = fit_circle(points, angles);
  // An independent estimate: the circle through the first, middle and last points.
  const Eigen::Vector3d a = points.front() - points.back(),
                        b = points[points.size() / 2] - points.back();
  const Eigen::Vector3d circumcentre =
      points.back() + (a.squaredNorm() * b - b.squaredNorm() * a).cross(a.cross(b)) /
                          (2 * a.cross(b).squaredNorm());
  std::printf(
      "neuebot IRB 140 j2: %zu points, centre %.4f %.4f %.4f mm (3-point circle %.4f %.4f "
      "%.4f), radius %.4f, rms %.5f mm\n",
      points.size(), fit.centre_mm.x(), fit.centre_mm.y(), fit.centre_mm.z(), circumcentre.x(),
      circumcentre.y(), circumcentre.z(), fit.radius_mm, fit.rms_mm);
  EXPECT_LT((fit.centre_mm - circumcentre).norm(), 0.01);
  EXPECT_LT(fit.rms_mm, 0.001);  // the file's µm rounding
  // On the nominal joint-2 axis (x = a1, z = d1) within what the recording gives (z 352.12).
  EXPECT_NEAR(fit.centre_mm.x(), 70, 0.01);
  EXPECT_NEAR(fit.centre_mm.z(), 352, 0.2);
  EXPECT_GT(std::abs(fit.axis.y()), 1 - 1e-9);
}

/// Monte Carlo: the spread of `estimate − truth` over runs against the mean reported σ, per
/// component; and every run's error within 4 of its own σ.
template <int N>
void expect_sigma_honest(const std::vector<Eigen::Matrix<double, N, 1>>& errors,
                         const std::vector<Eigen::Matrix<double, N, 1>>& sigmas, const char* what) {
  const double runs = static_cast<double>(errors.size());
  Eigen::Matrix<double, N, 1> mean = Eigen::Matrix<double, N, 1>::Zero(),
                              sq = Eigen::Matrix<double, N, 1>::Zero(),
                              reported = Eigen::Matrix<double, N, 1>::Zero();
  int outside = 0;
  for (size_t r = 0; r < errors.size(); ++r) {
    mean += errors[r] / runs;
    sq += errors[r].cwiseProduct(errors[r]) / runs;
    reported += sigmas[r] / runs;
    for (int i = 0; i < N; ++i) outside += std::abs(errors[r][i]) > 4 * sigmas[r][i];
  }
  for (int i = 0; i < N; ++i) {
    const double observed = std::sqrt(sq[i]);
    SCOPED_TRACE(
        fmt::format("{} component {}: observed RMS error {:.3g}, reported σ {:.3g}, bias {:.3g}",
                    what, i, observed, reported[i], mean[i]));
    EXPECT_GT(observed / reported[i], 0.8);
    EXPECT_LT(observed / reported[i], 1.25);
    EXPECT_LT(std::abs(mean[i]), 4 * reported[i] / std::sqrt(runs));
  }
  EXPECT_EQ(outside, 0) << what;
}

TEST(CampaignFrames, BaseFromJointOneAndTwoSweepsIsRecoveredWithinItsSigma) {
  const NominalCell cell;
  const auto position = [&](const Vector6d& q) { return cell.position(q); };
  Vector6 truth;
  truth << cell.params.head<6>();
  std::vector<Vector6> errors, sigmas;
  for (uint64_t seed = 1; seed <= 120; ++seed) {
    std::mt19937_64 rng(seed);
    const JointSweep s1 = sweep(1, deg(0, 20, -10, 0, 45, 0), -60, 60, 24, position, 0.022, rng);
    const JointSweep s2 = sweep(2, deg(30, 0, -10, 0, 45, 0), -20, 70, 18, position, 0.022, rng);
    const FrameEstimate base = base_from_sweeps(cell.model, s1, s2);
    errors.push_back(base.values - truth);
    sigmas.push_back(base.sigma);
    if (seed == 1)
      std::printf(
          "base from sweeps (seed 1): σ x %.4f y %.4f z %.4f mm, α %.5f β %.5f γ %.5f deg; "
          "σ noise %.4f mm\n",
          base.sigma[0], base.sigma[1], base.sigma[2], rad2deg(base.sigma[3]),
          rad2deg(base.sigma[4]), rad2deg(base.sigma[5]), base.sigma_mm);
  }
  expect_sigma_honest<6>(errors, sigmas, "base");
}

TEST(CampaignFrames, ToolTargetFromJointFiveAndSixSweepsIsRecoveredWithinItsSigma) {
  const NominalCell cell;
  const auto position = [&](const Vector6d& q) { return cell.position(q); };
  std::vector<Eigen::Vector3d> errors, sigmas;
  for (uint64_t seed = 1; seed <= 120; ++seed) {
    std::mt19937_64 rng(seed);
    const JointSweep s5 = sweep(5, deg(10, 20, -10, 30, 0, 0), -60, 60, 24, position, 0.022, rng);
    const JointSweep s6 =
        sweep(6, deg(10, 20, -10, 30, 40, 0), -150, 150, 30, position, 0.022, rng);
    const PointEstimate t = tool_from_sweeps(cell.model, s5, s6);
    errors.push_back(t.position_mm - cell.target);
    sigmas.push_back(t.sigma);
  }
  expect_sigma_honest<3>(errors, sigmas, "tool target");
}

TEST(CampaignFrames, ToolPointFromPivotPosesIsRecoveredWithinItsSigma) {
  const Eigen::Vector3d tcp(12, -30, 180), spot(500, 200, 100);
  std::vector<Eigen::Vector3d> errors, sigmas;
  double estimated_sigma = 0;
  for (uint64_t seed = 1; seed <= 300; ++seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.05);
    std::uniform_real_distribution<double> angle(-0.6, 0.6);
    std::vector<Pose<double>> poses;
    for (int k = 0; k < 6; ++k) {
      Pose<double> pose;
      pose.R = (Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(3 * angle(rng), Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
      pose.p = spot - pose.R * tcp + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      poses.push_back(pose);
    }
    // The 4σ check uses the known σ (a residual σ from 12 degrees of freedom has Student
    // tails); the residual estimate is checked on average.
    const PointEstimate t = tool_point_from_poses(poses, {}, 0.05);
    errors.push_back(t.position_mm - tcp);
    sigmas.push_back(t.sigma);
    estimated_sigma += tool_point_from_poses(poses).sigma_mm / 300;
  }
  expect_sigma_honest<3>(errors, sigmas, "pivot tool point");
  EXPECT_NEAR(estimated_sigma, 0.05, 0.004);
  EXPECT_REFUSED(tool_point_from_poses(std::vector<Pose<double>>(4)), InputError,
                 "the flange orientations are too alike to fix the tool point");  // all alike
}

TEST(CampaignFrames, FrameFromFourTableNestsIsRecoveredWithinItsSigma) {
  const std::vector<Eigen::Vector3d> nominal = {{0, 0, 0}, {400, 0, 0}, {0, 300, 0}, {400, 300, 5}};
  Pose<double> truth;
  truth.R = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
             Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitX()))
                .toRotationMatrix();
  truth.p = {-900, 1200, -100};
  Vector6 truth_values;
  truth_values << truth.p, xyz_angles(truth.R);
  std::vector<Vector6> errors, sigmas;
  for (uint64_t seed = 1; seed <= 300; ++seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.022);
    std::vector<Eigen::Vector3d> measured;
    for (const auto& n : nominal)
      measured.push_back(truth * n + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    const FrameEstimate frame = frame_from_nests(measured, nominal, 0.022);
    errors.push_back(frame.values - truth_values);
    sigmas.push_back(frame.sigma);
  }
  expect_sigma_honest<6>(errors, sigmas, "nest frame");
  EXPECT_REFUSED(
      frame_from_nests({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}),
      InputError, "the nests lie on one line: they cannot fix a frame");
}

TEST(CampaignFrames, NominalModelWithTheCircleFitBaseValidatesLikeTheSimulatedTruthSays) {
  // The published IRB 120 (link errors, compliance) measured by a tracker (σ 0.022 mm): the
  // base from sweeps of target 1, then the nominal model with that base against 1000 random
  // configurations of the published box. The best any nominal model can do is its rigid
  // best-fit base (the demo's "nominal" row); the circle-fit base (the published protocol's
  // "before") may only be worse, and by a bounded factor.
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  const TrueRobot truth = published_irb120_truth(model, tool);
  const auto position = [&](const Vector6d& q) {
    return true_flange_pose(truth, q) * tool.targets[0].position_mm;
  };
  std::mt19937_64 rng(7);
  const JointSweep s1 = sweep(1, deg(0, 30, 0, 0, 45, 0), -60, 60, 24, position, 0.022, rng);
  const JointSweep s2 = sweep(2, deg(0, 0, 0, 0, 45, 0), 0, 70, 14, position, 0.022, rng);
  const FrameEstimate base = base_from_sweeps(model, s1, s2);

  CalibratedRobot circle = CalibratedRobot::nominal(model, tool);
  for (int i = 0; i < 6; ++i) circle.params[i] = base.values[i];
  circle.base_fitted = true;

  const VirtualInstrument instrument = standard_instrument(InstrumentKind::LaserTracker, truth);
  RandomConfigurationOptions options;
  options.box = published_joint_box(model);
  const auto configs = random_configurations(truth, instrument, 1000, rng, options);
  VirtualInstrument exact = instrument;
  exact.tracker.sigma_mm.setZero();
  const MeasurementSet validation = simulate_measurements(truth, exact, configs, rng).measurements;
  const CalibratedRobot rigid = fit_base(CalibratedRobot::nominal(model, tool), validation);
  const auto mean_error = [&](const CalibratedRobot& robot) {
    double sum = 0;
    for (const PointMeasurement& m : validation.points)
      sum += (flange_pose(model, tool.payload, robot.params, m.joints) *
                  tool.targets[static_cast<size_t>(m.target)].position_mm -
              m.position_mm)
                 .norm();
    return sum / static_cast<double>(validation.points.size());
  };
  const double with_circle_base = mean_error(circle), with_rigid_base = mean_error(rigid);
  std::printf(
      "nominal IRB 120 vs the published truth, 1000 configurations: circle-fit base "
      "%.3f mm mean, rigid best-fit base %.3f mm mean (published real robot: 3.168)\n",
      with_circle_base, with_rigid_base);
  // Seeded: the figures this test computes (the circle-fit base leaves the link errors'
  // placement bias that the rigid fit absorbs; same order as the published 3.2 mm).
  EXPECT_NEAR(with_circle_base, 2.573, 0.01);
  EXPECT_NEAR(with_rigid_base, 0.762, 0.01);
  EXPECT_GE(with_circle_base, with_rigid_base);
  EXPECT_LT(with_circle_base, 4 * with_rigid_base);
}

TEST(CampaignFramesFile, SweepsAreCheckedRowByRowAndTheBaseReplacesOnlyItsBlock) {
  MeasurementSet set;
  set.file = "sweep.csv";
  for (int k = 0; k < 5; ++k) {
    PointMeasurement m;
    m.joints = deg(10.0 * k, 20, 0, 0, 0, 0);
    m.position_mm = Eigen::Vector3d(k, 0, 0);
    m.line = k + 2;
    set.points.push_back(m);
  }
  set.points[3].joints[2] = deg2rad(1);  // joint 3 moves on line 5
  try {
    sweep_from_measurements(set, 1, load_robot("abb-irb120"));
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sweep.csv:5 (j3): joint 3 moved"), std::string::npos)
        << e.what();
  }
  FrameEstimate base;
  base.values << -800, 1500, -95, deg2rad(0.25), deg2rad(-0.4), deg2rad(-57);
  base.sigma << 0.1, 0.2, 0.3, deg2rad(0.01), deg2rad(0.02), deg2rad(0.03);
  const std::string cell =
      "# my cell\nformat: robcal-cell\nrobot_base:\n  position_mm: [0, 0, 0]\n"
      "  rotation_xyz_deg: [0, 0, 0]\n# the tracker\ninstrument: {kind: laser-tracker, "
      "position_mm: [0, 0, 0]}\nfloor_z_mm: -100\n";
  const std::string out = cell_with_base(cell, "cell.yaml", base, "measured");
  EXPECT_EQ(out.substr(0, 30), "# my cell\nformat: robcal-cell\n");
  EXPECT_NE(out.find("# the tracker\ninstrument: {kind: laser-tracker"), std::string::npos) << out;
  const Cell parsed = parse_cell(out, "out.yaml");
  EXPECT_TRUE(parsed.base_measured);
  EXPECT_DOUBLE_EQ(parsed.robot_base[0], -800);
  EXPECT_NEAR(parsed.robot_base[5], deg2rad(-57), 1e-15);
  EXPECT_REFUSED(cell_with_base("format: robcal-cell\n", "cell.yaml", base, ""), InputError,
                 "cell.yaml (robot_base): no top-level 'robot_base:' line to replace");
}

TEST(CampaignFrames, ToolPointFromMeasuredConfigurationsWithTheCellsBase) {
  // The nominal robot at the simulator's base, target (75, 93.675, 215) read at 10 random
  // configurations: exact without noise; with 0.022 mm noise within 4 of the reported σ.
  const NominalCell cell;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> angle(-1.2, 1.2);
  std::normal_distribution<double> noise(0.0, 0.022);
  MeasurementSet exact, noisy;
  exact.file = noisy.file = "points.csv";
  for (int k = 0; k < 10; ++k) {
    Vector6d q;
    for (int j = 0; j < kJointCount; ++j) q[j] = angle(rng);
    PointMeasurement m;
    m.joints = q;
    m.position_mm = cell.position(q);
    exact.points.push_back(m);
    m.position_mm += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    noisy.points.push_back(m);
  }
  EXPECT_LT((tool_point_from_measurements(cell.model, cell.params, exact).position_mm - cell.target)
                .norm(),
            1e-9);
  const PointEstimate t = tool_point_from_measurements(cell.model, cell.params, noisy);
  for (int k = 0; k < 3; ++k)
    EXPECT_LT(std::abs(t.position_mm[k] - cell.target[k]), 4 * t.sigma[k]) << k;
  EXPECT_GT(t.sigma.minCoeff(), 0.001);
  EXPECT_LT(t.sigma.maxCoeff(), 0.05);
}

TEST(CampaignFrames, CoupledJointsOfAFanucAreSweptInModelAngles) {
  // LR Mate 200iC: the controller's J3 is measured from the horizontal (model q3 = −J2 − J3).
  // A joint-2 sweep with J3 held still turns model joint 3 too, and is refused; with J3
  // following (J3 = J3₀ − ΔJ2) it is a true joint-2 sweep and gives the base exactly.
  const RobotModel model = load_robot("fanuc-lrmate200ic");
  ParameterVector params = model.nominal();
  params.head<6>() << 300, -200, 10, deg2rad(0.3), deg2rad(-0.2), deg2rad(25);
  const Eigen::Vector3d target(40, 30, 150);
  const auto position = [&](const Vector6d& q) {
    return flange_pose(model, PointMass{}, params, q) * target;
  };
  std::mt19937_64 rng(1);
  const JointSweep s1 = sweep(1, deg(0, 10, -10, 0, 30, 0), -60, 60, 12, position, 0.0, rng);
  const JointSweep held = sweep(2, deg(20, 0, -10, 0, 30, 0), -20, 40, 12, position, 0.0, rng);
  try {
    base_from_sweeps(model, s1, held);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model joint 3 moved"), std::string::npos) << e.what();
  }
  JointSweep coupled = held;
  for (Vector6d& q : coupled.joints) q[2] = deg2rad(-10) - q[1];
  for (size_t k = 0; k < coupled.joints.size(); ++k)
    coupled.points_mm[k] = position(coupled.joints[k]);
  const FrameEstimate base = base_from_sweeps(model, s1, coupled, 0.01);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(base.values[i], params[i], 1e-7) << i;
}

}  // namespace
}  // namespace robcal::campaign
