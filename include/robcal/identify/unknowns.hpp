#pragma once
/// \file
/// What a calibration solves for: the robot's parameters (docs/method/03-error-model.md §1 layout)
/// followed by the extra unknowns the measurements bring — coordinates of tool targets given
/// without coordinates, the ballbar's fixed centre and, on request, the ballbar's length offset —
/// and which of them a calibration level and the user's `--identify`/`--fix` patterns set free.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "robcal/measure/measurements.hpp"
#include "robcal/model/parameters.hpp"
#include "robcal/model/robot_model.hpp"
#include "robcal/model/tool.hpp"

namespace robcal {

/// The four calibration levels (docs/method/01-overview.md §3, 03-error-model.md §1).
enum class CalibrationLevel {
  Base,       ///< the 6 base parameters: the nominal robot placed in the world
  Joints,     ///< + joint offsets link2..6.theta
  Kinematic,  ///< + every MDH error of links 2..6
  Full,       ///< + compliance of joints 2..6 under gravity
  /// Re-identification of a calibrated robot (calibrate --model, reidentify()): no model
  /// parameter; the tool's targets, or its TCP frame from poses, are identified.
  Tool,
  /// Re-identification of only the parameters the `--identify` patterns name.
  Patterns
};

/// "base", "joints", "kinematic", "full" → level; InputError (key "--level") otherwise.
CalibrationLevel parse_calibration_level(const std::string& text);
/// The same, and "tool": what `calibrate --model` may re-identify.
CalibrationLevel parse_reidentification_level(const std::string& text);
const char* level_name(CalibrationLevel level);

/// Model parameter indices a level frees.
std::vector<int> level_parameters(CalibrationLevel level);

/// The unknown vector of one calibration: kParameterCount model parameters, then the extras.
/// Names: the parameters' dotted names, `target.<name>.x|y|z`, `ballbar.centre.x|y|z`,
/// `ballbar.length_offset`, `tcp.x|y|z` (extras in mm), `tcp.rx|ry|rz` (deg outside).
struct UnknownLayout {
  std::vector<std::string> names;
  std::vector<int> target_slot;  ///< per tool target: index of its x coordinate, or -1 if known
  int centre = -1;               ///< index of ballbar.centre.x (distances only), or -1
  int length_offset = -1;        ///< index of ballbar.length_offset (distances only), or -1
  /// Poses with a TCP part to identify: index of tcp.x (mm), of tcp.rx (rad: the rotation
  /// vector φ of flange_T_tcp = start·exp([φ]×)), or -1.
  int tcp_position = -1;
  int tcp_rotation = -1;

  [[nodiscard]] int size() const { return static_cast<int>(names.size()); }
  [[nodiscard]] bool is_model(int index) const { return index < kParameterCount; }
  /// Internal → external unit factor (deg for angles, else 1) and the external unit's name.
  [[nodiscard]] double to_external(int index) const;
  [[nodiscard]] std::string unit(int index) const;
  /// A plausible error of an unknown (internal units), the physical scale of its column when
  /// deciding what the measurements see: 1 mm, 1 mrad, 1e-7 rad/N·mm (the published
  /// compliances are 0.3–6e-7), 1e-4 of a joint scale, 1 mm for extras.
  [[nodiscard]] double plausible_error(int index) const;
  /// Index of a name, or -1.
  [[nodiscard]] int index(const std::string& name) const;
};

UnknownLayout make_unknown_layout(const Tool& tool, MeasurementKind kind);

/// Which unknowns a calibration frees: the level's parameters, every target coordinate to be
/// identified and the ballbar centre; then each `identify` pattern adds and each `fix` pattern
/// removes the unknowns whose names match (glob, '*' and '?'). A pattern matching nothing, or
/// fixing a target that has no coordinates, is an InputError naming the pattern.
std::vector<bool> select_unknowns(const UnknownLayout& layout, CalibrationLevel level,
                                  const std::vector<std::string>& identify,
                                  const std::vector<std::string>& fix);

/// Motor-angle periodic terms (docs/method/03-error-model.md §9) of joints whose gear ratio the
/// robot file does not give: a pattern of `identify` that names them ('joint6.motor_periodic*')
/// is an InputError (key `--identify`) naming the joint; a family ('motor_periodic', 'groups') or
/// a pattern without 'motor' ('joint6.*') leaves them out of `requested` (model parameters).
void refuse_gearless_motor_terms(const RobotModel& model, const std::vector<std::string>& identify,
                                 std::vector<bool>& requested);

/// InputError (key `--identify`) naming the first pattern that matches no model parameter: checks
/// a request's patterns before any file is read.
void check_identify_patterns(CalibrationLevel level, const std::vector<std::string>& identify);

/// The model parameter indices (ascending) a calibration of `model` with `tool` and `kind`
/// identifies: the level's and those of `identify` (select_unknowns), motor-angle terms of
/// gearless joints left out (refuse_gearless_motor_terms). What a design is made for.
std::vector<int> identified_model_parameters(const RobotModel& model, const Tool& tool,
                                             MeasurementKind kind, CalibrationLevel level,
                                             const std::vector<std::string>& identify);

}  // namespace robcal
