// The hexapod session run on files (session_workflow.hpp) and its answer lines
// (session_answers.hpp): the writer's lines read back exactly, a run paused by the end of its
// input and resumed gives the journal and result of the session script fed the same readings
// directly, refused answers are asked again, "quit" pauses.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "robcal/hexapod/plan_file.hpp"
#include "robcal/hexapod/session_answers.hpp"
#include "robcal/hexapod/session_workflow.hpp"

namespace robcal::hexapod {
namespace {

using Kind = SessionAnswer::Kind;

TEST(HexapodSessionAnswers, ReadsWhatTheWriterWritesAndNothingElse) {
  for (double v : {299.987654321987, 300.0, 1e-7, -0.5, 150.0123})
    EXPECT_EQ(parse_session_answer(session_answer_text(v)).reading_mm, v) << v;
  EXPECT_EQ(session_answer_text(std::nullopt), "out");
  EXPECT_EQ(parse_session_answer(session_answer_text(std::nullopt)).kind, Kind::Out);
  EXPECT_EQ(parse_session_answer(" \t300.25\r").kind, Kind::Reading);
  EXPECT_EQ(parse_session_answer(" \t300.25\r").reading_mm, 300.25);
  EXPECT_EQ(parse_session_answer("x").kind, Kind::Out);
  EXPECT_EQ(parse_session_answer("quit").kind, Kind::Quit);
  EXPECT_EQ(parse_session_answer("q").kind, Kind::Quit);
  for (const char* bad : {"", "   ", "abc", "300.5mm", "1e999", "nan", "inf", "3 00", "outside"})
    EXPECT_EQ(parse_session_answer(bad).kind, Kind::Invalid) << bad;
}

/// Two configurations, no calibrator re-check: 3 tool sides, 3 base sides, 6 + 6 legs.
std::filesystem::path write_plan(const std::filesystem::path& dir) {
  const std::string legs = R"(["B1-T1","B1-T2","B2-T1","B2-T2","B2-T3","B3-T1"])";
  const auto path = dir / "plan.json";
  std::ofstream(path) << R"({"ballbar": {"tool_mm": 150, "leg_mm": 300, "range_mm": 1,
    "recheck_every": 0}, "configurations": [{"pose": "P01", "legs": )"
                      << legs << R"(}, {"pose": "P07", "legs": )" << legs << "}]}";
  return path;
}

struct Operator {
  std::vector<std::string> lines;
  size_t next = 0;
  std::string said;
  std::vector<std::string> refused;
  [[nodiscard]] campaign::SessionIo io() {
    return {[this](const std::string& text) { said += text; },
            [this](const std::string& why) { refused.push_back(why); },
            [this](std::string& line) {
              if (next >= lines.size()) return false;
              line = lines[next++];
              return true;
            },
            {}};
  }
};

std::string read_text(const std::filesystem::path& path) {
  std::stringstream text;
  text << std::ifstream(path).rdbuf();
  return text.str();
}

TEST(HexapodSessionWorkflow, PausedAndResumedGivesTheScriptsResult) {
  const auto dir = std::filesystem::temp_directory_path() / "robcal_test_session_workflow";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto plan = write_plan(dir);
  // Configuration 2's second leg is out of the ballbar's range: retry, its other legs skipped.
  const std::vector<std::optional<double>> readings{150.01, 149.99, 150.02, 300.01,      299.98,
                                                    300.03, 300.1,  300.2,  299.9,       300.05,
                                                    299.95, 300.0,  300.3,  std::nullopt};
  std::vector<std::string> lines;
  for (const auto& r : readings) lines.push_back(session_answer_text(r));

  Operator first;
  first.lines.assign(lines.begin(), lines.begin() + 8);
  first.lines.insert(first.lines.begin() + 7, "abc");  // a leg's: refused, asked again
  first.lines.insert(first.lines.begin() + 2, "out");  // not for a side: refused
  const HexapodSessionRequest request{plan.string(), (dir / "journal.jsonl").string(), false,
                                      (dir / "result.json").string()};
  const HexapodSessionRun paused = run_hexapod_session(request, first.io());
  EXPECT_EQ(paused.stop, HexapodSessionStop::EndOfInput);
  EXPECT_EQ(paused.answered, 8);
  ASSERT_EQ(first.refused.size(), 2u);
  EXPECT_EQ(first.refused[0], "'out' is not a reading: enter a length in mm, or 'quit'.");
  EXPECT_EQ(first.refused[1],
            "'abc' is not a reading: enter a length in mm, 'out' when the ballbar does not fit, "
            "or 'quit'.");
  EXPECT_FALSE(std::filesystem::exists(dir / "result.json"));
  EXPECT_EQ(hexapod_session_json(paused)["status"], "paused-end-of-input");
  EXPECT_FALSE(hexapod_session_json(paused).contains("result"));

  // Resumed: the journal answers the first 8 steps; "quit" pauses without a reading.
  Operator quitter{{lines[8], "quit"}};
  HexapodSessionRequest resume = request;
  resume.resume = true;
  const HexapodSessionRun quit = run_hexapod_session(resume, quitter.io());
  EXPECT_EQ(quit.stop, HexapodSessionStop::Quit);
  EXPECT_EQ(quit.replayed, 8);
  EXPECT_EQ(quit.answered, 9);
  EXPECT_NE(quitter.said.find("Resumed "), std::string::npos);

  Operator rest{{lines.begin() + 9, lines.end()}};
  const HexapodSessionRun done = run_hexapod_session(resume, rest.io());
  EXPECT_EQ(done.stop, HexapodSessionStop::Complete);
  EXPECT_EQ(done.replayed, 9);
  EXPECT_EQ(done.answered, static_cast<int>(readings.size()));

  // The session script fed the same readings directly.
  Session straight(read_hexapod_plan(plan).session);
  for (const auto& r : readings) straight.record(r);
  EXPECT_FALSE(straight.next_step());
  EXPECT_EQ(done.session.result_json(), straight.result_json());
  EXPECT_EQ(nlohmann::json::parse(read_text(dir / "result.json")), straight.result_json());
  EXPECT_EQ(straight.result_json()["measured"], 1);
  EXPECT_EQ(straight.result_json()["retry_after_preliminary_calibration"], 1);
  const nlohmann::json report = hexapod_session_json(done);
  EXPECT_EQ(report["status"], "complete");
  EXPECT_EQ(report["result"], straight.result_json());
  // One journal line per reading.
  std::istringstream journal(read_text(dir / "journal.jsonl"));
  int journal_lines = 0;
  for (std::string line; std::getline(journal, line);) ++journal_lines;
  EXPECT_EQ(journal_lines, static_cast<int>(readings.size()));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace robcal::hexapod
