// The analytic identification Jacobian (kinematic regressor) against Ceres automatic
// differentiation through the templated FK and against central finite differences, every
// column (periodic joint and motor errors included), with and without compliance, on the IRB 120
// and on the Fanuc (coupled joint map).

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "../src/kinematics/angle_shift.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/parameter_jacobian.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

Vector6d random_joints(const RobotModel& model, std::mt19937_64& rng) {
  Vector6d q;
  for (int i = 0; i < kJointCount; ++i) {
    std::uniform_real_distribution<double> u(model.limits[i].lower, model.limits[i].upper);
    q[i] = u(rng);
  }
  return q;
}

/// Parameters with every error of the model perturbed: base, links, compliance, scales, the
/// periodic joint errors and the motors', the direction of gravity (opt-in groups,
/// docs/method/03-error-model.md §5, §9, §11).
ParameterVector perturbed(const RobotModel& model, std::mt19937_64& rng, bool compliance) {
  ParameterVector x = model.nominal();
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < kComplianceOffset; ++i) {
    const bool angle = parameter_table()[i].kind == ParamKind::Angle;
    x[i] += angle ? deg2rad(2.0 * n(rng)) : 20.0 * n(rng);
  }
  for (int j = 1; j <= 6; ++j) x[compliance_param(j)] = compliance ? 5e-7 * (1 + n(rng)) : 0.0;
  for (int j = 1; j <= 6; ++j) x[scale_param(j)] = 1.0 + 0.01 * n(rng);
  for (int i = kPeriodicOffset; i < kMountingOffset; ++i) x[i] = deg2rad(0.05 * n(rng));
  for (int i = kMotorPeriodicOffset; i < kWarmupOffset; ++i) x[i] = deg2rad(0.005 * n(rng));
  for (const int i : {kGravityTiltA, kGravityTiltB}) x[i] = deg2rad(1.0 * n(rng));  // §11
  return x;
}

/// Finite-difference steps per parameter: 1e-4 mm, 1e-6 rad, 1e-9 rad/N·mm, 1e-6. The compliance
/// step deflects by 1e-9·τ: ≈ 1e-6 rad on joint 6 (τ ≈ 1e3 N·mm), where a smaller step leaves
/// the difference to rounding, and ≈ 4e-5 rad on joint 2, still far from curvature.
ParameterVector difference_steps() {
  ParameterVector step;
  for (int i = 0; i < kParameterCount; ++i) {
    const ParamKind kind = parameter_table()[i].kind;
    step[i] = kind == ParamKind::Length ? 1e-4 : kind == ParamKind::Compliance ? 1e-9 : 1e-6;
  }
  return step;
}

void expect_columns_match(const PositionJacobian& analytic, const Eigen::MatrixXd& reference,
                          double tolerance, const std::string& what) {
  for (int i = 0; i < kParameterCount; ++i) {
    const double scale = std::max(1.0, reference.col(i).norm());
    EXPECT_LT((analytic.col(i) - reference.col(i)).norm(), tolerance * scale)
        << what << ": column " << parameter_table()[i].name << "\nanalytic "
        << analytic.col(i).transpose() << "\nreference " << reference.col(i).transpose();
  }
}

/// `gravity_base`: gravity given in the robot's base frame (a wall or ceiling mounting,
/// docs/method/03-error-model.md §7) instead of the world's default.
void check_robot(const std::string& robot, uint64_t seed,
                 const Eigen::Vector3d* gravity_base = nullptr) {
  SCOPED_TRACE("robot " + robot + ", seed " + std::to_string(seed));
  RobotModel model = load_robot(robot);
  model.gear_ratio = {121, 121, 81, 50, 51.5, 101};  // motor-angle periodic errors on every joint
  if (gravity_base) {
    model.gravity_m_s2 = *gravity_base;
    model.gravity_in_base = true;
  }
  const PointMass payload{2.6, Eigen::Vector3d(50, 25, 100)};
  auto rng = test::seeded_rng(seed);
  for (int trial = 0; trial < 20; ++trial) {
    const bool compliance = trial % 4 != 0;
    const ParameterVector x =
        trial % 5 == 0 && !compliance ? model.nominal() : perturbed(model, rng, compliance);
    const Vector6d q = random_joints(model, rng);
    const Eigen::Vector3d target(40, -30, 120);
    Eigen::Vector3d p_analytic, p_autodiff;
    PositionJacobian J_analytic, J_autodiff;
    target_position_jacobian(model, payload, x, q, target, &p_analytic, &J_analytic);
    target_position_jacobian_autodiff(model, payload, x, q, target, &p_autodiff, &J_autodiff);
    EXPECT_LT((p_analytic - p_autodiff).norm(), 1e-9);
    expect_columns_match(J_analytic, J_autodiff, 1e-9, "autodiff");

    // Differences in steps fitted to each parameter's size: x = x0 + step ⊙ z.
    const ParameterVector step = difference_steps();
    const auto f = [&](const Eigen::VectorXd& z) -> Eigen::VectorXd {
      return flange_pose(model, payload, ParameterVector(x + step.cwiseProduct(z)), q) * target;
    };
    const Eigen::MatrixXd J_fd =
        test::numerical_jacobian(f, Eigen::VectorXd::Zero(kParameterCount), 1.0) *
        step.cwiseInverse().asDiagonal();
    expect_columns_match(J_analytic, J_fd, 1e-6, "finite differences");
  }
}

TEST(ParameterJacobian, AnalyticMatchesAutodiffAndFiniteDifferencesIrb120) {
  check_robot("abb-irb120", 11);
}

TEST(ParameterJacobian, AnalyticMatchesAutodiffAndFiniteDifferencesFanucCoupledJoints) {
  check_robot("fanuc-lrmate200ic", 12);
}

TEST(ParameterJacobian, WallAndCeilingMountingWithJoint1Compliance) {
  const Eigen::Vector3d wall(0, -9.81, 0), inclined(3.1, 2.0, -9.1);
  check_robot("abb-irb120", 13, &wall);
  check_robot("fanuc-lrmate200ic", 14, &inclined);
}

TEST(ParameterJacobian, ComplianceColumnAtZeroComplianceIsTheTorqueTimesTheJointColumn) {
  // At c = 0 the compliance column is τ_i · (joint i column): compare with the autodiff one
  // (which must not vanish although the compliance is zero) and with the FK's own torques.
  const RobotModel model = load_robot("abb-irb120");
  const PointMass payload{2.6, Eigen::Vector3d(-23, 0, 100)};
  const ParameterVector x = model.nominal();
  const Vector6d q = (Vector6d() << 0.3, 0.5, -0.4, 0.7, 0.9, -1.1).finished();
  PositionJacobian J, J_auto;
  Eigen::Vector3d p;
  target_position_jacobian(model, payload, x, q, Eigen::Vector3d(0, 0, 125), &p, &J);
  target_position_jacobian_autodiff(model, payload, x, q, Eigen::Vector3d(0, 0, 125), nullptr,
                                    &J_auto);
  std::array<double, kJointCount> theta;
  const auto qm = model_joint_angles<double>(model, q.data());
  for (int i = 0; i < kJointCount; ++i)
    theta[i] = qm[i] + (i == 0 ? model.mdh[0].theta_offset : x[link_param(i + 1, 2)]);
  const auto tau = gravity_torques<double>(model, payload, x.data(), theta);
  for (int joint = 2; joint <= 6; ++joint) {  // joint 1: τ_1 = 0 on the floor
    const Eigen::Vector3d expected = J.col(link_param(joint, 2)) * tau[joint - 1];
    EXPECT_LT((J.col(compliance_param(joint)) - expected).norm(), 1e-9 * expected.norm() + 1e-9)
        << "joint " << joint;
    EXPECT_LT((J_auto.col(compliance_param(joint)) - expected).norm(),
              1e-9 * expected.norm() + 1e-9)
        << "joint " << joint;
  }
  EXPECT_GT(J.col(compliance_param(2)).norm(), 1e3);  // ≈ 40 N·m on joint 2, lever ≈ 0.5 m
}

TEST(ParameterJacobian, TwistJacobianRotatesTheFlangeLikeFiniteDifferences) {
  const RobotModel model = load_robot("abb-irb120");
  const PointMass payload{2.6, Eigen::Vector3d(-23, 0, 100)};
  auto rng = test::seeded_rng(7);
  const ParameterVector x = perturbed(model, rng, true);
  const Vector6d q = random_joints(model, rng);
  Pose<double> F;
  TwistJacobian J;
  flange_twist_jacobian(model, payload, x, q, &F, &J);
  const ParameterVector step = difference_steps();
  for (int i = 0; i < kParameterCount; ++i) {
    const double h = step[i];
    ParameterVector xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    const Eigen::Matrix3d dR =
        (flange_pose(model, payload, xp, q).R - flange_pose(model, payload, xm, q).R) / (2 * h);
    const Eigen::Matrix3d W = dR * F.R.transpose();  // [ω]×
    const Eigen::Vector3d omega(W(2, 1), W(0, 2), W(1, 0));
    EXPECT_LT((omega - J.col(i).tail<3>()).norm(), 1e-5 * std::max(1.0, omega.norm()))
        << parameter_table()[i].name;
  }
}

TEST(ParameterJacobian, ShiftedSineAndCosineAreExactOnBothSidesOfTheSeriesLimit) {
  // Against long double sin and cos of θ + δ: the series (|δ| < kSeriesShiftLimitRad) and the
  // direct branch within a few ulp. Leaving out the δ⁶/720 term would err by 9e-14 at δ = 0.02.
  for (const double theta : {0.3, 2.5, -1.7, 3.1}) {
    for (const double delta :
         {1e-7, 1e-3, 1e-2, 1.9999e-2, 2.0001e-2, 0.05, 0.3, 3.0, -1e-3, -1.9999e-2, -0.5}) {
      double s = 0, c = 0;
      sin_cos_shifted(std::sin(theta), std::cos(theta), delta, &s, &c);
      const long double angle = static_cast<long double>(theta) + delta;
      EXPECT_NEAR(s, static_cast<double>(std::sin(angle)), 5e-16) << theta << " + " << delta;
      EXPECT_NEAR(c, static_cast<double>(std::cos(angle)), 5e-16) << theta << " + " << delta;
    }
  }
}

TEST(ParameterJacobian, ConfigurationPreparedAtOtherParametersGivesTheSameChain) {
  // The identification prepares each configuration at its start parameters and evaluates at
  // the iterates: link angles moved a little (series) and far (joint offsets by 5°, a scale by
  // 2 %: the direct branch) must give the chain and the regressor of a fresh preparation.
  const RobotModel model = load_robot("abb-irb120");
  const PointMass payload{2.6, Eigen::Vector3d(-23, 0, 100)};
  auto rng = test::seeded_rng(21);
  const ParameterVector x0 = perturbed(model, rng, true);
  ParameterVector x1 = x0;
  x1[5] += deg2rad(0.2);                   // base γ: θ_1 by 0.2° (series)
  x1[link_param(2, 2)] += deg2rad(5.0);    // θ_2 by 5° (direct)
  x1[link_param(3, 2)] -= deg2rad(0.3);    // series
  x1[link_param(5, 2)] += deg2rad(-40.0);  // a large move
  x1[scale_param(4)] += 2e-3;              // 2e-3·q_4: series
  x1[scale_param(6)] += 2e-2;              // 2e-2·q_6: direct for |q_6| > 0.5 rad
  x1[compliance_param(3)] *= 1.5;
  const ParameterTrig trig = parameter_trig(x1);
  for (int trial = 0; trial < 10; ++trial) {
    const Vector6d q = random_joints(model, rng);
    const FlangeRegressor moved(model, payload, x1, trig, prepare_configuration(model, x0, q));
    const FlangeRegressor fresh(model, payload, x1, trig, prepare_configuration(model, x1, q));
    const Pose<double> reference = flange_pose(model, payload, x1, q);  // templated FK
    EXPECT_LT((moved.flange().p - reference.p).norm(), 1e-9);
    EXPECT_LT((moved.flange().R - reference.R).norm(), 1e-12);
    EXPECT_LT((moved.flange().p - fresh.flange().p).norm(), 1e-10);
    TwistJacobian J_moved, J_fresh;
    moved.jacobian<6>(Eigen::Matrix<double, 6, 6>::Identity(), &J_moved);
    fresh.jacobian<6>(Eigen::Matrix<double, 6, 6>::Identity(), &J_fresh);
    for (int i = 0; i < kParameterCount; ++i)
      EXPECT_LT((J_moved.col(i) - J_fresh.col(i)).norm(),
                1e-10 * std::max(1.0, J_fresh.col(i).norm()))
          << parameter_table()[i].name;
  }
}

}  // namespace
}  // namespace robcal
