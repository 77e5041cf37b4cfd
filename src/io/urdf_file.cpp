#include "robcal/io/urdf_file.hpp"

#include <fmt/format.h>

#include <console_bridge/console.h>

#include <urdf_parser/urdf_parser.h>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal {
namespace {

constexpr double kMmPerM = 1000.0;
/// |z_i × z_i+1| below this: parallel axes (the common normal is not unique).
constexpr double kParallel = 1e-12;
// Plausible values (as in robot files, io/robot_file.cpp): beyond them a number is a unit slip
// (millimetres or degrees where URDF has metres and radians) or a typo, never a real arm.
constexpr double kMaxOriginM = 20;
constexpr double kMaxLimitRad = 6 * std::numbers::pi;
constexpr double kMaxMassKg = 10000;

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
          .normalized()
          .toRotationMatrix();
  T.translation() = kMmPerM * Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return T;
}

Eigen::Isometry3d frame(const Eigen::Vector3d& origin, const Eigen::Vector3d& x,
                        const Eigen::Vector3d& z) {
  Eigen::Isometry3d F = Eigen::Isometry3d::Identity();
  F.linear().col(0) = x;
  F.linear().col(1) = z.cross(x);
  F.linear().col(2) = z;
  F.translation() = origin;
  return F;
}

/// The MDH row of `rel` = Rot_x(α)·Trans_x(a)·Rot_z(θ)·Trans_z(d) (Craig eq. 3.6 inverted).
MdhRow mdh_row(const Eigen::Isometry3d& rel) {
  const Eigen::Matrix3d& R = rel.linear();
  const Eigen::Vector3d& p = rel.translation();
  MdhRow row;
  row.alpha = std::atan2(-R(1, 2), R(2, 2));
  row.theta_offset = std::atan2(-R(0, 1), R(0, 0));
  row.a = p.x();
  row.d = -std::sin(row.alpha) * p.y() + std::cos(row.alpha) * p.z();
  return row;
}

double snap_zero(double x, double below) {
  return std::abs(x) < below ? 0.0 : x;
}

struct ChainLink {
  urdf::JointConstSharedPtr joint;
  int follows = -1;                 ///< index of the previous movable joint, -1: none
  Eigen::Isometry3d world_T_joint;  ///< at zero joint values (mm)
  double mass = 0;                  ///< folded inertials moving with this joint
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();  ///< Σ m·c in the root frame (kg·mm)
};

struct Walk {
  std::map<std::string, Eigen::Isometry3d> world_T_link;  ///< every link at zero
  std::map<std::string, int> moved_by;  ///< link -> index of the last movable joint (-1: base)
  std::vector<ChainLink> movable;
};

/// Keeps urdfdom's error messages (console_bridge) for the refusal instead of printing them.
class KeepErrors : public console_bridge::OutputHandler {
 public:
  KeepErrors() { console_bridge::useOutputHandler(this); }
  ~KeepErrors() override { console_bridge::restorePreviousOutputHandler(); }
  KeepErrors(const KeepErrors&) = delete;
  KeepErrors& operator=(const KeepErrors&) = delete;
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR)
      errors += (errors.empty() ? "" : "; ") + text;
  }
  std::string errors;
};

[[noreturn]] void refuse(const std::string& path, const std::string& what) {
  throw InputError(SourceLocation{path, 0, 0, ""}, what);
}

/// A link's inertial folded into the joint that moves it (none before joint 1).
void add_mass(const urdf::Link& link, int moved_by, const std::string& path, Walk& w) {
  w.moved_by[link.name] = moved_by;
  if (link.inertial && !(link.inertial->mass >= 0 && link.inertial->mass <= kMaxMassKg))
    refuse(path, fmt::format("link '{}': mass {} kg is outside the plausible range [0, {}] kg",
                             link.name, link.inertial->mass, kMaxMassKg));
  if (link.inertial && link.inertial->mass > 0 && moved_by >= 0) {
    ChainLink& c = w.movable[moved_by];
    c.mass += link.inertial->mass;
    c.moment += link.inertial->mass *
                (w.world_T_link.at(link.name) * to_isometry(link.inertial->origin)).translation();
  }
}

/// Every link from the root, depth first in the file's order, with an explicit stack: a chain
/// of thousands of fixed joints must not exhaust the call stack.
void walk(const urdf::ModelInterface& urdf, const urdf::LinkConstSharedPtr& root,
          const std::string& path, Walk& w) {
  add_mass(*root, -1, path, w);
  std::vector<std::pair<urdf::JointSharedPtr, int>> pending;  // joint, index moving its parent
  const auto push_children = [&](const urdf::Link& link, int moved_by) {
    for (auto j = link.child_joints.rbegin(); j != link.child_joints.rend(); ++j)
      pending.emplace_back(*j, moved_by);
  };
  push_children(*root, -1);
  while (!pending.empty()) {
    const auto [joint, moved_by] = pending.back();
    pending.pop_back();
    const std::string where = fmt::format("joint '{}'", joint->name);
    // urdfdom accepts a joint back to a link already reached (its own parent, say): walking on
    // would never end.
    if (w.moved_by.contains(joint->child_link_name))
      refuse(path, fmt::format("{} leads back to link '{}', which it already reaches: the joints "
                               "form a loop, a robot's links form a tree",
                               where, joint->child_link_name));
    if (joint->mimic)
      refuse(path, where + " is a mimic joint: robcal needs six independent joints");
    const urdf::Vector3& origin = joint->parent_to_joint_origin_transform.position;
    if (std::max({std::abs(origin.x), std::abs(origin.y), std::abs(origin.z)}) > kMaxOriginM)
      refuse(path, fmt::format("{}: origin xyz=\"{} {} {}\" is beyond {} m from its parent link: "
                               "URDF lengths are in metres, not millimetres",
                               where, origin.x, origin.y, origin.z, kMaxOriginM));
    const Eigen::Isometry3d world_T_joint = w.world_T_link.at(joint->parent_link_name) *
                                            to_isometry(joint->parent_to_joint_origin_transform);
    int next = moved_by;
    switch (joint->type) {
      case urdf::Joint::FIXED:
        break;
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
        for (const ChainLink& c : w.movable)
          if (c.follows == moved_by)
            refuse(path,
                   fmt::format("joints '{}' and '{}' both hang on the part moved by {}: a "
                               "tree, not a serial chain",
                               c.joint->name, joint->name,
                               moved_by < 0 ? std::string("nothing (the base)")
                                            : "joint '" + w.movable[moved_by].joint->name + "'"));
        next = static_cast<int>(w.movable.size());
        w.movable.push_back({joint, moved_by, world_T_joint, 0, Eigen::Vector3d::Zero()});
        break;
      default:
        refuse(path, where +
                         " is not revolute (prismatic, floating or planar): robcal models "
                         "six revolute joints");
    }
    w.world_T_link[joint->child_link_name] = world_T_joint;
    const urdf::LinkConstSharedPtr child = urdf.getLink(joint->child_link_name);
    add_mass(*child, next, path, w);
    push_children(*child, next);
  }
}

/// The rotation as URDF's fixed-axis roll, pitch, yaw (R = Rz(y)·Ry(p)·Rx(r)); the roll is taken
/// from what remains after yaw and pitch, so that it stays exact near pitch ±90°.
Eigen::Vector3d rpy(const Eigen::Matrix3d& R) {
  const double p = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0)));
  const double y = std::atan2(R(1, 0), R(0, 0));
  const Eigen::Matrix3d rest = (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix()
                                   .transpose() *
                               R;
  return {std::atan2(rest(2, 1), rest(1, 1)), p, y};
}

std::string origin_tag(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d p = T.translation() / kMmPerM;
  const Eigen::Vector3d a = rpy(T.linear());
  return fmt::format("<origin xyz=\"{:.17g} {:.17g} {:.17g}\" rpy=\"{:.17g} {:.17g} {:.17g}\"/>",
                     p.x(), p.y(), p.z(), a.x(), a.y(), a.z());
}

Eigen::Isometry3d mdh_isometry(double alpha, double a, double theta, double d) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(alpha, Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(a, -std::sin(alpha) * d, std::cos(alpha) * d);
  return T;
}

}  // namespace

bool UrdfImport::has_base_placement() const {
  return params.head<kBaseParamCount>().cwiseAbs().maxCoeff() > 0;
}

bool UrdfImport::has_tip_offset() const {
  // Rounding of the frame construction leaves ~1e-13 mm and ~1e-16 rad.
  return flange_T_tip.translation().norm() > 1e-9 || !flange_T_tip.linear().isIdentity(1e-12);
}

UrdfImport robot_from_urdf(const std::string& xml, const std::string& path,
                           const UrdfImportOptions& options) {
  urdf::ModelInterfaceSharedPtr urdf;
  std::string errors;
  {
    KeepErrors keep;
    urdf = urdf::parseURDF(xml);
    errors = keep.errors;
  }
  if (!urdf)
    refuse(path, "not a valid URDF robot: " + (errors.empty() ? "urdfdom refused it" : errors));
  Walk w;
  const urdf::LinkConstSharedPtr root = urdf->getRoot();
  w.world_T_link[root->name] = Eigen::Isometry3d::Identity();
  walk(*urdf, root, path, w);
  if (w.movable.size() != kJointCount) {
    std::string names;
    for (const ChainLink& c : w.movable) names += (names.empty() ? "" : ", ") + c.joint->name;
    refuse(path, fmt::format("{} revolute joints ({}): robcal models chains of exactly six",
                             w.movable.size(), names.empty() ? "none" : names));
  }
  UrdfImport out;
  out.root_link = root->name;
  const std::string last_child = w.movable[5].joint->child_link_name;
  out.tip_link = options.tip_link;
  if (out.tip_link.empty())
    out.tip_link =
        w.moved_by.contains("tool0") && w.moved_by.at("tool0") == 5 ? "tool0" : last_child;
  if (!w.moved_by.contains(out.tip_link) || w.moved_by.at(out.tip_link) != 5)
    refuse(path, fmt::format("tip link '{}' does not follow joint '{}' through fixed joints only",
                             out.tip_link, w.movable[5].joint->name));

  // The axis lines at the zero joint values.
  std::array<Eigen::Vector3d, kJointCount> point, axis;
  for (int i = 0; i < kJointCount; ++i) {
    const ChainLink& c = w.movable[i];
    out.joint_names[i] = c.joint->name;
    const Eigen::Vector3d local(c.joint->axis.x, c.joint->axis.y, c.joint->axis.z);
    if (local.norm() < 1e-9) refuse(path, fmt::format("joint '{}' has a zero axis", c.joint->name));
    point[i] = c.world_T_joint.translation();
    axis[i] = (c.world_T_joint.linear() * local).normalized();
  }
  RobotModel& model = out.model;
  model.name = urdf->getName();
  model.source = "URDF " + path;
  // Joint 1 turns about +z of the model and joint 6 about the tip's z (when it lies along it):
  // an axis the other way is reversed in the joint map.
  const Eigen::Isometry3d world_T_tip = w.world_T_link.at(out.tip_link);
  for (const auto& [i, up] : {std::pair{0, Eigen::Vector3d::UnitZ().eval()},
                              std::pair{5, world_T_tip.linear().col(2).eval()}})
    if (axis[i].dot(up) < 0) {
      axis[i] = -axis[i];
      model.joint_map.matrix(i, i) = -1;
    }

  // MDH frames 1..5: origin at the foot of the common normal to the next axis, x along it.
  std::array<Eigen::Isometry3d, kJointCount> F;
  Eigen::Vector3d foot = point[0] - point[0].dot(axis[0]) * axis[0];  // root origin on axis 1
  for (int i = 0; i + 1 < kJointCount; ++i) {
    const Eigen::Vector3d& z = axis[i];
    const Eigen::Vector3d& zn = axis[i + 1];
    const Eigen::Vector3d c = z.cross(zn);
    Eigen::Vector3d origin, x;
    if (c.norm() > kParallel) {
      // Closest points of the lines point_i + s·z and point_i+1 + t·zn.
      const Eigen::Vector3d w0 = point[i] - point[i + 1];
      const double b = z.dot(zn), d = z.dot(w0), e = zn.dot(w0), den = 1 - b * b;
      const double s = (b * e - d) / den;
      origin = point[i] + s * z;
      x = c.normalized();
    } else {
      origin = foot;  // the previous foot (d = 0): the normal's place along z is free
      Eigen::Vector3d perp = point[i + 1] - origin;
      perp -= perp.dot(z) * z;
      if (perp.norm() < 1e-9)
        refuse(path, fmt::format("joints '{}' and '{}' turn about the same line",
                                 out.joint_names[i], out.joint_names[i + 1]));
      x = perp.normalized();
    }
    // Of the two directions of the normal, the one nearer the joint frame's x: a URDF written
    // from MDH frames (robot_to_urdf) gives its table back.
    if (x.dot(w.movable[i].world_T_joint.linear().col(0)) < 0) x = -x;
    F[i] = frame(origin, x, z);
    const double a = (point[i + 1] - origin).dot(x);
    foot = origin + a * x;
  }
  // Frame 6: on axis 6 at the tip's foot, x from the tip's x (or frame 5's when along axis 6).
  const Eigen::Vector3d z6 = axis[5];
  const Eigen::Vector3d o6 = point[5] + (world_T_tip.translation() - point[5]).dot(z6) * z6;
  Eigen::Vector3d x6 = world_T_tip.linear().col(0);
  x6 -= x6.dot(z6) * z6;
  x6 = x6.norm() > 1e-6 ? x6.normalized() : Eigen::Vector3d(F[4].linear().col(0));
  F[5] = frame(o6, x6, z6);
  out.flange_T_tip = F[5].inverse() * world_T_tip;

  // Frame 1 = Trans(x, y, d1)·Rot_x(alpha)·Rot_y(beta)·Rot_z(theta0) (forward_kinematics.hpp).
  const Eigen::Matrix3d& R1 = F[0].linear();
  model.mdh[0].d = F[0].translation().z();
  model.mdh[0].theta_offset = std::atan2(-R1(0, 1), R1(0, 0));
  for (int i = 1; i < kJointCount; ++i) model.mdh[i] = mdh_row(F[i - 1].inverse() * F[i]);
  // Rounding leaves ~1e-14 mm and ~1e-16 rad where the URDF means zero (and -0): print zeros.
  for (MdhRow& row : model.mdh) {
    row.alpha = snap_zero(row.alpha, 1e-14);
    row.theta_offset = snap_zero(row.theta_offset, 1e-14);
    row.a = snap_zero(row.a, 1e-11);
    row.d = snap_zero(row.d, 1e-11);
  }
  out.params = model.nominal();
  out.params[0] = F[0].translation().x();
  out.params[1] = F[0].translation().y();
  out.params[3] = std::atan2(-R1(1, 2), R1(2, 2));
  out.params[4] = std::atan2(R1(0, 2), std::hypot(R1(1, 2), R1(2, 2)));
  for (int k : {0, 1}) out.params[k] = snap_zero(out.params[k], 1e-11);
  for (int k : {3, 4}) out.params[k] = snap_zero(out.params[k], 1e-14);

  for (int i = 0; i < kJointCount; ++i) {
    const urdf::Joint& joint = *w.movable[i].joint;
    if (joint.type == urdf::Joint::CONTINUOUS || !joint.limits)
      model.limits[i] = {-2 * std::numbers::pi, 2 * std::numbers::pi};
    else
      model.limits[i] = {joint.limits->lower, joint.limits->upper};
    // Beyond three turns either way a limit is in degrees, not URDF's radians.
    for (const double limit : {model.limits[i].lower, model.limits[i].upper})
      if (std::abs(limit) > kMaxLimitRad)
        refuse(path, fmt::format("joint '{}': limit {} rad is beyond ±{:.2f} rad (3 turns): "
                                 "URDF limits are in radians, not degrees",
                                 joint.name, limit, kMaxLimitRad));
    if (model.limits[i].lower >= model.limits[i].upper)
      refuse(path, fmt::format("joint '{}': lower limit {} ≥ upper limit {} rad", joint.name,
                               model.limits[i].lower, model.limits[i].upper));
    const ChainLink& c = w.movable[i];
    if (c.mass > 0) {
      model.link_masses[i] = {c.mass, F[i].inverse() * (c.moment / c.mass)};
      for (double& v : model.link_masses[i].cog_mm) v = snap_zero(v, 1e-11);
    }
  }
  return out;
}

UrdfImport load_urdf_robot(const std::string& path, const UrdfImportOptions& options) {
  return robot_from_urdf(read_text_file(path), path, options);
}

UrdfExport robot_to_urdf(const RobotModel& model, const ParameterVector& params,
                         const Eigen::Isometry3d* flange_T_tcp) {
  UrdfExport out;
  const auto& table = parameter_table();
  for (int k = kComplianceOffset; k < kParameterCount; ++k) {
    const double neutral = k >= kScaleOffset && k < kPeriodicOffset ? 1.0 : 0.0;
    if (params[k] != neutral)
      out.left_out.push_back(fmt::format("{} = {:.6g} {} (URDF joints are rigid and unscaled)",
                                         table[k].name, params[k] * table[k].to_external(),
                                         table[k].unit));
  }
  // A diagonal joint map (signs, zero offsets) goes into the axes and origins; a coupled one
  // cannot: the URDF's joint values are then the model's angles.
  const Matrix6d& M = model.joint_map.matrix;
  const bool diagonal = M.isDiagonal(0.0) && M.diagonal().cwiseAbs().isOnes(0.0);
  if (!diagonal)
    out.left_out.push_back(
        "joint_map (coupled controller joints): the URDF's joint values are "
        "the model's angles q = M·J + offset, its limits the controller's");
  const auto sign = [&](int i) { return diagonal ? M(i, i) : 1.0; };
  const auto offset = [&](int i) { return diagonal ? model.joint_map.offset[i] : 0.0; };

  std::string name;  // an XML attribute value
  for (char ch : model.name.empty() ? std::string("robot") : model.name)
    name += ch == '&' ? "&amp;" : ch == '<' ? "&lt;" : ch == '"' ? "&quot;" : std::string(1, ch);
  std::string xml = fmt::format("<?xml version=\"1.0\"?>\n<robot name=\"{}\">\n", name);
  xml += "  <link name=\"base_link\"/>\n";
  for (int i = 0; i < kJointCount; ++i) {
    const int link = i + 1;
    Eigen::Isometry3d origin;
    if (link == 1) {
      origin = Eigen::Isometry3d::Identity();
      origin.translation() = Eigen::Vector3d(params[0], params[1], model.mdh[0].d + params[2]);
      origin.linear() = (Eigen::AngleAxisd(params[3], Eigen::Vector3d::UnitX()) *
                         Eigen::AngleAxisd(params[4], Eigen::Vector3d::UnitY()) *
                         Eigen::AngleAxisd(params[5] + model.mdh[0].theta_offset + offset(0),
                                           Eigen::Vector3d::UnitZ()))
                            .toRotationMatrix();
    } else {
      origin = mdh_isometry(params[link_param(link, 0)], params[link_param(link, 1)],
                            params[link_param(link, 2)] + offset(i), params[link_param(link, 3)]);
    }
    const PointMass& m = model.link_masses[i];
    std::string inertial;
    if (m.mass_kg > 0)
      inertial = fmt::format(
          "    <inertial>\n      <origin xyz=\"{:.17g} {:.17g} {:.17g}\"/>\n      <mass "
          "value=\"{:.17g}\"/>\n      <inertia ixx=\"0\" ixy=\"0\" ixz=\"0\" iyy=\"0\" iyz=\"0\" "
          "izz=\"0\"/>\n    </inertial>\n",
          m.cog_mm.x() / kMmPerM, m.cog_mm.y() / kMmPerM, m.cog_mm.z() / kMmPerM, m.mass_kg);
    xml += fmt::format(
        "  <joint name=\"joint_{0}\" type=\"revolute\">\n    <parent link=\"{1}\"/>\n    <child "
        "link=\"link_{0}\"/>\n    {2}\n    <axis xyz=\"0 0 {3}\"/>\n    <limit lower=\"{4:.17g}\" "
        "upper=\"{5:.17g}\" effort=\"0\" velocity=\"0\"/>\n  </joint>\n  <link "
        "name=\"link_{0}\"{6}",
        link, link == 1 ? "base_link" : fmt::format("link_{}", i), origin_tag(origin), sign(i),
        model.limits[i].lower, model.limits[i].upper,
        inertial.empty() ? "/>\n" : ">\n" + inertial + "  </link>\n");
  }
  xml +=
      "  <joint name=\"link_6-tool0\" type=\"fixed\">\n    <parent link=\"link_6\"/>\n    <child "
      "link=\"tool0\"/>\n  </joint>\n  <link name=\"tool0\"/>\n";
  if (flange_T_tcp)
    xml += fmt::format(
        "  <joint name=\"tool0-tcp\" type=\"fixed\">\n    <parent link=\"tool0\"/>\n    <child "
        "link=\"tcp\"/>\n    {}\n  </joint>\n  <link name=\"tcp\"/>\n",
        origin_tag(*flange_T_tcp));
  out.xml = xml + "</robot>\n";
  return out;
}

}  // namespace robcal
