// A user's program against the installed robcal: load a robot, calibrate it from simulated
// in-memory measurements, compensate a pose, solve the nominal IK. Checks its numbers itself
// (exit 1 on a failed check) and prints the ones run.sh compares between builds with
// different compiler flags.
#include <robcal/compensate/calibrated_chain.hpp>
#include <robcal/compensate/calibrated_ik.hpp>
#include <robcal/identify/identification.hpp>
#include <robcal/io/robot_file.hpp>
#include <robcal/kinematics/inverse_kinematics.hpp>
#include <robcal/kinematics/nominal_chain.hpp>
#include <robcal/sim/simulator.hpp>
#include <robcal/sim/true_robot.hpp>

#include <cmath>
#include <cstdio>
#include <random>

using namespace robcal;

namespace {
int failures = 0;
void check(bool ok, const char* what, double value) {
  std::printf("%-44s %.6g%s\n", what, value, ok ? "" : "   FAILED");
  if (!ok) ++failures;
}
}  // namespace

int main() {
  const RobotModel model = load_robot(ROBOT_LIBRARY "/robots/abb-irb120.yaml");
  const Tool tool = default_simulation_tool();
  const TrueRobot truth = published_irb120_truth(model, tool);
  const VirtualInstrument tracker = standard_instrument(InstrumentKind::LaserTracker, truth);
  std::mt19937_64 rng(7);
  RandomConfigurationOptions random;
  random.box = published_joint_box(model);
  const auto configs = random_configurations(truth, tracker, 60, rng, random);
  const SimulationResult sim = simulate_measurements(truth, tracker, configs, rng);

  IdentifyOptions options;
  options.prediction_configurations = 50;
  const IdentificationResult fit = calibrate(model, tool, sim.measurements, options);
  // Tracker noise σ = 0.022 mm per axis: the residual norm's RMS is about √3·σ ≈ 0.038 mm.
  check(fit.status.converged, "calibration converged", fit.status.iterations);
  check(fit.rms_mm > 0.02 && fit.rms_mm < 0.06, "residual RMS (mm), expected ~0.038", fit.rms_mm);

  // Compensation: the joints that put the TCP, on the calibrated model, where the nominal
  // model would have put it at q0.
  const Compensator comp = make_compensator(fit.robot);
  Vector6d q0;
  q0 << 0.3, 0.4, -0.2, 0.5, 0.6, -0.7;
  const Pose<double> target = comp.world_T_base * nominal_tcp_pose(comp, q0);
  const CalibratedIkResult ik = calibrated_ik(comp, target, arm_config(model, q0), q0);
  const Pose<double> reached = calibrated_tcp_pose(comp.chain, ik.joints);
  check(ik.ok(), "compensation converged", ik.iterations);
  check((reached.p - target.p).norm() < 1e-6, "compensated pose to target, calibrated (mm)",
        (reached.p - target.p).norm());
  // Against the true robot: the calibrated joints land near the target, the nominal ones not.
  const auto true_tcp = [&](const Vector6d& q) {
    return (true_flange_pose(truth, q) * comp.flange_T_tcp).p;
  };
  const double before = (true_tcp(q0) - target.p).norm(),
               after = (true_tcp(ik.joints) - target.p).norm();
  check(after < 0.2 && after < before / 5, "true robot error after compensation (mm)", after);
  std::printf("%-44s %.6g\n", "true robot error without compensation (mm)", before);

  // Nominal IK: every solution reproduces the pose, q0 is among them.
  const auto geometry = analyze_ortho_parallel(model);
  const NominalChain chain = make_nominal_chain(model);
  const Pose<double> flange = nominal_flange_pose(chain, q0);
  const IkResult solutions = nominal_ik(*geometry, flange, q0);
  double worst = 0, nearest = 1e9;
  for (const IkSolution& s : solutions) {
    const Pose<double> back = nominal_flange_pose(chain, s.joints);
    worst = std::max(worst, (back.p - flange.p).norm() + (back.R - flange.R).norm());
    nearest = std::min(nearest, (s.joints - q0).cwiseAbs().maxCoeff());
  }
  check(solutions.count >= 2 && solutions.count <= kMaxIkSolutions, "nominal IK solutions",
        solutions.count);
  check(worst < 1e-9, "worst IK solution's pose error", worst);
  check(nearest < 1e-9, "IK solution nearest q0 (rad)", nearest);

  std::printf("compare: rms %.5f solutions %d joints %.6f %.6f %.6f %.6f %.6f %.6f\n", fit.rms_mm,
              solutions.count, ik.joints[0], ik.joints[1], ik.joints[2], ik.joints[3], ik.joints[4],
              ik.joints[5]);
  return failures == 0 ? 0 : 1;
}
