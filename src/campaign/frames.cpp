#include "robcal/campaign/frames.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <functional>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal::campaign {
namespace {

using Points = std::vector<Eigen::Vector3d>;

/// Covariance of f(points) for independent noise of σ per axis on every coordinate:
/// σ²·G·Gᵀ, G by central differences (the fits are smooth and converge far below the step).
Eigen::MatrixXd propagate(const Points& points,
                          const std::function<Eigen::VectorXd(const Points&)>& f, double sigma_mm) {
  constexpr double kStep = 1e-3;  // mm
  const Eigen::VectorXd f0 = f(points);
  Eigen::MatrixXd G(f0.size(), 3 * static_cast<Eigen::Index>(points.size()));
  Points moved = points;
  for (size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      moved[i][k] = points[i][k] + kStep;
      const Eigen::VectorXd up = f(moved);
      moved[i][k] = points[i][k] - kStep;
      const Eigen::VectorXd down = f(moved);
      moved[i][k] = points[i][k];
      G.col(3 * static_cast<Eigen::Index>(i) + k) = (up - down) / (2 * kStep);
    }
  return sigma_mm * sigma_mm * G * G.transpose();
}

/// The swept joint's model angles (rad), after checking that only that joint moves.
std::vector<double> swept_angles(const RobotModel& model, const JointSweep& sweep,
                                 int expected_joint, const char* name) {
  if (sweep.joint != expected_joint)
    throw InputError({"", 0, 0, name}, fmt::format("expected a sweep of joint {}, got joint {}",
                                                   expected_joint, sweep.joint));
  if (sweep.joints.size() != sweep.points_mm.size())
    throw InputError({"", 0, 0, name}, fmt::format("{} joint rows but {} points",
                                                   sweep.joints.size(), sweep.points_mm.size()));
  if (sweep.points_mm.size() < 4)
    throw InputError({"", 0, 0, name}, fmt::format("a sweep needs at least 4 readings, got {}",
                                                   sweep.points_mm.size()));
  // The model's joints must stay still but the swept one: on a robot whose controller couples
  // joints (Fanuc J2/J3) the controller values of the others move with it.
  const auto first = model_joint_angles(model, sweep.joints[0].data());
  std::vector<double> angles;
  for (size_t k = 0; k < sweep.joints.size(); ++k) {
    const auto q = model_joint_angles(model, sweep.joints[k].data());
    for (int j = 0; j < kJointCount; ++j)
      if (j != expected_joint - 1 && std::abs(q[j] - first[j]) > 1e-9)
        throw InputError(
            {"", 0, 0, name},
            fmt::format("reading {}: model joint {} moved ({:.6f}° vs {:.6f}° in the "
                        "first reading): only joint {} may turn in this sweep",
                        k + 1, j + 1, rad2deg(q[j]), rad2deg(first[j]), expected_joint));
    angles.push_back(q[expected_joint - 1]);
  }
  return angles;
}

/// Point on line (c1, n1) closest to line (c2, n2) (unit directions, not parallel).
Eigen::Vector3d closest_on_first(const Eigen::Vector3d& c1, const Eigen::Vector3d& n1,
                                 const Eigen::Vector3d& c2, const Eigen::Vector3d& n2) {
  const Eigen::Vector3d w = c1 - c2;
  const double b = n1.dot(n2), d = n1.dot(w), e = n2.dot(w);
  return c1 + ((b * e - d) / (1 - b * b)) * n1;
}

/// x_{i-1} from the axes z_{i-1}, z_i of consecutive joints: z_{i-1} × z_i = sin α_i · x_{i-1}.
Eigen::Vector3d common_normal(const Eigen::Vector3d& z_prev, const Eigen::Vector3d& z_next,
                              double alpha, const char* what) {
  if (std::abs(std::sin(alpha)) < 1e-3)
    throw InputError(
        fmt::format("{}: the robot's axes are (nearly) parallel, their common "
                    "normal cannot orient the frame",
                    what));
  const Eigen::Vector3d cross = z_prev.cross(z_next);
  if (cross.norm() < 1e-6) throw InputError(fmt::format("{}: the fitted axes are parallel", what));
  return std::copysign(1.0, std::sin(alpha)) * cross.normalized();
}

Eigen::Matrix<double, 6, 1> pose_values(const Pose<double>& pose) {
  Eigen::Matrix<double, 6, 1> v;
  v << pose.p, xyz_angles(pose.R);
  return v;
}

void finish(FrameEstimate& frame) {
  frame.values = pose_values(frame.pose);
  for (int i = 0; i < 6; ++i) frame.sigma[i] = std::sqrt(std::max(frame.covariance(i, i), 0.0));
}

/// σ per axis from two circle fits' residuals (each residual is one projection of the noise),
/// pooled over their degrees of freedom.
double pooled_sigma(const CircleFit& a, const CircleFit& b) {
  const double dof = 2.0 * (a.points + b.points) - 12.0;
  return std::sqrt((a.sigma_mm * a.sigma_mm * (2.0 * a.points - 6) +
                    b.sigma_mm * b.sigma_mm * (2.0 * b.points - 6)) /
                   dof);
}

/// RMS of the residuals of two circle fits together.
double pooled_rms(const CircleFit& a, const CircleFit& b) {
  return std::sqrt((a.rms_mm * a.rms_mm * a.points + b.rms_mm * b.rms_mm * b.points) /
                   (a.points + b.points));
}

}  // namespace

Eigen::Vector3d xyz_angles(const Eigen::Matrix3d& R) {
  // R = Rx(α)Ry(β)Rz(γ): R(0,2) = sin β, R(1,2) = −sin α cos β, R(2,2) = cos α cos β,
  // R(0,0) = cos β cos γ, R(0,1) = −cos β sin γ.
  return {std::atan2(-R(1, 2), R(2, 2)), std::asin(std::clamp(R(0, 2), -1.0, 1.0)),
          std::atan2(-R(0, 1), R(0, 0))};
}

namespace {

/// What two sweeps give: a result vector computed from their circles (and the second sweep's
/// points), its covariance by propagation from every measured point, and the residuals.
struct TwoSweepEstimate {
  Eigen::VectorXd value;
  Eigen::MatrixXd covariance;
  double rms_mm = 0, sigma_mm = 0;
};

using FromCircles = std::function<Eigen::VectorXd(const CircleFit& first, const CircleFit& second,
                                                  const Points& second_points)>;

TwoSweepEstimate from_two_sweeps(const JointSweep& first, const std::vector<double>& first_angles,
                                 const JointSweep& second, const std::vector<double>& second_angles,
                                 const FromCircles& result, double sigma_mm) {
  const long n1 = static_cast<long>(first.points_mm.size());
  const auto evaluate = [&](const Points& all, CircleFit* c1, CircleFit* c2) {
    const Points second_points(all.begin() + n1, all.end());
    const CircleFit a = fit_circle(Points(all.begin(), all.begin() + n1), first_angles);
    const CircleFit b = fit_circle(second_points, second_angles);
    if (c1) *c1 = a;
    if (c2) *c2 = b;
    return result(a, b, second_points);
  };
  Points all = first.points_mm;
  all.insert(all.end(), second.points_mm.begin(), second.points_mm.end());
  TwoSweepEstimate out;
  CircleFit a, b;
  out.value = evaluate(all, &a, &b);
  out.rms_mm = pooled_rms(a, b);
  out.sigma_mm = sigma_mm > 0 ? sigma_mm : pooled_sigma(a, b);
  out.covariance = propagate(
      all, [&](const Points& p) { return evaluate(p, nullptr, nullptr); }, out.sigma_mm);
  return out;
}

}  // namespace

FrameEstimate base_from_sweeps(const RobotModel& model, const JointSweep& joint1,
                               const JointSweep& joint2, double sigma_mm) {
  const std::vector<double> a1 = swept_angles(model, joint1, 1, "joint-1 sweep");
  const std::vector<double> a2 = swept_angles(model, joint2, 2, "joint-2 sweep");
  const double theta1 =
      model_joint_angles(model, joint2.joints[0].data())[0] + model.mdh[0].theta_offset;
  const auto place = [&](const CircleFit& c1, const CircleFit& c2,
                         const Points&) -> Eigen::VectorXd {
    const Eigen::Vector3d z1 = c1.axis;
    const Eigen::Vector3d x1 = common_normal(z1, c2.axis, model.mdh[1].alpha, "base frame");
    const Eigen::Vector3d origin1 = closest_on_first(c1.centre_mm, z1, c2.centre_mm, c2.axis);
    Eigen::Matrix3d R1;
    R1 << x1, z1.cross(x1), z1;
    Pose<double> base;
    base.R = R1 * Eigen::AngleAxisd(-theta1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // d1 along world z (docs/method/02-frames.md §4).
    base.p = origin1 - Eigen::Vector3d(0, 0, model.mdh[0].d);
    return pose_values(base);
  };
  const TwoSweepEstimate e = from_two_sweeps(joint1, a1, joint2, a2, place, sigma_mm);
  FrameEstimate frame;
  frame.values = e.value;
  frame.pose.p = e.value.head<3>();
  frame.pose.R = (Eigen::AngleAxisd(e.value[3], Eigen::Vector3d::UnitX()) *
                  Eigen::AngleAxisd(e.value[4], Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(e.value[5], Eigen::Vector3d::UnitZ()))
                     .toRotationMatrix();
  frame.covariance = e.covariance;
  frame.rms_mm = e.rms_mm;
  frame.sigma_mm = e.sigma_mm;
  finish(frame);
  return frame;
}

PointEstimate tool_from_sweeps(const RobotModel& model, const JointSweep& joint5,
                               const JointSweep& joint6, double sigma_mm) {
  const std::vector<double> a5 = swept_angles(model, joint5, 5, "joint-5 sweep");
  const std::vector<double> a6 = swept_angles(model, joint6, 6, "joint-6 sweep");
  for (int j = 0; j < 4; ++j)
    if (std::abs(joint5.joints[0][j] - joint6.joints[0][j]) > 1e-9)
      throw InputError({"", 0, 0, "joint-6 sweep"},
                       fmt::format("joint {} differs between the joint-5 and joint-6 sweeps: "
                                   "joints 1–4 must stay where they are",
                                   j + 1));
  const MdhRow& link6 = model.mdh[5];
  const auto locate = [&](const CircleFit& c5, const CircleFit& c6,
                          const Points& p6) -> Eigen::VectorXd {
    const Eigen::Vector3d z6 = c6.axis;
    const Eigen::Vector3d x5 = common_normal(c5.axis, z6, link6.alpha, "tool");
    const Eigen::Vector3d flange =
        closest_on_first(c6.centre_mm, z6, c5.centre_mm, c5.axis) + link6.d * z6;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < p6.size(); ++k) {
      const double theta6 = a6[k] + link6.theta_offset;
      const Eigen::Vector3d x6 = std::cos(theta6) * x5 + std::sin(theta6) * z6.cross(x5);
      Eigen::Matrix3d R6;
      R6 << x6, z6.cross(x6), z6;
      sum += R6.transpose() * (p6[k] - flange);
    }
    return sum / static_cast<double>(p6.size());
  };
  const TwoSweepEstimate e = from_two_sweeps(joint5, a5, joint6, a6, locate, sigma_mm);
  PointEstimate estimate;
  estimate.position_mm = e.value;
  estimate.covariance = e.covariance;
  estimate.rms_mm = e.rms_mm;
  estimate.sigma_mm = e.sigma_mm;
  estimate.sigma = estimate.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  return estimate;
}

PointEstimate tool_point_from_poses(const std::vector<Pose<double>>& world_T_flange,
                                    const std::vector<Eigen::Vector3d>& measured_mm,
                                    double sigma_mm) {
  const int n = static_cast<int>(world_T_flange.size());
  if (n < 4) throw InputError(fmt::format("a tool point needs at least 4 poses, got {}", n));
  const bool pivot = measured_mm.empty();
  if (!pivot && measured_mm.size() != world_T_flange.size())
    throw InputError(fmt::format("{} poses but {} measured points", n, measured_mm.size()));
  const int unknowns = pivot ? 6 : 3;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * n, unknowns);
  Eigen::VectorXd b(3 * n);
  for (int k = 0; k < n; ++k) {
    A.block<3, 3>(3 * k, 0) = world_T_flange[static_cast<size_t>(k)].R;
    if (pivot) A.block<3, 3>(3 * k, 3) = -Eigen::Matrix3d::Identity();
    b.segment<3>(3 * k) = (pivot ? Eigen::Vector3d::Zero() : measured_mm[static_cast<size_t>(k)]) -
                          world_T_flange[static_cast<size_t>(k)].p;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  if (svd.singularValues().minCoeff() < 1e-3 * svd.singularValues().maxCoeff())
    throw InputError(
        "the flange orientations are too alike to fix the tool point: turn the tool "
        "by tens of degrees about different axes between the poses");
  const Eigen::VectorXd x = svd.solve(b);
  const Eigen::VectorXd r = A * x - b;
  PointEstimate estimate;
  estimate.position_mm = x.head<3>();
  estimate.rms_mm = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
  estimate.sigma_mm = sigma_mm > 0 ? sigma_mm : std::sqrt(r.squaredNorm() / (r.size() - unknowns));
  const Eigen::MatrixXd cov = estimate.sigma_mm * estimate.sigma_mm * (A.transpose() * A).inverse();
  estimate.covariance = cov.topLeftCorner<3, 3>();
  estimate.sigma = estimate.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  return estimate;
}

FrameEstimate frame_from_nests(const std::vector<Eigen::Vector3d>& measured_mm,
                               const std::vector<Eigen::Vector3d>& nominal_mm, double sigma_mm) {
  const size_t n = measured_mm.size();
  if (n < 3) throw InputError(fmt::format("a frame needs at least 3 nests, got {}", n));
  if (nominal_mm.size() != n)
    throw InputError(fmt::format("{} measured nests but {} nominal ones", n, nominal_mm.size()));
  Eigen::Matrix3Xd nominal(3, static_cast<Eigen::Index>(n));
  for (size_t i = 0; i < n; ++i) nominal.col(static_cast<Eigen::Index>(i)) = nominal_mm[i];
  const Eigen::Vector3d centre = nominal.rowwise().mean();
  const Eigen::JacobiSVD<Eigen::Matrix3Xd> spread(nominal.colwise() - centre);
  if (spread.singularValues()[1] < 1e-6 * std::max(spread.singularValues()[0], 1.0))
    throw InputError("the nests lie on one line: they cannot fix a frame");
  const auto fit = [&](const Points& measured) {
    Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(n));
    for (size_t i = 0; i < n; ++i) m.col(static_cast<Eigen::Index>(i)) = measured[i];
    const Eigen::Matrix4d T = Eigen::umeyama(nominal, m, false);
    Pose<double> pose;
    pose.R = T.topLeftCorner<3, 3>();
    pose.p = T.topRightCorner<3, 1>();
    return pose;
  };
  FrameEstimate frame;
  frame.pose = fit(measured_mm);
  double sum = 0;
  for (size_t i = 0; i < n; ++i) sum += (measured_mm[i] - frame.pose * nominal_mm[i]).squaredNorm();
  frame.rms_mm = std::sqrt(sum / (3.0 * static_cast<double>(n)));
  frame.sigma_mm = sigma_mm > 0 ? sigma_mm : std::sqrt(sum / (3.0 * static_cast<double>(n) - 6));
  frame.covariance = propagate(
      measured_mm, [&](const Points& p) -> Eigen::VectorXd { return pose_values(fit(p)); },
      frame.sigma_mm);
  finish(frame);
  return frame;
}

}  // namespace robcal::campaign
