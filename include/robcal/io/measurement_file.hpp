#pragma once
/// \file
/// Measurement files: CSV with a header row (docs/method/04-identification.md §1, 06-instruments.md
/// §1). Lines starting with `#` are comments, blank lines are skipped, columns are found by name in
/// any order. The kind is told by the columns:
///
/// | kind      | columns                                   | units                         |
/// |-----------|-------------------------------------------|-------------------------------|
/// | poses     | config,j1..j6,x,y,z + orientation         | deg; mm; see below            |
/// | points    | config,target,j1..j6,x,y,z                | deg; mm (world frame)         |
/// | distances | config,target,j1..j6,length               | deg; mm                       |
///
/// Orientation of a poses file, as instruments and controllers write it:
/// - `qw,qx,qy,qz`: unit quaternion;
/// - `a,b,c`: ABB/KUKA angles, R = Rz(a)·Ry(b)·Rx(c) (intrinsic ZYX);
/// - `w,p,r`: Fanuc angles, R = Rz(r)·Ry(p)·Rx(w) (extrinsic XYZ, the same matrix);
/// - `rx,ry,rz`: angles about x, y, z in a declared order, any of the 12: `# euler: intrinsic
///   ZYX` (R = Rz·Ry·Rx) or `# euler: extrinsic XYZ` (rotations about the fixed axes x, then y,
///   then z: also R = Rz·Ry·Rx), or MeasurementFormat::euler (the `--euler` option).
///
/// Any quaternion column, or a complete set of Euler columns in a file without `target`, makes a
/// poses file; otherwise x/y/z make a points file; otherwise `length` makes a distances file.
/// Any kind may add `approach`: six characters, one per joint, '+' approached from below, '-'
/// from above, '0' unknown (e.g. `++-+++`), which the backlash group needs
/// (docs/method/03-error-model.md §6); without it every joint counts as approached from below,
/// as the measurement programs do. The writer adds it only when a row is not '++++++'.
/// Joints are the controller's values as commanded. `target` names a target of the tool. Columns
/// the kind does not use are ignored with a warning. A UTF-8 byte-order mark is skipped.
/// An optional `payload` column names the payload a row carried, one of the tool file's
/// `payloads:` (empty: its `payload`), for several payloads in one calibration
/// (docs/method/03-error-model.md §7).
///
/// Units: mm and degrees (radians in memory) unless declared by a header comment
/// `# units: m, rad` (a length unit mm or m, an angle unit deg or rad — for the joints and the
/// Euler angles — either may be left out) or MeasurementFormat (the `--units` option). Never
/// guessed: when undeclared values look like the other unit (positions spanning less than
/// 10 mm, or ballbar lengths below 10 mm, over ≥ 5 rows: metres; every joint within ±2π over
/// ≥ 5 rows: radians), the file is refused with what to declare.
///
/// Plausible ranges (a value outside is a typo, a unit slip or a corrupt export, refused at its
/// file:line:column with the range in the file's units): x, y, z within ±100 m (±100000 mm:
/// any cell, a tracker's frame included); joints and Euler angles within ±720° (two turns: the
/// widest joint of a six-axis arm turns ±455°, a robot file allows ±1080°); ballbar `length`
/// above 0 and at most 100 m. Joints inside that range but outside the robot's limits are
/// warned by calibrate with their lines.

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "robcal/core/error.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/model/tool.hpp"

namespace robcal {

/// "points", "poses" or "distances".
std::string_view measurement_kind_name(MeasurementKind kind);

/// The rows of a file and the warnings met while reading it (ignored columns), for the caller
/// to print.
struct MeasurementFile {
  MeasurementSet measurements;
  std::vector<std::string> warnings;
};

enum class LengthUnit { Millimetre, Metre };
enum class AngleUnit { Degree, Radian };

/// Order of the rotations of `rx,ry,rz` columns: `axes` as written ("ZYX": 2, 1, 0);
/// intrinsic: R = R_axes[0]·R_axes[1]·R_axes[2]; extrinsic: R = R_axes[2]·R_axes[1]·R_axes[0].
struct EulerOrder {
  std::array<int, 3> axes{2, 1, 0};
  bool intrinsic = true;
};

/// The rotation of angles (rad) about x, y and z (`angles` indexed by axis) composed in `order`.
Eigen::Matrix3d rotation_from_axis_angles(const Eigen::Vector3d& angles, const EulerOrder& order);

/// What the caller declares about a file (command-line options); unset members come from the
/// file's header comments or the defaults (mm, deg). A declaration that contradicts the file's
/// header is an InputError.
struct MeasurementFormat {
  std::optional<LengthUnit> length;
  std::optional<AngleUnit> angle;
  std::optional<EulerOrder> euler;
};

/// Parses an approach such as "++-+++" (the `approach` column, `--approach`): per joint +1 from
/// below, −1 from above, 0 unknown; InputError at `where` for anything but six of '+', '-', '0'.
Vector6d parse_approach(std::string_view text, const SourceLocation& where);
/// The approach's text, as parse_approach reads it ("++-+++").
std::string approach_text(const Vector6d& approach);

/// True for a temperature (°C) from a workshop to a foundry, [−50, 150]; outside is a unit slip
/// (°F, K).
bool plausible_temperature_c(double celsius);

/// Parses a temperature cell (the `temperature` column, °C, docs/method/03-error-model.md §8):
/// empty is no reading (nullopt); InputError at `where` for anything but a finite, plausible
/// temperature.
std::optional<double> parse_temperature_c(std::string_view text, const SourceLocation& where);

/// Parses a time cell (the `time_s` column, s since the arm started working, the warm-up group,
/// docs/method/03-error-model.md §10): empty is no time (nullopt); InputError at `where` for
/// anything but a finite time in [0, 1e7] s.
std::optional<double> parse_time_s(std::string_view text, const SourceLocation& where);

/// The index of the payload `name` among the tool's `payloads` (the `payload` column,
/// docs/method/03-error-model.md §7); InputError at `where` listing them, `when_empty` saying what
/// an empty cell means instead.
int payload_index_of(std::string_view name, const Tool& tool, const SourceLocation& where,
                     std::string_view when_empty);

/// Parses "m, rad" / "mm" / "rad" (`--units`, `# units:`) into `format`; InputError at `where`.
void parse_units(std::string_view text, const SourceLocation& where, MeasurementFormat& format);
/// Parses "intrinsic ZYX" / "extrinsic xyz" (`--euler`, `# euler:`); InputError at `where`.
EulerOrder parse_euler_order(std::string_view text, const SourceLocation& where);

/// Reads a measurement file.
/// \param tool      resolves target names to indices into Tool::targets
/// \param accepted  kinds the calling command can use (empty: any); another kind is an error
/// \throws InputError naming the file, line, column (number and name) and what was expected:
///   unreadable or empty file, missing column, wrong field count, non-numeric or non-finite
///   value, unknown target (listing the tool's targets), duplicate row (same config and
///   target; same config for poses), quaternion not unit within 1e-5, kind not accepted.
MeasurementFile read_measurements_csv(const std::string& path, const Tool& tool,
                                      const std::vector<MeasurementKind>& accepted = {},
                                      const MeasurementFormat& format = {});

/// Same as read_measurements_csv on text already in memory; `source_name` is used in messages
/// and stored in MeasurementSet::file.
MeasurementFile parse_measurements_csv(std::string_view text, const std::string& source_name,
                                       const Tool& tool,
                                       const std::vector<MeasurementKind>& accepted = {},
                                       const MeasurementFormat& format = {});

/// The set as a CSV file of its kind, with the shortest decimal text that reads back to the
/// same double (joints converted to degrees). `comment` lines, if any, are written first as
/// `# ` lines. Targets are written by name (`tool` must hold every target index used).
std::string write_measurements_csv(const MeasurementSet& set, const Tool& tool,
                                   std::string_view comment = {});

}  // namespace robcal
