#pragma once
/// \file
/// Instrument exports joined with the robot's joint log into robcal's measurement CSV
/// (README "Measurements, CSV"), without hand editing (issue 16 item 4).
///
/// **The export** (one reading per line): points (x, y, z) of a laser tracker or a CMM probe,
/// or poses (x, y, z and a quaternion or three rotation angles) of an optical CMM, in the
/// instrument's (world) frame. The columns are found by name in a header line (case-insensitive,
/// a unit mark such as "X [mm]", "X (m)" or "x_mm" is read and removed), or given in file order
/// when the file has no header, e.g. SpatialAnalyzer's "Collection Group Target X Y Z" export:
/// `columns: [collection, group, target, x, y, z]`. Recognised names: `x y z`; `qw qx qy qz`;
/// `rx ry rz` (angles); `target` (also point, point name, name, target name, label, id);
/// `config` (also configuration, pose); `time` (also timestamp, time stamp, date/time).
/// Other columns are ignored; `roles` maps any column to a role (e.g. `config: group`).
///
/// **The joint log** the robot program writes: a header with `config` and `j1`…`j6`
/// (controller values, degrees), optional `time` and `target`; same dialect freedom.
///
/// **Joining**: by order (the k-th reading is the k-th log row), by configuration name (the
/// export's config column against the log's; with a log `target` column, by (config, target)),
/// or by time (the log row nearest in time within a tolerance). Counts that do not match are
/// refused with the rows named, never guessed.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "robcal/campaign/text_table.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/model/tool.hpp"

namespace robcal::campaign {

/// How rotation angles rx, ry, rz (columns of a pose export) compose.
enum class AngleOrder {
  FixedXyz,  ///< about the fixed axes x, then y, then z: R = Rz(rz)·Ry(ry)·Rx(rx) (roll-pitch-yaw)
  MobileXyz  ///< about the moving axes x, y', z'': R = Rx(rx)·Ry(ry)·Rz(rz)
};

/// How to read an instrument export. Defaults: everything detected from the file.
struct ExportFormat {
  TextDialect dialect;
  /// Column names in file order for a file without a header (or replacing its header when
  /// `has_header`); empty: the first data line is the header.
  std::vector<std::string> columns;
  bool has_header = true;  ///< with `columns` given: false unless told
  /// Role → column name (both lowercase), overriding the recognised names, e.g. {"config",
  /// "group"}. Roles: config, target, time, x, y, z, qw, qx, qy, qz, rx, ry, rz.
  std::map<std::string, std::string> roles;
  /// Length unit of x, y, z: "mm" or "m"; empty: from the header's unit marks, else mm.
  std::string unit;
  bool angles_in_degrees = true;  ///< rx, ry, rz
  AngleOrder angle_order = AngleOrder::FixedXyz;
};

/// Reads a mapping file (YAML) into a format:
/// ```yaml
/// delimiter: space          # comma, semicolon, tab, space (default: detected)
/// decimal: comma            # point or comma (default: detected)
/// header: false             # the file has no header line (then `columns` is required)
/// columns: [collection, group, target, x, y, z]
/// roles: {config: group}    # which column is which, when the names do not say
/// unit: m                   # mm (default) or m
/// angles: {unit: deg, order: fixed-xyz}   # deg|rad, fixed-xyz|mobile-xyz
/// ```
/// Unknown keys and values are refused with file:line:column.
ExportFormat parse_export_format(const std::string& yaml_text, const std::string& file);

/// Sets one option of `format` from text, as `robcal import` flags give them: "delimiter"
/// (comma, semicolon, tab, space), "decimal" (point, comma), "unit" (mm, m), "columns"
/// (comma-separated names in file order; the file then has no header), "config-column" (the
/// column holding the configuration name). \throws InputError naming `flag` otherwise.
void set_export_option(ExportFormat& format, const std::string& option, const std::string& value,
                       const std::string& flag);

/// How the readings find their joints.
enum class JoinBy { Order, Name, Time };

/// Parses "order", "name" or "time"; InputError naming `flag` otherwise.
JoinBy parse_join_by(const std::string& text, const std::string& flag);

/// One text file (name for messages, content).
struct NamedText {
  std::string name;
  std::string text;
};

struct ImportRequest {
  NamedText export_file;
  NamedText joint_log;
  ExportFormat format;
  TextDialect log_dialect;  ///< detected by default
  JoinBy join = JoinBy::Order;
  double time_tolerance_s = 0.5;  ///< JoinBy::Time
  /// Target name for point readings when neither the export nor the log names one.
  std::string default_target;
  /// Log rows without a reading are reported as warnings instead of refused.
  bool allow_unmeasured = false;
  /// Readings taken in the instrument's frame written in the frame F of a `robcal frames
  /// world` file (campaign/frames_world.hpp): instrument_T_F, and the file's name for the CSV.
  std::optional<Pose<double>> instrument_T_world;
  std::string world_frame_file;
  /// The configurations file the measurement program ran (`robcal plan --out`): each reading
  /// takes the `approach` and `payload` of its configuration's row there, joined by the joint
  /// log's configuration name (docs/method/05-observability.md §7).
  std::optional<NamedText> plan;
};

struct ImportResult {
  MeasurementSet measurements;  ///< points or poses, in the export's order
  /// The target names met, in order (indices of the points), and the plan's payload names met
  /// (indices of the rows' payloads; masses unknown here: the tool file has them).
  Tool targets;
  std::vector<std::string> warnings;
  std::string csv;          ///< the measurement CSV (io/measurement_file.hpp writer)
  std::string world_frame;  ///< the frame file the positions are in (empty: the instrument's)
};

/// Reads, joins and renders. \throws InputError naming the file, line and column (or the rows
/// on both sides of a mismatch) for anything that cannot be joined unambiguously, or a joint log
/// configuration the plan does not list.
ImportResult import_measurements(const ImportRequest& request);

/// The point readings (mm) of an export read so far, in file order, for a session that follows
/// the file as the instrument software appends to it: a last line without its newline (being
/// written) is left for later, as is a file with only comments or a header so far.
/// \throws InputError naming file, line and column for a malformed complete line, or a poses
///   export.
std::vector<Eigen::Vector3d> read_export_points(const NamedText& file, const ExportFormat& format);

}  // namespace robcal::campaign
