#pragma once
// Shared by the tests of the opt-in error groups (issue 19, docs/method/03-error-model.md §5–6):
// simulated campaigns on the published IRB 120, a level-full fit with groups, the validation
// error and the cross-validated cost of a group.

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "refusal.hpp"
#include "robcal/identify/cross_validation.hpp"
#include "robcal/identify/identification.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/simulator.hpp"
#include "robcal/validate/validation.hpp"
#include "test_compensate_support.hpp"

namespace robcal::test {

/// The simulation tool with two further payloads: none (0 kg) and a 6 kg gripper.
inline Tool tool_with_payloads() {
  Tool tool = default_simulation_tool();
  tool.payloads = {{"empty", {0.0, Eigen::Vector3d::Zero()}},
                   {"gripper", {6.0, Eigen::Vector3d(60, 20, 150)}}};
  return tool;
}

/// The calibrated chain of `robot` against the templated forward model at 30 random joint sets:
/// the TCP pose, and the position rows of its joint Jacobian against autodiff.
inline void expect_chain_matches_forward_model(const CalibratedRobot& robot, std::mt19937_64& rng,
                                               const std::string& name) {
  const Compensator comp = make_compensator(robot);
  using Jet = ceres::Jet<double, 6>;
  std::array<Jet, kParameterCount> params;
  for (int i = 0; i < kParameterCount; ++i) params[i] = Jet(robot.params[i]);
  for (int k = 0; k < 30; ++k) {
    const Vector6d j = random_joints(robot.model, rng);
    Matrix6d J;
    const Pose<double> got = calibrated_tcp_pose(comp.chain, j, &J);
    const Pose<double> want =
        flange_pose(robot.model, robot.tool.payload, robot.params, j) * comp.flange_T_tcp;
    ASSERT_LT((got.p - want.p).norm(), 1e-9) << name;
    ASSERT_LT((got.R - want.R).norm(), 1e-12) << name;
    std::array<Jet, kJointCount> jj;
    for (int i = 0; i < kJointCount; ++i) jj[i] = Jet(j[i], i);
    const Pose<Jet> flange =
        flange_pose<Jet>(robot.model, robot.tool.payload, params.data(), jj.data());
    const Vector3<Jet> tcp = flange * comp.flange_T_tcp.p.cast<Jet>();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < kJointCount; ++c)
        ASSERT_NEAR(J(r, c), tcp[r].v[c], 1e-9 * (1 + J.cwiseAbs().maxCoeff())) << name;
  }
}

/// The calibrated inverse of a robot with an error group round-trips 20 poses per
/// configuration branch: none fails, each within 1e-6 mm, the drawn joints recovered to 1e-7 rad.
inline void expect_calibrated_ik_round_trips(const CalibratedRobot& robot, std::mt19937_64& rng) {
  const Compensator comp = make_compensator(robot);
  const RoundTripStats st = round_trip(robot, comp, 20, 400'000, rng);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(st.failures[i], 0);
  EXPECT_TRUE(st.first_failure.empty()) << st.first_failure;
  EXPECT_LT(st.worst_mm, 1e-6);
  EXPECT_LT(st.worst_recovery_rad, 1e-7);
}

/// An optional number column of the measurement file (`temperature`, `time_s`), `member` of a
/// row: read without a "not used" warning, an empty field is a row without a value, written only
/// when a row has one, round trip; each of `bad` refused with file, line, column and the column.
inline void expect_optional_measurement_column(const std::string& column,
                                               std::optional<double> PointMeasurement::*member,
                                               const std::string& value_text, double value,
                                               const std::vector<std::string>& bad) {
  const Tool tool = default_simulation_tool();
  const std::string header = "config,target,j1,j2,j3,j4,j5,j6,x,y,z," + column + "\n";
  const std::string text = header + "c1,1,0,10,20,30,40,50,100,200,300," + value_text +
                           "\nc2,1,5,10,20,30,40,50,100,200,301,\n";
  const MeasurementFile file = parse_measurements_csv(text, "m.csv", tool);
  EXPECT_TRUE(file.warnings.empty());
  const MeasurementSet& set = file.measurements;
  ASSERT_EQ(set.points.size(), 2u);
  EXPECT_EQ(set.points[0].*member, value);
  EXPECT_FALSE((set.points[1].*member).has_value());
  const std::string written = write_measurements_csv(set, tool);
  EXPECT_NE(written.find("," + column + "\n"), std::string::npos) << written;
  const MeasurementSet back = parse_measurements_csv(written, "w.csv", tool).measurements;
  EXPECT_EQ(back.points[0].*member, value);
  EXPECT_FALSE((back.points[1].*member).has_value());
  MeasurementSet none = set;
  (none.points[0].*member).reset();
  EXPECT_EQ(write_measurements_csv(none, tool).find(column), std::string::npos);
  for (const std::string& v : bad)
    EXPECT_REFUSED(parse_measurements_csv(header + "c1,1,0,10,20,30,40,50,100,200,300," + v + "\n",
                                          "m.csv", tool),
                   InputError, "m.csv:2:12 (" + column + "): ");
}

struct GroupCampaign {
  MeasurementSet calibration, validation;
};

/// 100 calibration and 60 validation positions drawn in the joint box `box` on `truth`, laser
/// tracker with σ = `noise_mm`, measured with `sim` (the validation's approach sides drawn from
/// approach_seed + 1).
inline GroupCampaign simulate_campaign(const TrueRobot& truth, double noise_mm, uint64_t seed,
                                       const std::array<JointLimit, kJointCount>& box,
                                       SimulationOptions sim = {}) {
  std::mt19937_64 rng(seed);
  const VirtualInstrument tracker =
      standard_instrument(InstrumentKind::LaserTracker, truth, noise_mm);
  RandomConfigurationOptions options;
  options.box = box;
  GroupCampaign c;
  c.calibration =
      simulate_measurements(truth, tracker,
                            random_configurations(truth, tracker, 100, rng, options), rng, sim)
          .measurements;
  options.name_prefix = "V";
  ++sim.approach_seed;
  c.validation =
      simulate_measurements(truth, tracker, random_configurations(truth, tracker, 60, rng, options),
                            rng, sim)
          .measurements;
  return c;
}

/// Level full on `model` (default the IRB 120) with the default simulation tool, the groups
/// `identify` enabled.
inline IdentificationResult fit_full(const MeasurementSet& data,
                                     const std::vector<std::string>& identify,
                                     const RobotModel& model = load_robot("abb-irb120")) {
  IdentifyOptions options;
  options.level = CalibrationLevel::Full;
  options.identify = identify;
  return calibrate(model, default_simulation_tool(), data, options);
}

inline double validation_mean_mm(const IdentificationResult& r, const MeasurementSet& validation) {
  return validate_model(r.robot, validation, 1).positions.position_mm.mean;
}

/// Validation mean errors (mm) of level full: on effect-free data; on data with the effect,
/// without and with the groups `identify`; and that last fit.
struct GroupEffect {
  double free_of_effect = 0, without_group = 0, with_group = 0;
  IdentificationResult with;
};
inline GroupEffect group_effect(const GroupCampaign& clean, const GroupCampaign& effect,
                                const std::vector<std::string>& identify,
                                const RobotModel& model = load_robot("abb-irb120")) {
  GroupEffect g;
  g.free_of_effect = validation_mean_mm(fit_full(clean.calibration, {}, model), clean.validation);
  g.without_group = validation_mean_mm(fit_full(effect.calibration, {}, model), effect.validation);
  g.with = fit_full(effect.calibration, identify, model);
  g.with_group = validation_mean_mm(g.with, effect.validation);
  std::printf(
      "validation mean: effect-free %.4f mm, effect %.4f mm without the group, %.4f mm "
      "with it\n",
      g.free_of_effect, g.without_group, g.with_group);
  return g;
}

/// Normalised errors z = (estimate − truth)/σ (σ as reported) of parameters recovered over
/// Monte Carlo fits: each must be identified and within 3σ; rms() near 1 says the σ are honest.
struct NormalisedErrors {
  double sum_sq = 0;
  int count = 0;
  /// Adds parameter `i` of `r` against its true value; returns its σ.
  double add(const IdentificationResult& r, int i, double truth, uint64_t seed) {
    EXPECT_EQ(r.robot.status[static_cast<size_t>(i)], ParameterStatus::Identified);
    const double sigma = std::sqrt(r.robot.covariance(i, i));
    const double z = (r.robot.params[i] - truth) / sigma;
    EXPECT_LT(std::abs(z), 3.0) << parameter_table()[i].name << " seed " << seed;
    sum_sq += z * z;
    ++count;
    return sigma;
  }
  [[nodiscard]] double rms() const { return std::sqrt(sum_sq / count); }
};

/// The dead bands of `truth` recovered by `fit` (`*.backlash` identified): each within 3σ and
/// determined (σ under a quarter of the band), printed with the normalised errors' RMS.
inline void expect_dead_bands_recovered(const IdentificationResult& fit, const TrueRobot& truth,
                                        uint64_t seed) {
  NormalisedErrors z;
  for (int joint = 1; joint <= kJointCount; ++joint) {
    const double truth_rad = deg2rad(truth.effects.backlash_deg[static_cast<size_t>(joint - 1)]);
    const double sigma = z.add(fit, backlash_param(joint), truth_rad, seed);
    std::printf("joint%d.backlash %.5f ± %.5f deg (truth %.3f)\n", joint,
                rad2deg(fit.robot.params[backlash_param(joint)]), rad2deg(sigma),
                rad2deg(truth_rad));
    EXPECT_LT(sigma, 0.25 * truth_rad);  // determined, not merely bounded
  }
  std::printf("normalised errors: rms %.2f over %d\n", z.rms(), z.count);
}

/// Cross-validated mean error (5 folds, seed 7) on `model` without and with the groups
/// `identify`.
inline std::pair<double, double> cross_validated_cost(
    const MeasurementSet& data, const std::vector<std::string>& identify,
    const RobotModel& model = load_robot("abb-irb120")) {
  IdentifyOptions plain;
  IdentifyOptions with = plain;
  with.identify = identify;
  const double a = cross_validate(model, default_simulation_tool(), data, plain, 5, 7).mean_mm;
  const double b = cross_validate(model, default_simulation_tool(), data, with, 5, 7).mean_mm;
  std::printf("cross-validated mean: %.4f mm without, %.4f mm with the group\n", a, b);
  return {a, b};
}

}  // namespace robcal::test
