#pragma once
/// \file
/// The guided tracker/CMM-probe session (issue 16 item 5): the operator is prompted step by step
/// ("move to C12, measure target 2"), types or pipes each reading, and every reading is appended
/// to a journal and flushed at once, so a crash or Ctrl-C loses nothing and a resumed session
/// continues at the first unanswered step. A reference configuration is re-measured every N
/// configurations (warm-up and drift); a configuration whose reading is missing is marked, not
/// dropped.
///
/// The steps are a pure function of the plan, so the journal (one line per answered step:
/// `key,x,y,z,time[,temperature]` or `key,missing,time`) replays to the same state; the keys
/// are checked on replay.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "robcal/measure/measurements.hpp"
#include "robcal/sim/simulator.hpp"

namespace robcal::campaign {

struct SessionSettings {
  std::vector<PlannedConfiguration> configs;  ///< with the target to read (index into tool)
  Tool tool;                                  ///< target names
  int reference = -1;  ///< index into configs of the reference configuration (−1: none)
  int every = 0;       ///< re-measure the reference before every N-th configuration (0: never)
};

struct SessionStep {
  std::string key;     ///< "C12/2" for a configuration, "ref3/C1/2" for a drift check
  std::string prompt;  ///< what the operator is asked
  int config = 0;      ///< index into configs
  bool drift_check = false;
};

/// The steps: the reference first (when given), then every configuration, with the reference
/// again before every `every`-th one and at the end. \throws InputError for a configuration
/// without a target, or a reference index out of range.
std::vector<SessionStep> session_steps(const SessionSettings& settings);

/// One answered step.
struct SessionReading {
  std::string key;
  std::optional<Eigen::Vector3d> position_mm;  ///< empty: marked missing
  std::string time;                            ///< ISO 8601, UTC
  std::optional<double> temperature_c;
};

/// The operator's answer to `step`: "x y z" (or comma-separated, mm) with an optional fourth
/// number, the temperature in °C, or "skip"/"missing". \throws InputError saying what was
/// expected (the caller asks again).
SessionReading parse_answer(const std::string& line, const SessionStep& step,
                            const std::string& time);

/// The journal line of a reading (ends with a newline), full precision.
std::string journal_line(const SessionReading& reading);

/// The readings of a journal, checked against the steps in order. A last line without its
/// newline (torn by a crash mid-write) is dropped; `complete_bytes` receives the length of the
/// complete lines (the caller truncates the file there before appending). \throws InputError
/// naming file and line for a key that is not the next step's (another plan) or a bad line.
std::vector<SessionReading> replay_journal(const std::string& text, const std::string& file,
                                           const std::vector<SessionStep>& steps,
                                           size_t* complete_bytes = nullptr);

/// A drift check: the reference's reading against the first one.
struct DriftCheck {
  std::string key;
  double drift_mm = 0;
  std::string time;
  std::optional<double> temperature_c;
};

struct SessionResult {
  MeasurementSet measurements;       ///< the configurations read (not the drift checks)
  std::vector<std::string> missing;  ///< configurations marked missing
  std::vector<DriftCheck> drift;     ///< every reference reading after the first
};

/// What the readings so far give (the complete session when every step is answered).
SessionResult session_result(const SessionSettings& settings, const std::vector<SessionStep>& steps,
                             const std::vector<SessionReading>& readings);

}  // namespace robcal::campaign
