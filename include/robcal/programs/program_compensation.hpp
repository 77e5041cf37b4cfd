#pragma once
/// \file
/// The `robcal compensate-program` workflow (docs/method/10-compensation.md §5): a robot program
/// and a calibrated robot in, the program with every target corrected for the tool and frame active
/// at it out (program_filter.hpp, corrected_targets.hpp make_program_corrector). On a text (for
/// Python and tests) or between files (the original never overwritten). Its JSON is written here.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>

#include "robcal/compensate/compensation_setup.hpp"
#include "robcal/programs/program_filter.hpp"

namespace robcal {

struct ProgramCompensationRequest {
  CompensationSetup setup;
  std::string in;              ///< the program (its extension gives the language)
  std::string out;             ///< the corrected program: a new file of the same kind
  std::string confidence_out;  ///< "": no side file of per-target confidence radii
  /// Frames file (frames_file.hpp) of tools and frames the program uses but does not define;
  /// its entries join `options.tools` / `options.frames`.
  std::string frames_file;
  ProgramFilterOptions options;
  /// Each point under the side each joint reaches it from, the sign of its move from the
  /// previous point (make_program_corrector's `by_approach`), instead of `setup.approach`.
  bool approach_from_motion = false;
};

struct ProgramCompensationResult {
  std::string in;   ///< the program's name in messages
  std::string out;  ///< where it was written ("" = a text, not written)
  /// A KUKA module: the other corrected file written beside `out` (krl_companion_path).
  std::string out_companion;
  ProgramLanguage language = ProgramLanguage::Rapid;
  ProgramFilterResult filter;  ///< corrected text, counts, uncorrected and assumed points
};

/// Corrects the program `text` (named `file` in errors) with the compensation's model, tool and
/// payload. InputError (file, line, column) as filter_program.
ProgramCompensationResult compensate_program_text(const Compensation& compensation,
                                                  std::string_view text, ProgramLanguage language,
                                                  const std::string& file,
                                                  const ProgramFilterOptions& options);

/// Corrects a KUKA module (filter_krl_module): the .src text `src` and its .dat `dat`; the result's
/// filter.text is the corrected .src, filter.dat_text the .dat.
ProgramCompensationResult compensate_krl_module_text(const Compensation& compensation,
                                                     std::string_view src, std::string_view dat,
                                                     const std::string& src_file,
                                                     const std::string& dat_file,
                                                     const ProgramFilterOptions& options);

/// Reads request.in, corrects it and writes request.out (and the confidence side file), whole or
/// not at all; refuses an output that is the input (filter_program_file).
ProgramCompensationResult compensate_program(const ProgramCompensationRequest& request);

/// {in, out, out_companion (KUKA module), language, cartesian_points, joint_points, uncorrected:
/// [{where, reason}], assumed: [{where, reason}], assumed_default_tool_and_frame: count}.
void to_json(nlohmann::json& j, const ProgramCompensationResult& result);

}  // namespace robcal
