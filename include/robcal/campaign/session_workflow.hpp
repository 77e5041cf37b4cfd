#pragma once
/// \file
/// The workflow behind `robcal session` and Python's point_session: the guided tracker/CMM
/// session of campaign/point_session.hpp run end to end on files — the plan and tool read, the
/// reference found by name, the journal created or resumed (io/journal_file.hpp), every step
/// prompted and answered from the operator's lines or from an instrument export as it grows,
/// and the measurement CSV written (in a nest frame when asked) once every step is answered.
/// The operator's side (prompts out, lines in) goes through SessionIo, so a terminal, a pipe or
/// a Python list of answers drive the same code.

#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>

#include "robcal/campaign/point_session.hpp"

namespace robcal::campaign {

struct PointSessionRequest {
  std::string configs;    ///< plan CSV: config,target,j1..j6 (deg)
  std::string tool;       ///< tool file; empty: the simulator's (SMRs 1, 2, 3)
  std::string journal;    ///< append-only journal
  bool resume = false;    ///< continue an existing journal (else it must not exist)
  std::string reference;  ///< name of the reference configuration for drift checks
  int every = 0;          ///< re-measure the reference every N configurations (0: never)
  std::string follow;     ///< instrument export read as it grows instead of the answers
  std::string map;        ///< mapping file of the follow export (campaign/instrument_import)
  double follow_timeout_s = 600;
  std::string out;          ///< measurement CSV written when the session is complete
  std::string world_frame;  ///< frame file of `robcal frames world`: positions in that frame
};

/// The operator's side of the session.
struct SessionIo {
  /// Text for the operator (prompts, echoed readings), as it comes, without added newlines.
  std::function<void(const std::string&)> say;
  /// An answer refused (the step is asked again): the located error text.
  std::function<void(const std::string&)> refuse;
  /// The operator's next line; false at the end of the input (the session pauses).
  std::function<bool(std::string&)> read_line;
  /// Time stamp of a reading (ISO 8601 UTC); default utc_now_iso.
  std::function<std::string()> now;
};

enum class SessionStop {
  Complete,       ///< every step answered, the CSV written
  EndOfInput,     ///< the operator's input ended: paused, --resume continues
  FollowTimeout,  ///< the export did not grow within follow_timeout_s: paused
};

struct PointSessionRun {
  SessionStop stop = SessionStop::Complete;
  size_t steps = 0;           ///< steps of the plan (configurations and drift checks)
  size_t answered = 0;        ///< steps answered (journalled), resumed ones included
  size_t resumed = 0;         ///< steps answered by the journal when the run started
  size_t configurations = 0;  ///< configurations of the plan
  SessionResult result;       ///< what the answered steps give (in the instrument's frame)
  Tool tool;                  ///< the tool whose targets the measurements name
  std::string csv;            ///< the measurement CSV written (empty unless complete)
};

/// {read, missing: [config…], drift: [{key, drift_mm, time, temperature_c}]}.
nlohmann::json session_result_json(const SessionResult& result);

/// {status: complete|paused-end-of-input|paused-follow-timeout, steps, answered, resumed,
/// configurations} and session_result_json's entries.
nlohmann::json point_session_json(const PointSessionRun& run);

/// The current time, ISO 8601 UTC with milliseconds ("2026-11-25T04:05:06.789Z").
std::string utc_now_iso();

/// Runs the session until it is complete or paused. Everything that can be refused (plan, tool,
/// reference, --every without a reference, world frame, mapping file, an existing journal
/// without resume, a journal of another plan) is refused before the first prompt.
/// \throws InputError naming the file or the option (--reference, --every, --journal).
PointSessionRun run_point_session(const PointSessionRequest& request, const SessionIo& io);

}  // namespace robcal::campaign
