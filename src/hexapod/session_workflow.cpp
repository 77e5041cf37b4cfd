#include "robcal/hexapod/session_workflow.hpp"

#include <fmt/format.h>

#include <array>

#include <nlohmann/json.hpp>

#include "robcal/core/error.hpp"
#include "robcal/hexapod/plan_file.hpp"
#include "robcal/hexapod/session_answers.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal::hexapod {

HexapodSessionRun run_hexapod_session(const HexapodSessionRequest& request,
                                      const campaign::SessionIo& io) {
  HexapodSessionRun run{HexapodSessionStop::Complete, 0, 0,
                        Session(read_hexapod_plan(request.plan).session)};
  SessionJournal journal = request.resume ? SessionJournal::open_for_resume(request.journal)
                                          : SessionJournal::create(request.journal);
  if (request.resume) {
    run.replayed = journal.replay(run.session);
    run.answered = run.replayed;
    io.say(fmt::format("Resumed {}: {} readings replayed.\n", request.journal, run.replayed));
  }
  while (const std::optional<SessionStep> step = run.session.next_step()) {
    io.say(step->prompt + "\n> ");
    std::string line;
    if (!io.read_line(line)) {
      io.say(fmt::format("\nInput ended. Every reading is in {}; continue with --resume.\n",
                         request.journal));
      run.stop = HexapodSessionStop::EndOfInput;
      return run;
    }
    const SessionAnswer answer = parse_session_answer(line);
    if (answer.kind == SessionAnswer::Kind::Quit) {
      io.say(fmt::format("Stopped. Every reading is in {}; continue with --resume.\n",
                         request.journal));
      run.stop = HexapodSessionStop::Quit;
      return run;
    }
    if (answer.kind == SessionAnswer::Kind::Invalid ||
        (answer.kind == SessionAnswer::Kind::Out && step->kind != StepKind::Leg)) {
      io.refuse(
          fmt::format("'{}' is not a reading: enter a length in mm{}, or 'quit'.", line,
                      step->kind == StepKind::Leg ? ", 'out' when the ballbar does not fit" : ""));
      continue;
    }
    const std::optional<double> reading = answer.kind == SessionAnswer::Kind::Reading
                                              ? std::optional<double>(answer.reading_mm)
                                              : std::nullopt;
    std::string message;
    try {
      message = run.session.record(reading);
    } catch (const InputError& e) {
      io.refuse(e.what());
      continue;
    }
    journal.append(step->key, reading);
    ++run.answered;
    if (!message.empty()) io.say(message + "\n");
  }
  if (!request.out.empty())
    write_file_atomically(request.out, run.session.result_json().dump(2) + "\n");
  return run;
}

nlohmann::json hexapod_session_json(const HexapodSessionRun& run) {
  static constexpr std::array<const char*, 3> kStatus{"complete", "paused-end-of-input",
                                                      "paused-quit"};
  nlohmann::json out{{"status", kStatus[static_cast<size_t>(run.stop)]},
                     {"replayed", run.replayed},
                     {"answered", run.answered}};
  if (run.stop == HexapodSessionStop::Complete) out["result"] = run.session.result_json();
  return out;
}

}  // namespace robcal::hexapod
