#pragma once
// Private to measurement programs: one writer and one joint-move reader per language, fed by
// measurement_program.cpp, which checks the request and splits it into parts.

#include <span>
#include <string>
#include <vector>

#include "robcal/programs/measurement_program.hpp"

namespace robcal::detail {

/// One configuration as the program visits it, controller joints in degrees.
struct Visit {
  std::string name;
  Vector6d approach_deg;
  Vector6d target_deg;
  bool approach = true;    ///< move to approach_deg first
  bool measure = true;     ///< settle and run the hook at target_deg
  std::string from_above;  ///< the joints approached from above ("2,3"), empty when none
  /// The comment naming the configuration: its name, marked when nothing is measured there or
  /// when some joint comes from above.
  [[nodiscard]] std::string label() const {
    return name +
           (from_above.empty() || !approach ? "" : " (from above: joints " + from_above + ")") +
           (measure ? "" : " (not measured)");
  }
};

/// One program (file) of a measurement program.
struct MeasurementPart {
  const MeasurementProgramRequest& request;
  std::string program;  ///< program name (RAPID module, KRL DEF, LS /PROG, JBI //NAME, UR def)
  int part = 1, parts = 1;
  size_t first = 0;  ///< index of the part's first configuration in the request
  std::span<const Visit> visits;
  std::string payload;  ///< the payload to mount for this part (empty: the tool's own)
};

std::string write_rapid_measurement(const MeasurementPart& part);
std::string write_krl_measurement(const MeasurementPart& part);
std::string write_ls_measurement(const MeasurementPart& part);
std::string write_jbi_measurement(const MeasurementPart& part);
std::string write_urscript_measurement(const MeasurementPart& part);

std::vector<JointMove> read_ls_joint_moves(const std::string& text, const std::string& file);
std::vector<JointMove> read_jbi_joint_moves(const std::string& text, const std::string& file,
                                            const std::array<double, kJointCount>& pulses);
std::vector<JointMove> read_urscript_joint_moves(const std::string& text, const std::string& file);

/// The header comment of each file: part k of n, which configurations, the approach and how
/// the language stops at a point; each line starts with `prefix` (the comment start).
std::string header_comment(const MeasurementPart& part, std::string_view prefix,
                           std::string_view stop);

/// A decimal number at `text[at]` (optional sign, digits, point, exponent), read whole and
/// finite; InputError at file:line:column otherwise. Advances `at` past it.
double read_number(std::string_view text, size_t& at, const std::string& file, int line,
                   size_t line_start);

}  // namespace robcal::detail
