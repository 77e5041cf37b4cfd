#include "robcal/compensate/corrected_targets.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <variant>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/kinematics/parameter_jacobian.hpp"

namespace robcal {
namespace {

/// χ²(3 degrees of freedom) at 95 %: a 3-D Gaussian lies within √(7.815·σ²) of its mean
/// along its longest axis with 95 % probability (conservative for the other axes).
constexpr double kChiSquare3Dof95 = 7.814727903;

}  // namespace

std::optional<double> position_confidence95_mm(const CalibratedRobot& robot,
                                               const PointMass& payload,
                                               const Pose<double>& flange_T_tcp,
                                               const Vector6d& joints) {
  if (robot.covariance.rows() != kParameterCount || robot.covariance.cols() != kParameterCount)
    return std::nullopt;
  Eigen::Vector3d p;
  PositionJacobian J;
  target_position_jacobian_autodiff(robot.model, payload, robot.params, joints, flange_T_tcp.p, &p,
                                    &J);
  const Eigen::Matrix3d S = J * robot.covariance * J.transpose();
  const double largest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(S).eigenvalues().maxCoeff();
  return std::sqrt(kChiSquare3Dof95 * std::max(largest, 0.0));
}

std::vector<CorrectedTarget> correct_targets(const Compensator& comp, const CalibratedRobot& robot,
                                             const std::vector<WantedTarget>& wanted,
                                             const std::string& file, IkMethod method) {
  return correct_targets(std::vector<const Compensator*>(wanted.size(), &comp), robot, wanted, file,
                         method);
}

std::vector<CorrectedTarget> correct_targets(const std::vector<const Compensator*>& comps,
                                             const CalibratedRobot& robot,
                                             const std::vector<WantedTarget>& wanted,
                                             const std::string& file, IkMethod method) {
  std::vector<CorrectedTarget> out;
  Vector6d previous = Vector6d::Zero();  // home
  for (size_t i = 0; i < wanted.size(); ++i) {
    const WantedTarget& w = wanted[i];
    const Compensator& comp = *comps.at(i);
    const SourceLocation where{file, w.line, 0, w.name};
    // Without a configuration: the branch of the nominal solution nearest the previous joints.
    ArmConfig config;
    if (w.config) {
      config = *w.config;
    } else {
      const IkResult all = nominal_ik(
          comp.geometry, comp.world_T_base.inverse() * w.world_T_tcp * comp.flange_T_tcp.inverse(),
          previous);
      const IkSolution* nearest = nearest_solution(all, previous);
      if (!nearest)
        throw InputError(where, fmt::format("unreachable: the nominal inverse has no solution ({})",
                                            to_string(all.status)));
      config = nearest->config;
    }
    CorrectedTarget t;
    t.name = w.name;
    t.config = config;
    t.condition = comp.condition;
    t.ik = calibrated_ik(comp, w.world_T_tcp, config, previous, method);
    if (!t.ik.ok())
      throw InputError(where,
                       fmt::format("cannot correct in configuration {}: {} ({} iterations, "
                                   "{:.3g} mm and {:.3g} deg from the pose)",
                                   config.label(), to_string(t.ik.status), t.ik.iterations,
                                   t.ik.position_error_mm, rad2deg(t.ik.orientation_error_rad)));
    t.base_T_tcp_nominal = nominal_tcp_pose(comp, t.ik.joints);
    t.confidence95_mm =
        position_confidence95_mm(robot, comp.condition.payload, comp.flange_T_tcp, t.ik.joints);
    previous = t.ik.joints;
    out.push_back(std::move(t));
  }
  return out;
}

std::string corrected_targets_csv(const std::vector<CorrectedTarget>& rows, const RobotModel& model,
                                  bool with_conditions) {
  const auto labels = euler_labels(model.euler);
  // The warm-up time only when a row was corrected for one: the files of runs without a warm-up
  // stay as they were.
  const bool with_time =
      with_conditions && std::any_of(rows.begin(), rows.end(), [](const auto& r) {
        return r.condition.warmup_time_s.has_value();
      });
  std::string out = fmt::format(
      "name,config,j1,j2,j3,j4,j5,j6,x,y,z,qw,qx,qy,qz,{},{},{},iterations,residual_mm,"
      "confidence95_mm{}{}\n",
      labels[0], labels[1], labels[2], with_conditions ? ",approach,temperature,payload" : "",
      with_time ? ",time_s" : "");
  // The condition in the targets file's own notation (io/pose_list_file.hpp).
  const auto condition = [&](const ReachCondition& c) {
    if (!with_conditions) return std::string();
    std::string text =
        fmt::format(",{},{:.6g},{}", approach_text(c.approach),
                    model.reference_temperature_c + c.temperature_rise_k, c.payload_name);
    if (with_time)
      text += !c.warmup_time_s               ? ","
              : std::isinf(*c.warmup_time_s) ? fmt::format(",{}", kWarmCell)
                                             : fmt::format(",{:.10g}", *c.warmup_time_s);
    return text;
  };
  for (const CorrectedTarget& r : rows) {
    const Eigen::Quaterniond q = to_quaternion(r.base_T_tcp_nominal.R);
    const Eigen::Vector3d euler = euler_angles_deg(r.base_T_tcp_nominal.R, model.euler);
    const Vector6d j = r.ik.joints * kRadToDeg;
    const Eigen::Vector3d& p = r.base_T_tcp_nominal.p;
    out += fmt::format(
        "{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},"
        "{:.10f},{:.10f},{:.10f},{:.10f},{:.6f},{:.6f},{:.6f},{},{:.3g},{}{}\n",
        r.name, r.config.label(), j[0], j[1], j[2], j[3], j[4], j[5], p.x(), p.y(), p.z(), q.w(),
        q.x(), q.y(), q.z(), euler[0], euler[1], euler[2], r.ik.iterations, r.ik.position_error_mm,
        r.confidence95_mm ? fmt::format("{:.4f}", *r.confidence95_mm) : "", condition(r.condition));
  }
  return out;
}

namespace {

/// A joint that moves less than this between two points stays on the side it was (rad).
constexpr double kStillRad = 1e-9;

/// How near the previous corrected target a target must be for the calibrated inverse to start
/// from the previous joints on a general 6R arm (make_program_corrector).
constexpr double kContinuationMm = 50.0;
constexpr double kContinuationRad = 0.35;  // 20°

/// Configuration data of one target, at most six integers, held without allocating (it is
/// computed for every candidate solution of every target of a program).
class ConfigurationData {
 public:
  ConfigurationData(std::initializer_list<int> values) : size_(values.size()) {
    std::copy(values.begin(), values.end(), values_.begin());
  }
  int operator[](size_t k) const { return values_[k]; }
  bool operator==(const std::vector<int>& other) const {
    return other.size() == size_ && std::equal(other.begin(), other.end(), values_.begin());
  }
  [[nodiscard]] std::vector<int> vector() const {
    return {values_.begin(), values_.begin() + static_cast<std::ptrdiff_t>(size_)};
  }

 private:
  std::array<int, 6> values_{};
  size_t size_;
};

/// maker_configuration of joints whose arm configuration is known (a labelled IK solution):
/// no forward kinematics.
ConfigurationData configuration_data(ProgramLanguage language, const Vector6d& joints,
                                     const ArmConfig& config) {
  if (language == ProgramLanguage::Rapid) {
    // Quadrant of a joint; the tolerance keeps an exact 0° (or 90°...) that the closed form
    // returns as −1e-14 in the quadrant above, as it was written.
    const auto quadrant = [&](int i) {
      return static_cast<int>(std::floor(rad2deg(joints[i]) / 90.0 + 1e-9));
    };
    return {quadrant(0), quadrant(3), quadrant(5), config.index()};
  }
  if (language == ProgramLanguage::FanucLs) {
    // CONFIG 'N|F U|D T|B, t4, t5, t6': turn t of a joint at θ is θ ∈ [−180 + 360t, 180 + 360t).
    const auto turn = [&](int i) {
      return static_cast<int>(std::floor((rad2deg(joints[i]) + 180.0) / 360.0 + 1e-12));
    };
    return {
        config.flip ? 1 : 0, config.down ? 1 : 0, config.back ? 1 : 0, turn(3), turn(4), turn(5)};
  }
  if (language == ProgramLanguage::Jbi) {
    // ///RCONF l,m,n,o,p,q: 0 flip / 1 no-flip, 0 upper / 1 lower arm, 0 front / 1 rear, then
    // R (axis 4), T (axis 6), S (axis 1) below 180° in magnitude (0) or not (1).
    const auto beyond = [&](int i) { return std::abs(rad2deg(joints[i])) >= 180.0 - 1e-9 ? 1 : 0; };
    return {config.flip ? 0 : 1, config.down ? 1 : 0, config.back ? 1 : 0,
            beyond(3),           beyond(5),           beyond(0)};
  }
  int s = (config.back ? 1 : 0) | (config.down ? 0 : 2) | (joints[4] <= 0 ? 4 : 0);
  int t = 0;
  for (int i = 0; i < kJointCount; ++i)
    if (joints[i] < 0) t |= 1 << i;
  return {s, t};
}

/// The arm branch the written configuration data names: RAPID cfx, Fanuc's letters, Yaskawa's
/// first three flags; none for KRL (S leaves flip to the wrist's sign) and URScript.
std::optional<ArmConfig> written_branch(ProgramLanguage language, const std::vector<int>& config) {
  if (config.empty()) return std::nullopt;
  if (language == ProgramLanguage::Rapid && config.size() == 4 && config[3] >= 0 && config[3] <= 7)
    return ArmConfig{(config[3] & 4) != 0, (config[3] & 2) != 0, (config[3] & 1) != 0};
  if (language == ProgramLanguage::FanucLs && config.size() >= 3)
    return ArmConfig{config[2] != 0, config[1] != 0, config[0] != 0};
  if (language == ProgramLanguage::Jbi && config.size() >= 3)
    return ArmConfig{config[2] != 0, config[1] != 0, config[0] == 0};
  return std::nullopt;
}

}  // namespace

std::vector<int> maker_configuration(const Compensator& comp, ProgramLanguage language,
                                     const Vector6d& joints) {
  return configuration_data(language, joints, arm_config(comp.model, joints)).vector();
}

PointCorrector make_program_corrector(const Compensator& comp, ProgramLanguage language,
                                      const CalibratedRobot* robot,
                                      ApproachCompensators by_approach) {
  // The previous point's joints: the branch of KRL points without S/T; and its target, when it
  // was corrected (the continuation below); the side each joint reached it from.
  auto previous = std::make_shared<Vector6d>(Vector6d::Zero());
  auto previous_target = std::make_shared<std::optional<Pose<double>>>();
  auto previous_side = std::make_shared<std::optional<Vector6d>>();
  const bool general_arm = std::holds_alternative<General6rGeometry>(comp.geometry);
  return [&comp, language, robot, previous, previous_target, previous_side, general_arm,
          by_approach = std::move(by_approach)](const ProgramPoint& point) {
    CorrectedPoint out;
    // The side each joint reaches the point from (docs/method/10-compensation.md §6): the
    // sign of its move from the previous point; a joint that does not move stays on its
    // side; the first point, the run's.
    const auto side_of = [&](const Vector6d& joints) {
      if (!previous_side->has_value()) return Vector6d(comp.condition.approach);
      Vector6d side = **previous_side;
      for (int i = 0; i < kJointCount; ++i) {
        const double move = joints[i] - (*previous)[i];
        if (std::abs(move) > kStillRad) side[i] = move > 0 ? 1.0 : -1.0;
      }
      return side;
    };
    Vector6d side = comp.condition.approach;
    // The calibrated inverse `iterate` under the run's condition, or with `by_approach`
    // under the side of the move: guessed from the seed, checked on the answer (the two
    // differ for a joint that moves less than the calibration changes it).
    const auto calibrated = [&](const auto& iterate, const Vector6d& seed) {
      if (!by_approach) return iterate(comp);
      side = side_of(seed);
      CalibratedIkResult r = iterate(by_approach(side));
      if (r.ok() && side_of(r.joints) != side) {
        side = side_of(r.joints);
        r = iterate(by_approach(side));
      }
      return r;
    };
    Pose<double> base_T_tcp;
    Vector6d near;
    ArmConfig branch{};
    // A point for another tool Tk is the flange pose X·Tk⁻¹: solved as the compensator's TCP
    // T0 at X·Tk⁻¹·T0, and written back as the nominal flange pose times Tk.
    const Pose<double> tool_shift =
        point.flange_T_tcp ? point.flange_T_tcp->inverse() * comp.flange_T_tcp : Pose<double>{};
    // The calibrated answer `r` of the target `base_T_tcp` in `branch`, written back.
    const auto finish = [&](const CalibratedIkResult& r, const ArmConfig& branch,
                            const Pose<double>& target) {
      if (!r.ok()) {
        previous_target->reset();
        out.failure = fmt::format("cannot correct: {} ({:.3g} mm from the pose)",
                                  to_string(r.status), r.position_error_mm);
        return out;
      }
      *previous = r.joints;
      *previous_target = target;
      *previous_side = side;
      out.joints_deg = r.joints * kRadToDeg;
      out.base_T_tcp = nominal_tcp_pose(comp, r.joints) * tool_shift.inverse();
      if (robot)
        out.confidence95_mm =
            position_confidence95_mm(*robot, comp.condition.payload,
                                     point.flange_T_tcp.value_or(comp.flange_T_tcp), r.joints);
      if (!point.is_joint_target && !point.config.empty())
        out.config = configuration_data(language, r.joints, branch).vector();
      return out;
    };
    if (point.is_joint_target) {
      near = point.joints_deg * kDegToRad;
      base_T_tcp = nominal_tcp_pose(comp, near);
      branch = arm_config(comp.model, near);
    } else {
      base_T_tcp = point.base_T_tcp * tool_shift;
      const Pose<double> base_T_flange = base_T_tcp * comp.flange_T_tcp.inverse();
      // The written branch solved alone (its turn nearest the previous joints) when the
      // configuration names it: when its turns are the written ones too, no other solution
      // can score better below.
      const IkSolution* best = nullptr;
      const std::optional<ArmConfig> written = written_branch(language, point.config);
      // On a general 6R arm the nominal inverse (every real solution, ≈ 150 µs) is most of a
      // target's cost, and a program's targets usually follow each other: Newton on the
      // calibrated model from the previous target's joints, kept only when that target was
      // near (a small move cannot jump to another solution of the same written configuration)
      // and the answer has the written configuration, branch and turns.
      if (general_arm && written && previous_target->has_value() &&
          (base_T_tcp.p - (*previous_target)->p).norm() < kContinuationMm &&
          Eigen::AngleAxisd((*previous_target)->R.transpose() * base_T_tcp.R).angle() <
              kContinuationRad) {
        const CalibratedIkResult r = calibrated(
            [&](const Compensator& c) {
              return calibrated_ik_newton(c, c.world_T_base * base_T_tcp, *previous);
            },
            *previous);
        if (r.ok() && arm_config(comp.model, r.joints) == *written &&
            configuration_data(language, r.joints, *written) == point.config)
          return finish(r, *written, base_T_tcp);
      }
      const IkBranchResult alone =
          written ? nominal_ik_branch(comp.geometry, base_T_flange, *written, *previous)
                  : IkBranchResult{};
      if (alone.status == IkStatus::Solved &&
          configuration_data(language, alone.solution.joints, alone.solution.config) ==
              point.config)
        best = &alone.solution;
      if (best) {
        near = best->joints;
        branch = best->config;
      } else {
        // Initialised in place: IkResult's unused entries are never copied (they hold no
        // values).
        const IkResult all = nominal_ik(comp.geometry, base_T_flange, *previous);
        // The written configuration: the branch must match, the turns should.
        int best_score = -1;
        for (const IkSolution& s : all) {
          // The solver labels its solutions: no forward kinematics per candidate.
          const ConfigurationData cfg = configuration_data(language, s.joints, s.config);
          int score = 0;
          if (point.config.empty()) {
            score = 1;
          } else {
            // The branch: RAPID cfx, KRL S, Fanuc's three letters, Yaskawa's first three flags.
            const auto same = [&](size_t k) { return cfg[k] == point.config[k]; };
            const bool three =
                language == ProgramLanguage::FanucLs || language == ProgramLanguage::Jbi;
            if (language == ProgramLanguage::Rapid ? !same(3)
                : three                            ? !(same(0) && same(1) && same(2))
                                                   : !same(0))
              continue;
            score = cfg == point.config ? 2 : 1;
          }
          if (score > best_score ||
              (score == best_score &&
               (s.joints - *previous).squaredNorm() < (best->joints - *previous).squaredNorm())) {
            best = &s;
            best_score = score;
          }
        }
        if (!best) {
          out.failure =
              point.config.empty()
                  ? fmt::format("unreachable for the nominal robot ({})", to_string(all.status))
                  : fmt::format("no nominal solution with the written configuration [{}]",
                                fmt::join(point.config, ","));
          previous_target->reset();
          return out;
        }
        near = best->joints;
        branch = best->config;
      }
    }
    // `near` is the nominal solution of `branch`: the seed of the calibrated inverse.
    return finish(calibrated(
                      [&](const Compensator& c) {
                        return calibrated_ik_from_seed(c, c.world_T_base * base_T_tcp, branch,
                                                       near);
                      },
                      near),
                  branch, base_T_tcp);
  };
}

}  // namespace robcal
