#pragma once
/// \file
/// Measurement files: CSV with a header row (METHOD §5, §7). Lines starting with `#` are
/// comments, blank lines are skipped, columns are found by name in any order. The kind is told
/// by the columns:
///
/// | kind      | columns                                   | units                         |
/// |-----------|-------------------------------------------|-------------------------------|
/// | poses     | config,j1..j6,x,y,z,qw,qx,qy,qz           | deg; mm; unit quaternion wxyz |
/// | points    | config,target,j1..j6,x,y,z                | deg; mm (world frame)         |
/// | distances | config,target,j1..j6,length               | deg; mm                       |
///
/// Any quaternion column makes a poses file; otherwise x/y/z make a points file; otherwise
/// `length` makes a distances file. Joints are the controller's values in degrees as commanded
/// (radians in memory). `target` names a target of the tool. Columns the kind does not use are
/// ignored with a warning.

#include <string>
#include <string_view>
#include <vector>

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

/// Reads a measurement file.
/// \param tool      resolves target names to indices into Tool::targets
/// \param accepted  kinds the calling command can use (empty: any); another kind is an error
/// \throws InputError naming the file, line, column (number and name) and what was expected:
///   unreadable or empty file, missing column, wrong field count, non-numeric or non-finite
///   value, unknown target (listing the tool's targets), duplicate row (same config and
///   target; same config for poses), quaternion not unit within 1e-5, kind not accepted.
MeasurementFile read_measurements_csv(const std::string& path, const Tool& tool,
                                      const std::vector<MeasurementKind>& accepted = {});

/// Same as read_measurements_csv on text already in memory; `source_name` is used in messages
/// and stored in MeasurementSet::file.
MeasurementFile parse_measurements_csv(std::string_view text, const std::string& source_name,
                                       const Tool& tool,
                                       const std::vector<MeasurementKind>& accepted = {});

/// The set as a CSV file of its kind, with the shortest decimal text that reads back to the
/// same double (joints converted to degrees). `comment` lines, if any, are written first as
/// `# ` lines. Targets are written by name (`tool` must hold every target index used).
std::string write_measurements_csv(const MeasurementSet& set, const Tool& tool,
                                   std::string_view comment = {});

}  // namespace robcal
