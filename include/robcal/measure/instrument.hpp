#pragma once
/// \file
/// The measuring instruments of docs/method/06-instruments.md §1–§2 as plain descriptions with free
/// functions: what each one can see (visibility predicates, used by the planner's candidate filter)
/// and what it reads (noisy measurements, used by the simulator).
///
/// Frames: every position and pose passed to these functions must be expressed in one common
/// frame, the frame the instrument's own placement is given in. The simulator uses the
/// measurement (world) frame; a planner may use the robot's base frame. Units: mm, rad inside,
/// degrees in the user-facing fields whose names end in `_deg`.

#include <Eigen/Core>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/model/tool.hpp"

namespace robcal {

/// Laser tracker (FARO ION class): the 3D position of one SMR. The SMR reflects the beam only
/// while the tracker lies inside its acceptance cone (±30° about the SMR's axis,
/// docs/method/06-instruments.md §2).
struct LaserTracker {
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();  ///< tracker head
  /// Standard deviation of the reading along each axis of the common frame, mm
  /// (docs/method/06-instruments.md §1: ≈0.022 mm typical).
  Eigen::Vector3d sigma_mm = Eigen::Vector3d::Constant(0.022);
  double cone_half_angle_deg = 30;
  double min_range_mm = 0;      ///< closer SMRs are not tracked
  double max_range_mm = 35000;  ///< FARO ION: 35 m
  /// Axis of each target's SMR in the flange frame (unit vectors), by target index. Targets
  /// beyond this list use smr_axis_flange_default().
  std::vector<Eigen::Vector3d> smr_axes_flange;
};

/// Axis of target `target`'s SMR in the flange frame: the tracker's per-target entry if any,
/// else the direction from the flange origin out to the target (nests on a tool face outwards),
/// or the flange z axis for a target at the flange origin.
Eigen::Vector3d smr_axis_flange(const LaserTracker& tracker, const Tool& tool, int target);

/// True when the tracker can read an SMR at `smr_mm` whose axis is `smr_axis` (unit vector, same
/// frame): the line of sight lies within the cone (edge included) and the range fits.
bool smr_visible(const LaserTracker& tracker, const Eigen::Vector3d& smr_mm,
                 const Eigen::Vector3d& smr_axis);

/// Indices of the tool's targets (with known coordinates) the tracker can read when the flange
/// is at `frame_T_flange`, in target order.
std::vector<int> visible_targets(const LaserTracker& tracker, const Pose<double>& frame_T_flange,
                                 const Tool& tool);

/// One reading of the SMR at `smr_mm`: the true position plus Gaussian noise (σ per axis).
Eigen::Vector3d read_point(const LaserTracker& tracker, const Eigen::Vector3d& smr_mm,
                           std::mt19937_64& rng);

/// Optical CMM (Creaform C-Track class): the 6D pose of a target cluster on the tool. The
/// cameras see the cluster while one of its faces looks at them within the facing limit
/// (docs/method/06-instruments.md §2: face normal within 15° of the line of sight).
struct OpticalCmm {
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();  ///< camera bar centre
  double sigma_mm = 0.05;  ///< per axis, docs/method/06-instruments.md §1: 0.040–0.065 mm on bars
  double sigma_orientation_deg = 0.03;  ///< per rotation axis (≈ σ / 100 mm artifact radius)
  double facing_limit_deg = 15;
  double min_range_mm = 1000;  ///< C-Track 780 working volume, about 1.0–4.0 m from the bar
  double max_range_mm = 4000;
  /// Outward normals of the artifact's reflector faces in the flange frame (unit vectors). The
  /// default is a spatial artifact: a cube on the flange with five faces seen from outside.
  std::vector<Eigen::Vector3d> face_normals_flange = {
      Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitX(),
      Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitY()};
};

/// Index of the face the CMM sees best (smallest angle between its normal and the line of sight
/// from the tool centre to the camera), or std::nullopt when no face is within the facing limit
/// (edge included) or the tool centre is out of range.
std::optional<int> facing_face(const OpticalCmm& cmm, const Pose<double>& frame_T_flange,
                               const Tool& tool);

/// True when the CMM can measure the tool at this flange pose.
bool cmm_sees_tool(const OpticalCmm& cmm, const Pose<double>& frame_T_flange, const Tool& tool);

/// One reading of the tool centre pose: position plus Gaussian noise (σ per axis) and the
/// rotation composed with a small random rotation (σ per axis of its rotation vector).
Pose<double> read_pose(const OpticalCmm& cmm, const Pose<double>& frame_T_tcp,
                       std::mt19937_64& rng);

/// Telescoping ballbar (Renishaw QC20-W class) between a target of the tool and a fixed centre
/// cup: one length, readable only within ±range of its nominal length
/// (docs/method/06-instruments.md §1).
struct Ballbar {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  ///< the fixed cup
  double nominal_length_mm = 100;                       ///< 100, 150 or 300 mm set-ups
  double sigma_mm = 0.00051;                            ///< 0.51 µm (2 µm at 95 %)
  double range_mm = 1.0;                                ///< readable within nominal ± range
};

/// True when a ballbar whose balls are `length_mm` apart gives a reading (edge included).
bool ballbar_readable(const Ballbar& ballbar, double length_mm);

/// One reading for the tool cup at `cup_mm`, or std::nullopt when out of the ballbar's range.
std::optional<double> read_length(const Ballbar& ballbar, const Eigen::Vector3d& cup_mm,
                                  std::mt19937_64& rng);

/// The three instruments by command-line name: "laser-tracker", "optical-cmm", "ballbar".
enum class InstrumentKind { LaserTracker, OpticalCmm, Ballbar };

/// The kind named `name`; InputError naming `flag` and the accepted names otherwise.
InstrumentKind parse_instrument_kind(const std::string& name, const std::string& flag);
std::string instrument_name(InstrumentKind kind);

}  // namespace robcal
