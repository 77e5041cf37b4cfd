#pragma once
/// \file
/// Where a closed-form inverse puts its candidates (parallel_axes_ik.cpp, general_6r_ik.cpp):
/// MDH link angles to controller joints, every turn inside the limits into an array, or per
/// branch only the turn nearest the seed. Internal to src/kinematics.

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "robcal/kinematics/closed_form_joints.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"

namespace robcal {

inline constexpr double kIkTwoPi = 2.0 * std::numbers::pi;
/// Turns are counted by multiplying with 1/(2π) rather than dividing by 2π (a division per joint
/// and limit was most of a solution's cost): a count off by one at an exact multiple moves the
/// joint by rounding only, which the limit tolerance absorbs.
inline constexpr double kIkInvTwoPi = 0.5 / std::numbers::pi;
inline constexpr double kIkLimitTolerance = 1e-9;  // rad, as RobotModel::within_limits

/// Where the candidates go: every turn inside the limits into an array, or per branch only the
/// turn nearest the seed; counts the branches that reach the pose before the limits.
class IkSink {
 public:
  IkSink(const ClosedFormJoints& joints, const Vector6d& seed, IkSolution* solutions, int capacity,
         bool nearest_turn_only)
      : joints_(joints),
        seed_(seed),
        solutions_(solutions),
        capacity_(capacity),
        nearest_turn_only_(nearest_turn_only) {}

  void add(const std::array<double, kJointCount>& theta, const ArmConfig& config,
           bool wrist_singular, bool shoulder_singular) {
    ++branches_reached_;
    Vector6d j = controller_from_link_angles(joints_, theta);
    // Each joint to its lowest turn at or above the lower limit; the further turns that fit.
    std::array<int, kJointCount> turns{};
    for (int i = 0; i < kJointCount; ++i) {
      const double lower = joints_.limits[i].lower - kIkLimitTolerance;
      const double upper = joints_.limits[i].upper + kIkLimitTolerance;
      j[i] -= kIkTwoPi * std::floor((j[i] - lower) * kIkInvTwoPi);
      if (!(j[i] <= upper)) return;  // NaN is outside
      turns[i] = 1 + static_cast<int>(std::floor((upper - j[i]) * kIkInvTwoPi));
      if (nearest_turn_only_) {
        const double k = std::floor((seed_[i] - j[i]) * kIkInvTwoPi + 0.5);
        j[i] += kIkTwoPi * std::clamp(k, 0.0, static_cast<double>(turns[i] - 1));
        turns[i] = 1;
      }
    }
    // Every combination of the turns, joint 0 fastest.
    std::array<int, kJointCount> k{};
    while (true) {
      if (count_ == capacity_) {
        truncated_ = true;
        return;
      }
      IkSolution& s = solutions_[count_++];
      s.joints = j;
      for (int i = 0; i < kJointCount; ++i) s.joints[i] += kIkTwoPi * k[i];
      s.config = config;
      s.wrist_singular = wrist_singular;
      s.shoulder_singular = shoulder_singular;
      int i = 0;
      while (i < kJointCount && ++k[i] == turns[i]) k[i++] = 0;
      if (i == kJointCount) return;
    }
  }

  [[nodiscard]] IkStatus status() const {
    if (truncated_) return IkStatus::Truncated;
    if (branches_reached_ == 0) return IkStatus::Unreachable;
    if (count_ == 0) return IkStatus::OutsideLimits;
    return IkStatus::Solved;
  }
  [[nodiscard]] int count() const { return count_; }
  /// Count, branches reached and status into `result`, whose array this sink filled.
  void finish(IkResult& result) const {
    result.count = count_;
    result.branches_reached = branches_reached_;
    result.status = status();
  }
  [[nodiscard]] int branches_reached() const { return branches_reached_; }

 private:
  const ClosedFormJoints& joints_;
  const Vector6d& seed_;
  IkSolution* solutions_;
  int capacity_;
  bool nearest_turn_only_;
  int count_ = 0, branches_reached_ = 0;
  bool truncated_ = false;
};

}  // namespace robcal
