// URDF in and out (io/urdf_file.hpp): robcal's FK of an imported URDF against KDL's FK of the
// same file (an independent implementation, Debian's orocos-kdl, fed by urdfdom's parse), round
// trips model → URDF → model on every built-in robot, a calibrated model's geometry, refusals.

#include <gtest/gtest.h>

#include <urdf_parser/urdf_parser.h>
#include <cmath>
#include <cstdio>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <numbers>
#include <random>

#include "refusal.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/urdf_file.hpp"
#include "robcal/kinematics/forward_kinematics.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

constexpr double kMm = 1000.0;  // KDL and URDF work in metres

Eigen::Isometry3d iso(const Pose<double>& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = p.R;
  T.translation() = p.p;
  return T;
}

Eigen::Isometry3d iso(const KDL::Frame& f) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T.linear()(r, c) = f.M(r, c);
    T.translation()[r] = kMm * f.p[r];
  }
  return T;
}

KDL::Frame kdl_frame(const urdf::Pose& p) {
  return KDL::Frame(
      KDL::Rotation::Quaternion(p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w),
      KDL::Vector(p.position.x, p.position.y, p.position.z));
}

/// The KDL chain from the URDF's root to `tip`, built the way kdl_parser does: each joint a
/// rotation about its axis through the joint origin, in the parent link's frame.
KDL::Chain kdl_chain(const urdf::ModelInterface& urdf, const std::string& tip) {
  std::vector<urdf::JointSharedPtr> joints;
  for (auto link = urdf.getLink(tip); link->parent_joint;
       link = urdf.getLink(link->parent_joint->parent_link_name))
    joints.insert(joints.begin(), link->parent_joint);
  KDL::Chain chain;
  for (const auto& j : joints) {
    const KDL::Frame origin = kdl_frame(j->parent_to_joint_origin_transform);
    const KDL::Joint joint =
        j->type == urdf::Joint::FIXED
            ? KDL::Joint(j->name, KDL::Joint::Fixed)
            : KDL::Joint(j->name, origin.p, origin.M * KDL::Vector(j->axis.x, j->axis.y, j->axis.z),
                         KDL::Joint::RotAxis);
    chain.addSegment(KDL::Segment(j->child_link_name, joint, origin));
  }
  return chain;
}

Eigen::Isometry3d kdl_fk(const KDL::Chain& chain, const Vector6d& q, int segment = -1) {
  KDL::ChainFkSolverPos_recursive solver(chain);
  KDL::JntArray joints(chain.getNrOfJoints());
  for (unsigned i = 0; i < chain.getNrOfJoints(); ++i) joints(i) = q[i];
  KDL::Frame f;
  EXPECT_GE(solver.JntToCart(joints, f, segment), 0);
  return iso(f);
}

Eigen::Isometry3d robcal_fk(const UrdfImport& r, const Vector6d& q) {
  return iso(flange_pose(r.model, PointMass{}, r.params, q)) * r.flange_T_tip;
}

/// Largest position difference (mm) and rotation difference (rad) between two poses.
std::pair<double, double> gap(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return {(a.translation() - b.translation()).norm(),
          Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle()};
}

Vector6d random_joints(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-std::numbers::pi, std::numbers::pi);
  Vector6d q;
  for (double& v : q) v = u(rng);
  return q;
}

TEST(UrdfFile, SkewArmMatchesKdlOnTenThousandConfigurations) {
  const std::string path = test::data_path("urdf/skew6r.urdf");
  const std::string xml = read_text_file(path);
  const auto urdf = urdf::parseURDF(xml);
  ASSERT_TRUE(urdf);
  for (const std::string tip : {"tool0", "tcp"}) {
    SCOPED_TRACE(tip);
    const UrdfImport r = robot_from_urdf(xml, path, {tip});
    EXPECT_TRUE(r.has_base_placement());  // the tilted mount
    EXPECT_EQ(r.has_tip_offset(), tip == "tcp");
    EXPECT_EQ(r.model.joint_map.matrix(0, 0), -1);  // joint 1 turns about -z
    const KDL::Chain chain = kdl_chain(*urdf, tip);
    ASSERT_EQ(chain.getNrOfJoints(), 6u);
    std::mt19937_64 rng = test::seeded_rng(15);
    double worst_mm = 0, worst_rad = 0;
    for (int k = 0; k < 10000; ++k) {
      const Vector6d q = random_joints(rng);
      const auto [mm, rad] = gap(robcal_fk(r, q), kdl_fk(chain, q));
      worst_mm = std::max(worst_mm, mm);
      worst_rad = std::max(worst_rad, rad);
    }
    EXPECT_LT(worst_mm, 1e-9);
    EXPECT_LT(worst_rad, 1e-12);
    std::printf("skew6r to %s vs KDL, 10,000 configurations: %.2e mm, %.2e rad\n", tip.c_str(),
                worst_mm, worst_rad);
  }
}

TEST(UrdfFile, SkewArmLimitsAndMassesFromTheFile) {
  const std::string path = test::data_path("urdf/skew6r.urdf");
  const UrdfImport r = load_urdf_robot(path);
  EXPECT_EQ(r.tip_link, "tool0");
  EXPECT_EQ(r.joint_names[3], "joint_4");
  EXPECT_DOUBLE_EQ(r.model.limits[1].lower, -1.5);
  EXPECT_DOUBLE_EQ(r.model.limits[2].upper, 1.2);
  EXPECT_DOUBLE_EQ(r.model.limits[5].upper, 2 * std::numbers::pi);  // continuous joint 6
  // Masses per moving link: link_3 and its fixed cover are one; tool0's goes to link 6; the
  // base's moves with nothing.
  const std::array<double, 6> mass{0, 3, 3, 0, 0, 0.5};
  for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(r.model.link_masses[i].mass_kg, mass[i]) << i;
  // Link 3's centre of gravity in the world, against KDL's frames of link_3 and cover.
  const auto urdf = urdf::parseURDF(read_text_file(path));
  const KDL::Chain to_link3 = kdl_chain(*urdf, "link_3"), to_cover = kdl_chain(*urdf, "cover");
  std::mt19937_64 rng = test::seeded_rng(16);
  for (int k = 0; k < 50; ++k) {
    const Vector6d q = random_joints(rng);
    const Eigen::Vector3d expected = (2 * (kdl_fk(to_link3, q) * Eigen::Vector3d(50, 10, 0)) +
                                      1 * (kdl_fk(to_cover, q) * Eigen::Vector3d(0, 0, 10))) /
                                     3;
    const auto frames = link_frames(r.model, PointMass{}, r.params.data(), q.data());
    EXPECT_LT((frames[2] * r.model.link_masses[2].cog_mm - expected).norm(), 1e-9);
  }
}

TEST(UrdfFile, EveryBuiltInRobotRoundTrips) {
  std::mt19937_64 rng = test::seeded_rng(17);
  double all_mm = 0;
  for (const std::string& name : builtin_robot_names()) {
    SCOPED_TRACE(name);
    const RobotModel model = load_robot(name);
    const ParameterVector nominal = model.nominal();
    const UrdfExport out = robot_to_urdf(model, nominal);
    const bool coupled = !out.left_out.empty();  // only a coupled joint map is left out
    if (coupled) {
      EXPECT_NE(out.left_out[0].find("joint_map"), std::string::npos);
    }
    const UrdfImport back = robot_from_urdf(out.xml, name + ".urdf");
    EXPECT_FALSE(back.has_base_placement());
    EXPECT_FALSE(back.has_tip_offset());
    for (int i = 0; i < 6; ++i) {
      EXPECT_NEAR(back.model.limits[i].lower, model.limits[i].lower, 1e-15);
      EXPECT_NEAR(back.model.limits[i].upper, model.limits[i].upper, 1e-15);
      EXPECT_NEAR(back.model.link_masses[i].mass_kg, model.link_masses[i].mass_kg, 1e-15);
    }
    // Without sign flips or offsets the URDF's joint frames are the MDH frames: the table
    // itself comes back (angles compared on the circle).
    if (model.joint_map.is_identity())
      for (int i = 0; i < 6; ++i) {
        const MdhRow &a = model.mdh[i], &b = back.model.mdh[i];
        EXPECT_NEAR(std::remainder(a.alpha - b.alpha, 2 * std::numbers::pi), 0, 1e-12) << i;
        EXPECT_NEAR(std::remainder(a.theta_offset - b.theta_offset, 2 * std::numbers::pi), 0, 1e-12)
            << i;
        EXPECT_NEAR(a.a, b.a, 1e-9) << i;
        EXPECT_NEAR(a.d, b.d, 1e-9) << i;
      }
    double worst_mm = 0, worst_rad = 0, worst_cog = 0;
    for (int k = 0; k < 200; ++k) {
      const Vector6d j = random_joints(rng);
      // With a coupled map the URDF's joint values are the model's angles.
      const Vector6d urdf_joints = coupled ? model.joint_map.to_model(j) : j;
      const auto [mm, rad] =
          gap(iso(flange_pose(model, PointMass{}, nominal, j)), robcal_fk(back, urdf_joints));
      worst_mm = std::max(worst_mm, mm);
      worst_rad = std::max(worst_rad, rad);
      const auto a = link_frames(model, PointMass{}, nominal.data(), j.data());
      const auto b = link_frames(back.model, PointMass{}, back.params.data(), urdf_joints.data());
      for (int i = 0; i < 6; ++i)
        worst_cog = std::max(
            worst_cog,
            (a[i] * model.link_masses[i].cog_mm - b[i] * back.model.link_masses[i].cog_mm).norm());
    }
    EXPECT_LT(worst_mm, 1e-9);
    EXPECT_LT(worst_rad, 1e-12);
    EXPECT_LT(worst_cog, 1e-9);
    all_mm = std::max(all_mm, worst_mm);
  }
  std::printf("built-in robots through URDF and back: worst %.2e mm\n", all_mm);
}

TEST(UrdfFile, CalibratedModelKeepsItsGeometryAndNamesWhatIsLeftOut) {
  const RobotModel model = load_robot("abb-irb120");
  ParameterVector params = model.nominal();
  std::mt19937_64 rng = test::seeded_rng(18);
  std::normal_distribution<double> mm(0, 0.5), rad(0, 1e-3);
  for (int k = 0; k < kBaseParamCount; ++k) params[k] += k < 3 ? 100 * mm(rng) : 100 * rad(rng);
  for (int link = 2; link <= 6; ++link)
    for (int k = 0; k < 4; ++k) params[link_param(link, k)] += k % 2 ? mm(rng) : rad(rng);
  params[compliance_param(2)] = 1e-9;
  params[compliance_param(3)] = -2e-9;
  params[scale_param(4)] = 1.001;
  Eigen::Isometry3d flange_T_tcp = Eigen::Isometry3d::Identity();
  flange_T_tcp.translation() << 12, -3, 150;
  flange_T_tcp.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).matrix();

  const UrdfExport out = robot_to_urdf(model, params, &flange_T_tcp);
  ASSERT_EQ(out.left_out.size(), 3u);
  EXPECT_EQ(out.left_out[0].rfind("joint2.compliance", 0), 0u);
  EXPECT_EQ(out.left_out[1].rfind("joint3.compliance", 0), 0u);
  EXPECT_EQ(out.left_out[2].rfind("joint4.scale", 0), 0u);

  ParameterVector rigid = params;  // the geometric part: no compliance, unit scales
  rigid.segment<5>(kComplianceOffset).setZero();
  rigid[scale_param(4)] = 1;
  const UrdfImport flange = robot_from_urdf(out.xml, "calibrated.urdf");
  const UrdfImport tcp = robot_from_urdf(out.xml, "calibrated.urdf", {"tcp"});
  EXPECT_TRUE(flange.has_base_placement());
  double worst = 0;
  for (int k = 0; k < 500; ++k) {
    const Vector6d j = random_joints(rng);
    const Eigen::Isometry3d expected = iso(flange_pose(model, PointMass{}, rigid, j));
    worst = std::max({worst, gap(expected, robcal_fk(flange, j)).first,
                      gap(expected * flange_T_tcp, robcal_fk(tcp, j)).first});
  }
  EXPECT_LT(worst, 1e-9);
  std::printf("calibrated IRB 120 through URDF, rigid FK: worst %.2e mm\n", worst);
}

/// A serial chain of revolute joints joint_1..joint_n; `edit` changes its text.
std::string chain_urdf(int n, const std::string& joint3_extra = "",
                       const std::string& joint3_type = "revolute") {
  std::string xml = "<robot name=\"bad\">\n<link name=\"link_0\"/>\n";
  for (int i = 1; i <= n; ++i)
    xml += "<joint name=\"joint_" + std::to_string(i) + "\" type=\"" +
           (i == 3 ? joint3_type : "revolute") + "\"><parent link=\"link_" + std::to_string(i - 1) +
           "\"/><child link=\"link_" + std::to_string(i) +
           "\"/><origin xyz=\"0.1 0 0.2\"/><axis xyz=\"" + (i % 2 ? "0 0 1" : "0 1 0") +
           "\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>" +
           (i == 3 ? joint3_extra : "") + "</joint>\n<link name=\"link_" + std::to_string(i) +
           "\"/>\n";
  return xml + "</robot>\n";
}

TEST(UrdfFile, RefusesWhatIsNotASixRevoluteChain) {
  EXPECT_NO_THROW(robot_from_urdf(chain_urdf(6), "ok.urdf"));
  EXPECT_REFUSED(robot_from_urdf(chain_urdf(7), "seven.urdf"), InputError,
                 "seven.urdf: 7 revolute joints (joint_1, joint_2, joint_3, joint_4, joint_5, "
                 "joint_6, joint_7)");
  EXPECT_REFUSED(robot_from_urdf(chain_urdf(5), "five.urdf"), InputError, "5 revolute joints");
  EXPECT_REFUSED(robot_from_urdf(chain_urdf(6, "", "prismatic"), "slide.urdf"), InputError,
                 "slide.urdf: joint 'joint_3' is not revolute");
  EXPECT_REFUSED(robot_from_urdf(chain_urdf(6, "<mimic joint=\"joint_2\"/>"), "mimic.urdf"),
                 InputError, "mimic.urdf: joint 'joint_3' is a mimic joint");
  std::string tree = chain_urdf(6);
  tree.insert(tree.find("</robot>"),
              "<joint name=\"branch\" type=\"revolute\"><parent link=\"link_2\"/><child "
              "link=\"side\"/><axis xyz=\"1 0 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" "
              "velocity=\"1\"/></joint><link name=\"side\"/>\n");
  EXPECT_REFUSED(robot_from_urdf(tree, "tree.urdf"), InputError, "a tree, not a serial chain");
  EXPECT_REFUSED(robot_from_urdf(tree, "tree.urdf"), InputError, "'branch'");
  EXPECT_REFUSED(robot_from_urdf(tree, "tree.urdf"), InputError, "moved by joint 'joint_2'");
  std::string orphan = chain_urdf(6);
  orphan.replace(orphan.find("<parent link=\"link_3\"/>"), 23, "<parent link=\"nowhere\"/>");
  EXPECT_REFUSED(robot_from_urdf(orphan, "orphan.urdf"), InputError,
                 "orphan.urdf: not a valid URDF");
  EXPECT_REFUSED(robot_from_urdf(orphan, "orphan.urdf"), InputError, "nowhere");
  // A joint back to a link already reached (urdfdom accepts one to its own parent link): refused,
  // not walked for ever.
  std::string loop = chain_urdf(6);
  loop.insert(loop.find("</robot>"),
              "<joint name=\"back\" type=\"fixed\"><parent link=\"link_6\"/><child "
              "link=\"link_6\"/></joint>\n");
  EXPECT_REFUSED(robot_from_urdf(loop, "loop.urdf"), InputError,
                 "loop.urdf: joint 'back' leads back to link 'link_6'");
  EXPECT_REFUSED(robot_from_urdf(chain_urdf(6), "ok.urdf", {"link_4"}), InputError,
                 "tip link 'link_4' does not follow joint 'joint_6'");
}

}  // namespace
}  // namespace robcal
