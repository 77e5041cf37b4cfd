// The guided hexapod session's script and journal: replaying a journal restores the exact state,
// a cut-short last line is dropped, a journal of another plan is refused.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/hexapod/session.hpp"

namespace robcal::hexapod {
namespace {

SessionPlan small_plan() {
  SessionPlan plan;
  plan.recheck_every = 1;
  for (int c = 0; c < 3; ++c) {
    SessionConfiguration config;
    config.id = c + 1;
    config.pose = "P0" + std::to_string(c + 1);
    for (size_t i = 0; i < kDesignLegs.size(); ++i)
      config.legs.push_back({kDesignLegs[i].base, kDesignLegs[i].tool});
    plan.configurations.push_back(config);
  }
  return plan;
}

std::filesystem::path temp_journal(const std::string& name) {
  const auto path = std::filesystem::temp_directory_path() / ("robcal_test_" + name + ".jsonl");
  std::filesystem::remove(path);
  return path;
}

TEST(HexapodSession, ScriptOrderRetryAndRecheck) {
  Session s(small_plan());
  std::vector<std::string> keys;
  int step = 0;
  while (const auto next = s.next_step()) {
    keys.push_back(next->key);
    // Configuration 2's third leg is out of range: retry, its other legs are skipped.
    const bool out = next->key == "leg/2/B2-T1";
    const std::string message = s.record(out ? std::optional<double>(301.2) : 300.0 + 0.001 * step);
    if (out) {
      EXPECT_NE(message.find("retry after preliminary calibration"), std::string::npos);
    }
    ++step;
  }
  // 3 + 3 sides, 6 + 3 + 6 legs, checks after configurations 1 and 2 (not after the last).
  EXPECT_EQ(keys.size(), 3u + 3u + 6u + 3u + 6u + 2u);
  EXPECT_EQ(keys[0], "tool/T1-T2");
  EXPECT_EQ(keys[5], "base/B3-B1");
  EXPECT_EQ(keys[6], "leg/1/B1-T1");
  EXPECT_EQ(keys[12], "check/1");
  EXPECT_EQ(keys[16], "check/2");
  const nlohmann::json result = s.result_json();
  EXPECT_TRUE(result["complete"].get<bool>());
  EXPECT_EQ(result["configurations"][1]["status"], "retry");
  EXPECT_EQ(result["measured"], 2);
  EXPECT_REFUSED(s.record(300.0), InputError, "the session is complete: no reading is expected");
}

TEST(HexapodSession, SideReadingsMustBePositive) {
  Session s(small_plan());
  EXPECT_REFUSED(s.record(std::nullopt), InputError,
                 "tool/T1-T2: expected a positive length in mm");
  EXPECT_REFUSED(s.record(-150.0), InputError, "tool/T1-T2: expected a positive length in mm");
  EXPECT_EQ(s.next_step()->key, "tool/T1-T2");
}

TEST(HexapodSession, JournalReplayRestoresTheStateExactly) {
  const auto path = temp_journal("replay");
  Session straight(small_plan());
  {
    SessionJournal journal = SessionJournal::create(path);
    for (int i = 0; i < 14; ++i) {
      const auto step = straight.next_step();
      const std::optional<double> reading =
          i == 10 ? std::nullopt : std::optional<double>(300.0 + 1e-4 * i + 1.0 / 3.0 * 1e-3);
      straight.record(reading);
      journal.append(step->key, reading);
    }
  }
  EXPECT_REFUSED(SessionJournal::create(path), InputError,  // never overwritten
                 "(--journal): the journal exists already: continue it with --resume");
  Session resumed(small_plan());
  SessionJournal journal = SessionJournal::open_for_resume(path);
  EXPECT_EQ(journal.replay(resumed), 14);
  EXPECT_EQ(resumed.result_json(), straight.result_json());
  EXPECT_EQ(resumed.next_step()->key, straight.next_step()->key);
  std::filesystem::remove(path);
}

TEST(HexapodSession, CutShortLastLineIsDroppedAndForeignJournalRefused) {
  const auto path = temp_journal("cut");
  {
    std::ofstream out(path);
    out << "{\"key\":\"tool/T1-T2\",\"reading\":150.01}\n{\"key\":\"tool/T2-T3\",\"rea";
  }
  {
    Session s(small_plan());
    SessionJournal journal = SessionJournal::open_for_resume(path);
    EXPECT_EQ(journal.replay(s), 1);
    EXPECT_EQ(s.next_step()->key, "tool/T2-T3");
    journal.append("tool/T2-T3", 149.99);
  }
  {
    Session s(small_plan());
    SessionJournal journal = SessionJournal::open_for_resume(path);
    EXPECT_EQ(journal.replay(s), 2);  // the appended entry follows the first on its own line
  }
  {
    std::ofstream out(path);
    out << "{\"key\":\"base/B1-B2\",\"reading\":300.0}\n";
  }
  Session s(small_plan());
  SessionJournal journal = SessionJournal::open_for_resume(path);
  try {
    journal.replay(s);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does not match"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(":1"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(HexapodSession, PlanFileErrorsNameTheKey) {
  const nlohmann::json bad = nlohmann::json::parse(
      R"({"configurations": [{"pose": "P01", "legs": ["B1-T1","B1-T2","B2-T1","B2-T2","B2-T4","B3-T1"]}]})");
  try {
    parse_session_plan(bad, "plan.json");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("configurations[0].legs"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("B2-T4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace robcal::hexapod
