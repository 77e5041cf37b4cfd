// Forward kinematics against independent values: the IRB 120 home pose, the reference data
// set's 200 nominal and true poses (an independent implementation of docs/method/), pybotics' UR10
// poses (Craig MDH), and derivatives against finite differences.

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

Vector6d joints_of(const test::CsvTable& t, size_t row) {
  Vector6d q;
  for (int i = 0; i < 6; ++i) q[i] = deg2rad(t.rows[row][i]);
  return q;
}

TEST(ForwardKinematics, Irb120HomeIsAt374_0_630) {
  const RobotModel model = load_robot("abb-irb120");
  const Pose<double> pose = flange_pose(model, PointMass{}, model.nominal(), Vector6d::Zero());
  EXPECT_NEAR(pose.p.x(), 374.0, 1e-12);
  EXPECT_NEAR(pose.p.y(), 0.0, 1e-12);
  EXPECT_NEAR(pose.p.z(), 630.0, 1e-12);
  // Flange z axis points along +x of the base at home (tool0 of ABB).
  EXPECT_NEAR(pose.R(0, 2), 1.0, 1e-12);
}

TEST(ForwardKinematics, NominalMatchesReferenceCases) {
  const RobotModel model = load_robot("abb-irb120");
  const auto cases = test::read_csv(test::data_path("irb120-published/fk_cases.csv"));
  ASSERT_EQ(cases.rows.size(), 200u);
  for (size_t r = 0; r < cases.rows.size(); ++r) {
    const Pose<double> pose = flange_pose(model, PointMass{}, model.nominal(), joints_of(cases, r));
    const Eigen::Vector3d expected(cases.at(r, "nominal_x"), cases.at(r, "nominal_y"),
                                   cases.at(r, "nominal_z"));
    EXPECT_LT((pose.p - expected).norm(), 1e-8) << "case " << r;
    const Eigen::Quaterniond q(cases.at(r, "nominal_qw"), cases.at(r, "nominal_qx"),
                               cases.at(r, "nominal_qy"), cases.at(r, "nominal_qz"));
    EXPECT_LT(rotation_distance(pose.R, q.toRotationMatrix()), 1e-9) << "case " << r;
  }
}

TEST(ForwardKinematics, TrueRobotWithComplianceMatchesReferenceCases) {
  const test::ReferenceTruth truth = test::load_reference_truth();
  const Tool tool = load_tool(test::data_path("irb120-published/tool.yaml"));
  const auto cases = test::read_csv(test::data_path("irb120-published/fk_cases.csv"));
  double worst = 0;
  for (size_t r = 0; r < cases.rows.size(); ++r) {
    const Pose<double> pose =
        flange_pose(truth.model, tool.payload, truth.params, joints_of(cases, r));
    const Eigen::Vector3d expected(cases.at(r, "true_x"), cases.at(r, "true_y"),
                                   cases.at(r, "true_z"));
    worst = std::max(worst, (pose.p - expected).norm());
    const Eigen::Quaterniond q(cases.at(r, "true_qw"), cases.at(r, "true_qx"),
                               cases.at(r, "true_qy"), cases.at(r, "true_qz"));
    EXPECT_LT(rotation_distance(pose.R, q.toRotationMatrix()), 1e-9) << "case " << r;
    for (int k = 1; k <= 3; ++k) {
      const Eigen::Vector3d target = pose * tool.targets[k - 1].position_mm;
      const std::string prefix = "true_t" + std::to_string(k) + "_";
      const Eigen::Vector3d expected_target(cases.at(r, prefix + "x"), cases.at(r, prefix + "y"),
                                            cases.at(r, prefix + "z"));
      EXPECT_LT((target - expected_target).norm(), 1e-7) << "case " << r << " target " << k;
    }
  }
  EXPECT_LT(worst, 1e-7);
}

TEST(ForwardKinematics, Ur10PybioticsPosesCraigMdh) {
  // pybotics' own "UR10" MDH numbers (a convention check, not UR's data sheet).
  const auto root = yaml::parse(R"(
name: pybotics UR10 (MDH convention check)
mdh:
  - [0, 0, 0, 118]
  - [90, 0, 180, 0]
  - [0, 612.7, 0, 0]
  - [0, 571.6, 0, 163.9]
  - [-90, 0, 0, 115.7]
  - [90, 0, 180, 92.2]
joint_limits_deg: [[-360,360],[-360,360],[-360,360],[-360,360],[-360,360],[-360,360]]
)",
                                "inline");
  const RobotModel model = parse_robot(root);
  std::ifstream in(test::data_path("pybotics/ur10-joints-poses.csv"));
  ASSERT_TRUE(in.good());
  std::string line;
  int checked = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string cell;
    std::vector<double> v;
    while (std::getline(ss, cell, ',')) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 22u);
    Vector6d q;
    for (int i = 0; i < 6; ++i) q[i] = deg2rad(v[i]);
    const Pose<double> pose = flange_pose(model, PointMass{}, model.nominal(), q);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(pose.R(r, c), v[6 + 4 * r + c], 1e-12);
      EXPECT_NEAR(pose.p[r], v[6 + 4 * r + 3], 1e-9);
    }
    ++checked;
  }
  EXPECT_EQ(checked, 20);
}

TEST(ForwardKinematics, JetDerivativesMatchFiniteDifferences) {
  // d(target position)/d(parameters, joints) through Ceres Jets vs central differences,
  // with compliance on, at random configurations (seed 7).
  const test::ReferenceTruth truth = test::load_reference_truth();
  const Tool tool = load_tool(test::data_path("irb120-published/tool.yaml"));
  const Eigen::Vector3d t = tool.targets[1].position_mm;
  constexpr int N = kParameterCount + kJointCount;
  using Jet = ceres::Jet<double, N>;
  auto rng = test::seeded_rng(7);
  std::uniform_real_distribution<double> angle(-1.5, 1.5);
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd x(N);
    x.head(kParameterCount) = truth.params;
    for (int i = 0; i < kJointCount; ++i) x[kParameterCount + i] = angle(rng);
    std::array<Jet, N> xj;
    for (int i = 0; i < N; ++i) xj[i] = Jet(x[i], i);
    const Pose<Jet> pose =
        flange_pose<Jet>(truth.model, tool.payload, xj.data(), xj.data() + kParameterCount);
    const Vector3<Jet> p = pose * t.cast<Jet>();
    Eigen::MatrixXd J_ad(3, N);
    for (int r = 0; r < 3; ++r) J_ad.row(r) = p[r].v.transpose();
    auto f = [&](const Eigen::VectorXd& y) -> Eigen::VectorXd {
      const Pose<double> q =
          flange_pose<double>(truth.model, tool.payload, y.data(), y.data() + kParameterCount);
      return q * t;
    };
    const Eigen::MatrixXd J_fd = test::numerical_jacobian(f, x, 1e-7);
    for (int c = 0; c < N; ++c) {
      // Compliance columns are ~1e9 mm per unit: compare relative to the column's size.
      const double scale = std::max(1.0, J_ad.col(c).norm());
      EXPECT_LT((J_ad.col(c) - J_fd.col(c)).norm() / scale,
                c >= kComplianceOffset && c < kScaleOffset ? 1e-4 : 1e-5)
          << "column " << parameter_table()[std::min(c, kParameterCount - 1)].name << " trial "
          << trial;
    }
  }
}

}  // namespace
}  // namespace robcal
