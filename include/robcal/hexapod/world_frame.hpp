#pragma once
/// \file
/// The world frame from the three base cups, and the set-up that places them
/// (docs/method/08-world-frame.md §1–§2).
///
/// The robot puts a setting ball (its TCP) at three points 300 mm apart according to its own
/// model, p1..p3 (robot frame); the cups snap on and are locked; the ballbar then measures the
/// true sides. The triangle q1..q3 built from those sides is fitted to the p's in their plane by a
/// planar rigid transform (x, y, φ), Gauss–Newton from the identity on the 6×3 system; the world
/// frame is the base fixture frame of the corrected points T·q_i.

#include <Eigen/Core>
#include <array>

#include "robcal/hexapod/fixture.hpp"

namespace robcal::hexapod {

struct WorldFrameFit {
  Pose<double> robot_T_fixture;  ///< base fixture frame (the world) in the robot frame
  Cups<double> corrected;        ///< T·q_i in the robot frame, mm
  Eigen::Vector3d planar = Eigen::Vector3d::Zero();  ///< x, y (mm), φ (rad) in the plane of the p's
  double rms_mm = 0;  ///< √(Σ|p_i − T·q_i|² / 3) at the optimum
  int iterations = 0;
  bool converged = false;
};

/// Fits the measured triangle (ballbar sides) to the points the robot placed the cups at.
/// Throws InputError when the sides make no triangle or the points are collinear.
WorldFrameFit fit_world_frame(const Cups<double>& robot_points, const TriangleSides& measured);

/// Where the robot must put the setting ball: the three points of an equilateral triangle of
/// side `side_mm` centred on the rough base-fixture placement `robot_T_rough` (its xy plane is the
/// cup plane, z up): in that frame c1 = (−s/2, −s/(2√3), 0), c2 = (s/2, −s/(2√3), 0),
/// c3 = (0, s/√3, 0), counter-clockwise seen from above; returned in the robot frame.
Cups<double> setting_ball_points(const Pose<double>& robot_T_rough, double side_mm);

/// Where the robot must put the setting ball for a fourth base cup B4 given by its distances
/// d14, d24, d34 to B1..B3: on the triangle of `points` (the setting points of B1..B3, robot
/// frame) as fixture_cup_positions places it (fixture.hpp). B1..B3 keep defining the world frame.
Eigen::Vector3d fourth_setting_ball_point(const Cups<double>& points,
                                          const std::array<double, 3>& base_cup4_mm);

}  // namespace robcal::hexapod
