#pragma once
/// \file
/// Which hexapod poses can be set up physically (issue 20): a tool cup must not sit on or bump
/// into a base cup, and the ballbar of each leg must leave both fixtures on the side their cups
/// open to and must not run into a third cup. The planned poses of docs/method/07-hexapod.md §3 are
/// computed for points; with a tool triangle as large as the base one, most of them put a tool cup
/// on a base cup.

#include <Eigen/Core>

#include <string>
#include <vector>

#include "robcal/hexapod/poses.hpp"

namespace robcal::hexapod {

struct CupClearance {
  double cup_diameter_mm = 25;  ///< outer diameter of a magnetic cup (two cups closer collide)
};

/// Empty when the configuration can be set up; otherwise the first reason it cannot, naming the
/// cups and the leg: a tool cup within a cup diameter of a base cup, a leg going through its
/// base fixture (tool cup on the closed side of the base plane) or through its tool fixture
/// (base cup on the closed side of the tool plane), or a leg passing within a cup radius of a
/// cup other than its two ends. Cups in one frame; the fixture planes are those of cups 1..3,
/// the cups opening towards +z of frame_from_cups (fixture.hpp).
std::string cup_collision(const std::vector<Eigen::Vector3d>& base_cups,
                          const std::vector<Eigen::Vector3d>& tool_cups,
                          const std::vector<PhysicalLeg>& legs, const CupClearance& clearance);

/// The poses that survive pruning and those refused, with the reason.
struct PoseScreening {
  std::vector<HexapodPose> kept;
  struct Refused {
    HexapodPose pose;
    std::string reason;
  };
  std::vector<Refused> refused;
};

/// Refuses the poses that cannot be set up (cup_collision with the base cups of `geometry` and
/// the pose's tool cups, fourth ones included, with all its legs), then prunes the others as
/// prune_redundant does (a refused pose cannot make another redundant). Throws InputError when a
/// fixture's sides do not make a triangle, the clearance is not a positive length or a fourth
/// cup is within a cup diameter of another of its fixture (key "--tool-cup4-mm" or
/// "--base-cup4-mm").
PoseScreening screen_poses(const std::vector<HexapodPose>& poses, const HexapodGeometry& geometry,
                           double max_angle_rad, double max_distance_mm,
                           const CupClearance& clearance);

}  // namespace robcal::hexapod
