#pragma once
/// \file
/// ISO 9283:1998 ("Manipulating industrial robots — Performance criteria and related test
/// methods") pose characteristics: the test cube and its poses P1–P5, and the analysis of
/// measured cycles. The clause numbers were checked against the standard's published table of
/// contents (6.8 poses, 6.9 cycles, 7.2 pose accuracy and repeatability, 7.3 distance) and a
/// test house's description of GB/T 12642-2013, the identical Chinese adoption (7.2.1 AP, 7.2.2
/// RP, 7.2.3 vAP); sources in docs/validation.md. The corner labels, the P2–P5 assignment and
/// the cycle order are robcal's reading, not verified against the (non-public) text; the cube,
/// the 10 % corner offset and the formulas agree with the public sources listed there.
///
/// Test cube (clause 6.8): the largest cube inside the given workspace region, edges parallel
/// to the world axes. Corners here: C1 (−,−,−), C2 (+,−,−), C3 (+,+,−), C4 (−,+,−) below and
/// C5..C8 above them. The poses lie on the diagonal plane C1–C2–C7–C8 (clause 6.8): P1 at
/// the centre of the cube, P2..P5 on the diagonals towards C1, C2, C7, C8 at 10 % of the
/// diagonal's length from the corner, i.e. P = centre + 0.8·(C − centre). Every pose has the
/// same commanded tool orientation. A cycle visits P1 → P5 → P4 → P3 → P2; 30 cycles
/// (clause 6.9, number of cycles).
///
/// Analysis, for n cycles of pose P with commanded position (x_c, y_c, z_c) and attained
/// positions (x_j, y_j, z_j), j = 1..n (clause 7.2.1, pose accuracy):
///   x̄ = (1/n) Σ x_j (likewise ȳ, z̄);  AP_x = x̄ − x_c …;  AP_P = √(AP_x² + AP_y² + AP_z²);
/// orientation: a_j, b_j, c_j are the attained orientation's deviations from the commanded one
/// about the commanded tool axes x, y, z (the components, in degrees, of the rotation vector of
/// R_cᵀ·R_j; the standard's a, b, c for the small deviations measured), so a_c = b_c = c_c = 0
/// and AP_a = ā − a_c = ā …
/// Pose repeatability (clause 7.2.2):
///   l_j = √((x_j − x̄)² + (y_j − ȳ)² + (z_j − z̄)²);  l̄ = (1/n) Σ l_j;
///   S_l = √(Σ (l_j − l̄)² / (n − 1));  RP_l = l̄ + 3·S_l;
///   RP_a = ±3·S_a, S_a = √(Σ (a_j − ā)² / (n − 1)) (likewise b, c).
/// Multi-directional pose accuracy variation (clause 7.2.3), the pose approached from three
/// directions h = 1..3 (mean positions x̄_h…):
///   vAP_P = max_{h,k} √((x̄_h − x̄_k)² + (ȳ_h − ȳ_k)² + (z̄_h − z̄_k)²);
///   vAP_a = max_{h,k} |ā_h − ā_k| (likewise b, c).
/// Distance accuracy and repeatability (clause 7.3) between P2 and P4 (the poses at opposite
/// corners): D_c = |P_c2 − P_c4|, D_j = |P_2j − P_4j|, D̄ = (1/n) Σ D_j;
///   AD_P = D̄ − D_c;  RD_P = ±3·S_D, S_D = √(Σ (D_j − D̄)² / (n − 1));
///   orientation D_aj = a_2j − a_4j (deviations, so D_ca = 0): AD_a = D̄_a, RD_a = ±3·S_Da.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/programs/measurement_program.hpp"

namespace robcal {

/// Cycles the standard asks for (clause 6.9).
inline constexpr int kIso9283Cycles = 30;
/// Fewest cycles any figure can be computed from (S uses n − 1).
inline constexpr int kIso9283MinimumCycles = 2;

struct Iso9283PlanRequest {
  CalibratedRobot robot;  ///< nominal or calibrated; joints come from its compensation IK
  Eigen::Vector3d region_min_mm = Eigen::Vector3d::Zero();  ///< the workspace region (world)
  Eigen::Vector3d region_max_mm = Eigen::Vector3d::Zero();
  Eigen::Matrix3d world_R_tcp = Eigen::Matrix3d::Identity();  ///< the one tool orientation
  ArmConfig config{false, false, false};
  int cycles = kIso9283Cycles;
  /// > 0: also plan the multi-directional test (vAP): every pose approached along the world
  /// axes +x, +y, +z (directions 1, 2, 3) from a pre-pose this far back (mm).
  double vap_approach_mm = 0;
};

struct Iso9283PlannedPose {
  std::string name;  ///< "P1".."P5"
  Pose<double> world_T_tcp;
  Vector6d joints = Vector6d::Zero();  ///< controller joints, rad (compensation IK)
};

/// One move of the multi-directional test.
struct Iso9283Move {
  int cycle = 1;          ///< 1-based
  int pose = 0;           ///< index into Iso9283Plan::poses
  int direction = 1;      ///< 1..3: approached along world +x, +y, +z
  bool approach = false;  ///< the pre-pose (not measured) or the pose
  bool operator==(const Iso9283Move&) const = default;
};

struct Iso9283Plan {
  Eigen::Vector3d cube_centre_mm = Eigen::Vector3d::Zero();
  double cube_edge_mm = 0;
  std::array<Eigen::Vector3d, 8> corners_mm;  ///< C1..C8
  std::vector<Iso9283PlannedPose> poses;      ///< P1..P5
  /// The cycles' sequence: indices into `poses`, P1 → P5 → P4 → P3 → P2 per cycle.
  std::vector<std::pair<int, int>> sequence;  ///< (cycle 1-based, pose index)
  /// Multi-directional test (when vap_approach_mm > 0): approaches[pose index][h − 1] is the
  /// pre-pose P − d·u_h the pose is approached from, u_1..u_3 = world +x, +y, +z.
  std::vector<std::array<Iso9283PlannedPose, 3>> approaches;
  /// Its moves: for each direction h, each cycle, each pose in the cycle's order: the pre-pose
  /// (`approach` true), then the pose, where it is measured with direction h.
  std::vector<Iso9283Move> vap_sequence;
};

/// The test cube, its poses and joint targets.
/// \throws InputError for a region that is not a box of positive size, fewer than
///   kIso9283MinimumCycles cycles, or a pose the IK does not reach in the configuration
///   (naming the pose and why)
Iso9283Plan iso9283_plan(const Iso9283PlanRequest& request);

/// The poses as a pose-list file (io/pose_list_file.hpp: name,x,y,z,qw,qx,qy,qz,config).
std::string iso9283_pose_list_csv(const Iso9283Plan& plan, const ArmConfig& config);
/// The cycles' joint targets, one row per move: `cycle,pose,j1,…,j6` (degrees).
std::string iso9283_cycles_csv(const Iso9283Plan& plan);
/// The multi-directional test's joint targets, one row per move:
/// `cycle,pose,direction,move,j1,…,j6` (move: approach or measure; degrees). Empty without it.
std::string iso9283_vap_cycles_csv(const Iso9283Plan& plan);

/// The measurement program of the cycles through the programs layer
/// (programs/measurement_program.hpp): `base` gives the language, hook and signals; its names
/// and joints are replaced by the cycles' moves, named `C01-P1` (cycle, pose) for the
/// unidirectional test, and `V01-P1-D2` (pose) / `V01-P1-D2-from` (pre-pose) for the
/// multi-directional one. No configuration gets the programs layer's q − approach_deg joint
/// approach: the cycle's own moves are the approach the standard prescribes. The pre-poses
/// are visited without the settle wait and the hook (ConfigurationVisit::measure false): only
/// the test's poses are measured.
/// InputError (key --vap-approach) for a multi-directional program of a plan without it.
MeasurementProgramRequest iso9283_program_request(const Iso9283Plan& plan,
                                                  MeasurementProgramRequest base,
                                                  bool multidirectional);

/// One attained pose of one cycle.
struct Iso9283Sample {
  int pose = 1;       ///< 1..5
  int cycle = 1;      ///< 1-based
  int direction = 0;  ///< 1..3 for the multi-directional test (clause 7.2.3); 0: unidirectional
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();
  std::optional<Eigen::Matrix3d> world_R_tcp;  ///< when the instrument measured orientation
  int line = 0;                                ///< in the file, for messages
};

struct Iso9283AnalysisRequest {
  std::string file;  ///< the measurements' file name, for messages
  /// Commanded poses P1..P5 (index 0 = P1); poses without samples are skipped.
  std::vector<Pose<double>> commanded;
  std::vector<Iso9283Sample> samples;
  int min_cycles = kIso9283Cycles;  ///< fewer cycles for a pose: InputError
};

/// Figures of one pose (clause 7.2).
struct Iso9283PoseFigures {
  int pose = 1;
  int cycles = 0;
  Eigen::Vector3d mean_mm = Eigen::Vector3d::Zero();  ///< x̄, ȳ, z̄
  Eigen::Vector3d ap_xyz_mm = Eigen::Vector3d::Zero();
  double ap_mm = 0;  ///< AP_P
  double l_mean_mm = 0, s_l_mm = 0;
  double rp_mm = 0;  ///< RP_l
  bool has_orientation = false;
  Eigen::Vector3d ap_abc_deg = Eigen::Vector3d::Zero();  ///< AP_a, AP_b, AP_c
  Eigen::Vector3d rp_abc_deg = Eigen::Vector3d::Zero();  ///< RP_a… (±, the value given ≥ 0)
  int directions = 0;  ///< distinct approach directions among the samples (vAP needs ≥ 2)
  std::optional<double> vap_mm;
  std::optional<Eigen::Vector3d> vap_abc_deg;
};

/// Distance figures between P2 and P4 (clause 7.3).
struct Iso9283DistanceFigures {
  int cycles = 0;
  double commanded_mm = 0, mean_mm = 0;
  double ad_mm = 0, s_d_mm = 0, rd_mm = 0;
  bool has_orientation = false;
  Eigen::Vector3d ad_abc_deg = Eigen::Vector3d::Zero(), rd_abc_deg = Eigen::Vector3d::Zero();
};

struct Iso9283Result {
  std::vector<Iso9283PoseFigures> poses;
  std::optional<Iso9283DistanceFigures> distance;  ///< when both P2 and P4 were measured
};

/// The figures of the measured cycles. Pose accuracy and repeatability use the
/// unidirectional samples (a pose's direction 0, or its direction 1 when it has no direction 0);
/// vAP uses directions 1..3 (at least two of them).
/// \throws InputError naming the file (and line) for a pose outside 1..5 or without a commanded
///   pose, a cycle given twice, fewer than `min_cycles` cycles of a pose, samples mixing with
///   and without orientation, P2 and P4 measured in different cycles
Iso9283Result iso9283_analyse(const Iso9283AnalysisRequest& request);

/// Reads measured cycles: a CSV with the header `pose,cycle,x,y,z` or
/// `pose,cycle,x,y,z,qw,qx,qy,qz`, optionally followed by `direction` (mm; pose "P1".."P5" or
/// 1..5). InputError with file, line and column for anything else.
std::vector<Iso9283Sample> read_iso9283_samples(const std::string& path);
std::vector<Iso9283Sample> parse_iso9283_samples(const std::string& text, const std::string& file);

/// The analysis request of a test: the commanded poses named P1..P5 in a pose-list file (the
/// one `iso9283_pose_list_csv` writes) and the measured cycles. InputError naming the pose-list
/// file when a pose is missing.
Iso9283AnalysisRequest read_iso9283_request(const std::string& poses_path,
                                            const std::string& measurements_path, int min_cycles);

}  // namespace robcal
