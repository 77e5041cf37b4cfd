#pragma once
/// \file
/// The user's cell (issue 16 item 1): where the robot and the instrument stand, what the
/// instrument can see, and what the robot must not touch. World frame, mm and degrees in the
/// file (radians inside). The file, `format: robcal-cell` (data/cells/default-tracker.yaml is
/// the simulator's cell):
///
/// ```yaml
/// format: robcal-cell
/// name: my cell
/// robot_base:                      # the robot's base placement (docs/method/02-frames.md §4 base
/// parameters)
///   position_mm: [-812.25, 1503.5, -95]     # x, y, z: world_A_1 = Trans(x, y, d1 + z)·…
///   rotation_xyz_deg: [0.25, -0.4, -57]     # α, β, γ: R = Rx(α)·Ry(β)·Rz(γ)
///   source: nominal                # nominal (from a drawing) or measured (robcal frames base)
/// instrument:
///   kind: laser-tracker            # laser-tracker or optical-cmm
///   position_mm: [0, 0, 0]         # world frame; or `from_nests` (below) instead
///   range_mm: [0, 35000]           # working range from the instrument
///   sigma_mm: 0.022                # optional: noise per axis, for simulations
///   cone_half_angle_deg: 30        # tracker: SMR acceptance cone half-angle
///   target_axes_flange: {"1": [0, 0, 1]}    # optional: SMR/reflector axes in the flange frame
///                                  # (default: from the flange origin out through the target)
///   # optical CMM only:
///   view_direction: [1, 0, 0]      # world frame, the camera bar's optical axis
///   field_of_view_deg: 60          # half-angle of the viewing cone about view_direction
///   facing_limit_deg: 15           # a target is seen while its axis is this close to the LOS
///   min_visible_targets: 3         # the pose is measured when this many targets are seen
///   # from_nests: {measured_mm: [[…], …], world_mm: [[…], …]}  # ≥ 3 nests on the table:
///   #   their centres measured by the instrument and their world coordinates
/// floor_z_mm: -95                  # floor or table top (world z); default: the robot base z
/// link_radius_mm: 60               # capsule radius of the robot's links (conservative)
/// keep_out:                        # boxes (axis-aligned, world frame) nothing may enter,
///   - {name: fence, min_mm: [-2000, 2500, -95], max_mm: [2000, 2600, 2000]}  # nor the LOS cross
/// ```
/// Unknown keys are refused; every error names file:line:column and the key.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "robcal/kinematics/forward_kinematics.hpp"
#include "robcal/measure/instrument.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal::campaign {

/// An axis-aligned box in the world frame.
struct KeepOutBox {
  std::string name;
  Eigen::Vector3d min_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_mm = Eigen::Vector3d::Zero();
  /// True when p (world frame, mm) is inside the box or on its faces.
  [[nodiscard]] bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= min_mm.array()).all() && (p.array() <= max_mm.array()).all();
  }
};

struct CellInstrument {
  InstrumentKind kind = InstrumentKind::LaserTracker;
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();  ///< world frame
  double min_range_mm = 0;
  double max_range_mm = 35000;
  double sigma_mm = 0;              ///< per axis, for simulations (0: the instrument's default)
  double cone_half_angle_deg = 30;  ///< tracker
  /// Reflector axes in the flange frame by target name; other targets use the default
  /// (measure/instrument.hpp smr_axis_flange).
  std::vector<std::pair<std::string, Eigen::Vector3d>> target_axes_flange;
  Eigen::Vector3d view_direction = Eigen::Vector3d::UnitX();  ///< CMM, world frame, unit
  double field_of_view_deg = 60;                              ///< CMM, half-angle
  double facing_limit_deg = 15;                               ///< CMM
  int min_visible_targets = 3;                                ///< CMM
};

struct Cell {
  std::string name;
  std::string file;                    ///< where it was read from (messages)
  std::array<double, 6> robot_base{};  ///< x, y, z (mm), α, β, γ (rad)
  bool base_measured = false;
  CellInstrument instrument;
  double floor_z_mm = 0;
  double link_radius_mm = 60;
  std::vector<KeepOutBox> keep_out;

  /// The nominal robot's parameters placed at this cell's base.
  [[nodiscard]] ParameterVector robot_params(const RobotModel& model) const;
};

/// Parses a cell file. \throws InputError naming file:line:column and the key: unknown key,
/// missing key, wrong value, an empty or inverted box, the instrument inside a keep-out box
/// or below the floor, fewer than 3 nests.
Cell parse_cell(const std::string& yaml_text, const std::string& file);
Cell load_cell(const std::string& path);

}  // namespace robcal::campaign
