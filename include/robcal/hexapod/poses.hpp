#pragma once
/// \file
/// The measurable poses of the ballbar hexapod (docs/method/07-hexapod.md §3): with every leg at
/// the ballbar's nominal length, 4 assembly modes × 3 rotations of the tool fixture (0, ±120° about
/// its normal) × 6 permutations of the base cups = 72 poses of the tool fixture relative to the
/// base fixture; poses closer than given orientation and position distances to an earlier one are
/// redundant and pruned.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "robcal/hexapod/direct_kinematics.hpp"

namespace robcal::hexapod {

/// The measured fixtures and the ballbar's nominal length (mm).
struct HexapodGeometry {
  TriangleSides base{300, 300, 300};  ///< b12, b23, b31
  TriangleSides tool{150, 150, 150};  ///< t12, t23, t31
  double leg_mm = 300;                ///< every leg at this length in a planned pose
  /// A fourth tool cup T4 (issue 20): its distances d14, d24, d34 to T1..T3 (fixture_cup_positions
  /// places it). Its legs are extra legs of the poses where they fit the gauge
  /// (add_fourth_cup_legs); the design of each pose stays on T1..T3.
  std::optional<std::array<double, 3>> tool_cup4_mm{};
  /// A fourth base cup B4: its distances d14, d24, d34 to B1..B3, as T4's. B1..B3 still define
  /// the base fixture frame (the world); B4's legs are extra legs like T4's.
  std::optional<std::array<double, 3>> base_cup4_mm{};
  [[nodiscard]] FixtureDistances tool_fixture() const { return {tool, tool_cup4_mm}; }
  [[nodiscard]] FixtureDistances base_fixture() const { return {base, base_cup4_mm}; }
};

/// Throws InputError naming the setting (`--base-mm`, `--tool-mm`, `--leg-mm`, `--tool-cup4-mm`,
/// `--base-cup4-mm`) when a fixture's sides make no triangle, a fourth cup is collinear with two
/// others or no
/// point has its distances, or the ballbar length is not positive: every workflow that plans with
/// a geometry checks it here first.
void check_geometry(const HexapodGeometry& geometry);

/// One leg between physical cups (0-based: base cup B(base+1), tool cup T(tool+1)).
struct PhysicalLeg {
  int base = 0;
  int tool = 0;
  /// "B1-T2": the cups' labels, as plan files and session prompts write them.
  [[nodiscard]] std::string name() const;
};

struct HexapodPose {
  int index = 0;             ///< 1-based position in the enumeration (1..72)
  std::string label;         ///< "P01".."P72"
  int mode = 0;              ///< assembly mode 1..4
  int rotation_deg = 0;      ///< tool fixture rotation: 0, -120 or 120 (of the labels
                             ///< T1 T3 T2 when design.tool_mirrored())
  LegDesign design;          ///< physical cup of each design role
  Cups<double> tool_cups;    ///< physical T1..T3 in the base fixture frame, mm
  Pose<double> base_T_tool;  ///< tool fixture frame in the base fixture frame
  /// The six legs of the design in measurement order (kDesignLegs), then the extra legs to a
  /// fourth cup on either fixture (add_fourth_cup_legs).
  std::vector<PhysicalLeg> legs;

  /// "mode 2, tool −120°, base B2 B1 B3" (the physical cups in the design roles B1, B2, B3).
  [[nodiscard]] std::string description() const;
};

/// Which relabellings of the tool cups enumerate_poses uses for each assembly mode.
enum class ToolRelabelling {
  /// Rotations, or rotations of the mirrored numbering (odd permutations), whichever makes the
  /// tool cups face the base cups (fixture normal towards the base cups' centroid): every pose
  /// can be set up with cups on one face of the tool plate (docs/method/07-hexapod.md §3).
  FacingBase,
  /// Rotations of the tool fixture only. In assembly modes 1 and 3 these put the tool cups facing
  /// away from the base: every leg would go through the tool plate (cup_collision.hpp). Kept to
  /// show why FacingBase is the default.
  Rotations,
};

/// The 72 poses (fewer if some assembly mode has no real solution for these fixtures), in the
/// order mode, rotation (0, −120, +120), base permutation (lexicographic).
/// Throws InputError when a fixture's sides do not make a triangle.
std::vector<HexapodPose> enumerate_poses(const HexapodGeometry& geometry,
                                         ToolRelabelling relabelling = ToolRelabelling::FacingBase);

/// Keeps each pose unless an already kept one is both within `max_angle_rad` in orientation and
/// `max_distance_mm` between the tool-fixture centroids (docs/method/07-hexapod.md §3 defaults:
/// 30°, 50 mm).
std::vector<HexapodPose> prune_redundant(const std::vector<HexapodPose>& poses,
                                         double max_angle_rad, double max_distance_mm);

/// The physical tool cups (base fixture frame) of the pose with every leg at `leg_mm`, for the
/// physical cups `base` and `tool` (fixture frames), a leg design and an assembly mode; nullopt
/// when that mode has no real solution.
std::optional<Cups<double>> planned_tool_cups(const Cups<double>& base, const Cups<double>& tool,
                                              const LegDesign& design, int mode, double leg_mm);

/// The leg design a pose's first six physical legs (measurement order) follow, or nullopt when
/// there are fewer or they do not follow design 1^12 2^123 3^1 with one cup per role (the legs
/// after them are extra).
std::optional<LegDesign> design_of_legs(const std::vector<PhysicalLeg>& legs);

/// The physical tool cups of a pose in the base fixture frame: T1..T3, then T4 when the geometry
/// has one (carried by the pose's tool fixture frame).
std::vector<Eigen::Vector3d> pose_tool_cups(const HexapodPose& pose,
                                            const HexapodGeometry& geometry);

/// The base cups in the base fixture frame: B1..B3, then B4 when the geometry has one.
std::vector<Eigen::Vector3d> base_cup_positions(const HexapodGeometry& geometry);

/// Adds to each pose the legs from B1..B3 to a fourth tool cup, then those from a fourth base cup
/// to T1..T3 (and T4), whose planned length is within `tolerance_mm` of the ballbar's length
/// (those the gauge reads with the robot's errors on top). With T4 on the circumcircle of T1..T3
/// the base cup of design role B2 — at the ballbar's length from all three tool cups, so on the
/// tool triangle's axis — reaches T4 in every pose; likewise the tool cup of design role T1
/// reaches a B4 on the circumcircle of B1..B3.
void add_fourth_cup_legs(std::vector<HexapodPose>& poses, const HexapodGeometry& geometry,
                         double tolerance_mm);

/// Physical tool cups (base fixture frame) from a DKP solution in design roles.
Cups<double> physical_tool_cups(const LegDesign& design, const Cups<double>& design_tool);

/// Design-role base cups and tool sides for a leg design (what the DKP needs).
Cups<double> design_base_cups(const LegDesign& design, const Cups<double>& physical_base);
TriangleSides design_tool_sides(const LegDesign& design, const Cups<double>& physical_tool);

}  // namespace robcal::hexapod
