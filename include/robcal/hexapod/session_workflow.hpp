#pragma once
/// \file
/// The workflow behind `robcal hexapod session` and Python's hexapod.session: the guided session
/// of session.hpp run on files — the plan read, the journal created or resumed, every step
/// prompted and answered from the operator's lines (session_answers.hpp), every reading
/// journalled at once, and the result file written once every step is answered. The operator's
/// side goes through campaign::SessionIo, so a terminal, a pipe or a Python list drive the same
/// code.

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "robcal/campaign/session_workflow.hpp"
#include "robcal/hexapod/session.hpp"

namespace robcal::hexapod {

struct HexapodSessionRequest {
  std::string plan;     ///< plan file of `robcal hexapod plan` or `replan`
  std::string journal;  ///< append-only journal
  bool resume = false;  ///< continue an existing journal (else it must not exist)
  std::string out;      ///< result JSON written when the session is complete (empty: none)
};

enum class HexapodSessionStop {
  Complete,    ///< every step answered, the result written
  EndOfInput,  ///< the operator's input ended: paused, resume continues
  Quit,        ///< the operator answered "quit": paused, resume continues
};

struct HexapodSessionRun {
  HexapodSessionStop stop = HexapodSessionStop::Complete;
  int replayed = 0;  ///< readings the journal answered when the run started (resume)
  int answered = 0;  ///< readings so far, replayed ones included
  Session session;   ///< the state reached
};

/// Runs the session until it is complete or paused. io.say gets the prompts and the messages
/// ("Resumed …", a reading's note, "Stopped …"), each a whole line; io.refuse an answer that is
/// not a reading for the step (asked again) or a reading the session refuses, with the reason.
/// \throws InputError naming the plan or the journal (an existing journal without resume, a
/// journal of another plan).
HexapodSessionRun run_hexapod_session(const HexapodSessionRequest& request,
                                      const campaign::SessionIo& io);

/// {status: complete|paused-end-of-input|paused-quit, replayed, answered (readings so far),
/// result: the session's result_json() when complete}.
nlohmann::json hexapod_session_json(const HexapodSessionRun& run);

}  // namespace robcal::hexapod
