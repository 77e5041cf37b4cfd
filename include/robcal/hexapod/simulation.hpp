#pragma once
/// \file
/// A simulated hexapod cell (docs/method/08-world-frame.md §1–§3, published procedure): a true
/// robot (sim/true_robot.hpp) places the base cups with a setting ball where its nominal model
/// says, the ballbar (measure/instrument.hpp: σ and ±range) measures the fixture sides and the
/// legs. Everything the operator would not know — the true cup positions, the true fixture sides —
/// stays in the cell for the simulation to use and the pipeline never sees.
///
/// Frames: the simulation world is the truth's world (the laser tracker's); the robot frame is
/// the nominal model's; the hexapod world is the base fixture frame fitted from the cups.

#include <optional>
#include <random>
#include <string>

#include "robcal/hexapod/measurement.hpp"
#include "robcal/hexapod/planning.hpp"
#include "robcal/hexapod/poses.hpp"
#include "robcal/hexapod/session.hpp"
#include "robcal/hexapod/world_frame.hpp"
#include "robcal/sim/true_robot.hpp"

namespace robcal::hexapod {

struct HexapodCellOptions {
  HexapodGeometry design;              ///< nominal fixtures and the ballbar's set-up length
  double fixture_tolerance_mm = 0.05;  ///< true fixture sides within ± this of the design
  Pose<double> placement;              ///< rough base-fixture placement (cup centroid), robot frame
  double tool_offset_mm = 100;         ///< tool fixture centroid along the flange z
  double ball_offset_mm = 100;         ///< setting ball along the flange z
  double table_z_mm = 0;
  double sigma_mm = 0.00051;  ///< ballbar σ (docs/method/06-instruments.md §1)
  double range_mm = 1.0;      ///< ballbar range about its set-up length
};

struct SimulatedHexapodCell {
  TrueRobot truth;
  RobotModel nominal;  ///< the robot file the operator uses
  HexapodCellOptions options;
  CellSetup cell;              ///< as the operator knows it: fitted world frame, nominal tool mount
  Cups<double> base_cups_sim;  ///< true cup centres, simulation world frame
  std::optional<Eigen::Vector3d> base_cup4_sim{};     ///< a true fourth base cup, simulation world
  Cups<double> tool_cups_flange;                      ///< true tool cups, flange frame
  std::optional<Eigen::Vector3d> tool_cup4_flange{};  ///< a true fourth tool cup, flange frame
  Cups<double> setting_points;  ///< p_i: where the nominal model put the ball, robot frame
  std::optional<Eigen::Vector3d> setting_point4{};      ///< … for a fourth base cup
  TriangleSides base_sides;                             ///< measured with the ballbar
  TriangleSides tool_sides;                             ///< measured with the ballbar
  std::optional<std::array<double, 3>> tool_cup4_mm{};  ///< T4's d14, d24, d34, measured
  std::optional<std::array<double, 3>> base_cup4_mm{};  ///< B4's d14, d24, d34, measured
  [[nodiscard]] FixtureDistances base_fixture() const { return {base_sides, base_cup4_mm}; }
  WorldFrameFit world;       ///< robot_T_world from p_i and the measured base sides
  Pose<double> world_T_sim;  ///< true base fixture frame ← simulation world
};

/// A true robot with random errors (sim/true_robot.hpp) levelled on its table: base tilts zero,
/// so gravity is along its base z as the relative model assumes; it carries `payload`.
TrueRobot levelled_random_truth(const RobotModel& model, const PointMass& payload,
                                const ErrorBounds& errors, std::mt19937_64& rng);

/// Places the base cups with the true robot (nominal inverse kinematics of the setting-ball
/// points, the configuration nearest the joints' zero; a fourth base cup at its own setting point,
/// fourth_setting_ball_point), measures the fixture sides (and fourth cups' distances, each at
/// its design length) and fits the world frame on B1..B3. Throws InputError when a setting point
/// cannot be reached or a fourth cup's distance is out of the ballbar's range.
SimulatedHexapodCell set_up_simulated_cell(const TrueRobot& truth, const RobotModel& nominal,
                                           const HexapodCellOptions& options, std::mt19937_64& rng);

/// One leg's reading with the true robot at `joints`, or nullopt when out of the ballbar's range.
std::optional<double> simulate_leg(const SimulatedHexapodCell& cell, const PhysicalLeg& leg,
                                   const Vector6d& joints, std::mt19937_64& rng);

/// What the operator reads at a session step in this cell: the fixture sides measured at set-up,
/// a leg (nullopt: out of range) with the true robot at the configuration's planned joints, or
/// the ballbar on its calibrator (its set-up length within σ). Throws InputError when a leg step's
/// configuration has no joints.
std::optional<double> simulate_session_reading(const SimulatedHexapodCell& cell,
                                               const SessionPlan& plan, const SessionStep& step,
                                               std::mt19937_64& rng);

/// Laser-tracker validation readings (docs/method/09-validation.md §1): random configurations in
/// the published joint box (sim/simulator.hpp), the tracker (σ per axis) reading a point of the
/// tool given in the flange frame of the true robot, registered on the base cups: base fixture
/// frame.
struct TrackerValidation {
  std::vector<Vector6d> joints;  ///< controller, rad
  Eigen::Matrix3Xd measured;     ///< base fixture frame, mm
};
TrackerValidation simulate_tracker_validation(const SimulatedHexapodCell& cell,
                                              const Eigen::Vector3d& point_flange, int count,
                                              double sigma_mm, std::mt19937_64& rng);

/// Readings of the six design legs of `pose` with the true robot at `joints` (controller, rad), in
/// measurement order, or nullopt with `out_of_range` set to the first leg the ballbar cannot
/// read (0..5).
std::optional<LegLengths<double>> simulate_legs(const SimulatedHexapodCell& cell,
                                                const HexapodPose& pose, const Vector6d& joints,
                                                std::mt19937_64& rng, int* out_of_range = nullptr);

/// One configuration's readings of every leg of `pose` (the design's, then those to a fourth cup)
/// with the true robot at `joints`, labelled `config`; nullopt when any leg is out of the
/// ballbar's range (the session then retries the whole configuration).
std::optional<LegReadings> simulate_pose_readings(const SimulatedHexapodCell& cell,
                                                  const HexapodPose& pose, std::string config,
                                                  const Vector6d& joints, std::mt19937_64& rng);

}  // namespace robcal::hexapod
