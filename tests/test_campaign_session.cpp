// The guided tracker session's journal (issue 16 item 5): cut at any byte (a crash mid-write)
// and resumed, it gives the same measurements as the uninterrupted session; drift checks and
// missing readings are kept; a journal of another plan is refused by line.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <filesystem>
#include <random>

#include "refusal.hpp"
#include "robcal/campaign/point_session.hpp"
#include "robcal/campaign/session_workflow.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal::campaign {
namespace {

struct Fixture {
  SessionSettings settings;
  std::vector<SessionStep> steps;
  std::vector<std::string> answers;  ///< what the operator types, step by step
  Fixture() {
    const TrueRobot truth =
        published_irb120_truth(load_robot("abb-irb120"), default_simulation_tool());
    const VirtualInstrument tracker = standard_instrument(InstrumentKind::LaserTracker, truth);
    std::mt19937_64 rng(4);
    RandomConfigurationOptions options;
    options.box = published_joint_box(truth.robot.model);
    settings.configs = random_configurations(truth, tracker, 10, rng, options);
    settings.tool = default_simulation_tool();
    settings.reference = 0;
    settings.every = 3;
    steps = session_steps(settings);
    const auto read = simulate_measurements(truth, tracker, settings.configs, rng).measurements;
    int drift = 0;
    for (const SessionStep& s : steps) {
      const Eigen::Vector3d p = read.points[static_cast<size_t>(s.config)].position_mm +
                                Eigen::Vector3d(0, 0, s.drift_check ? 0.01 * drift++ : 0.0);
      answers.push_back(
          s.key.rfind("R5/", 0) == 0  // the operator could not read R5
              ? "skip"
              : fmt::format("{:.17g} {:.17g} {:.17g} {}", p.x(), p.y(), p.z(), 20 + drift));
    }
  }
  [[nodiscard]] std::string journal(size_t from, size_t to) const {
    std::string text;
    for (size_t i = from; i < to; ++i)
      text += journal_line(parse_answer(answers[i], steps[i], fmt::format("t{}", i)));
    return text;
  }
};

TEST(CampaignSession, StepsInterleaveTheReferenceEveryNConfigurations) {
  const Fixture f;
  ASSERT_EQ(f.steps.size(), 15u);  // reference, 10 configurations, 3 checks between, 1 at the end
  EXPECT_TRUE(f.steps[0].drift_check);
  EXPECT_EQ(
      f.steps[0].key,
      "ref1/R1/" + f.settings.tool.targets[static_cast<size_t>(f.settings.configs[0].target)].name);
  EXPECT_TRUE(f.steps[4].drift_check);  // before the 4th configuration
  EXPECT_TRUE(f.steps.back().drift_check);
  EXPECT_NE(f.steps[1].prompt.find("move to R1 (joints"), std::string::npos) << f.steps[1].prompt;
}

TEST(CampaignSession, AJournalCutAtAnyByteResumesToTheSameMeasurements) {
  const Fixture f;
  const std::string whole = f.journal(0, f.steps.size());
  const SessionResult expected =
      session_result(f.settings, f.steps, replay_journal(whole, "j", f.steps));
  ASSERT_EQ(expected.measurements.points.size(), 9u);
  ASSERT_EQ(expected.missing, std::vector<std::string>{"R5"});
  ASSERT_EQ(expected.drift.size(), 4u);
  EXPECT_NEAR(expected.drift.back().drift_mm, 0.04, 1e-9);
  std::mt19937_64 rng(11);
  for (int run = 0; run < 200; ++run) {
    const size_t cut = std::uniform_int_distribution<size_t>(0, whole.size())(rng);
    size_t complete = 0;
    const auto before = replay_journal(whole.substr(0, cut), "j", f.steps, &complete);
    // The torn tail is dropped; the session asks again from the first unanswered step.
    const std::string resumed =
        whole.substr(0, complete) + f.journal(before.size(), f.steps.size());
    ASSERT_EQ(resumed, whole) << "cut at byte " << cut;
    const SessionResult got =
        session_result(f.settings, f.steps, replay_journal(resumed, "j", f.steps));
    ASSERT_EQ(got.measurements.points.size(), expected.measurements.points.size());
    for (size_t i = 0; i < got.measurements.points.size(); ++i)
      ASSERT_EQ(got.measurements.points[i].position_mm,
                expected.measurements.points[i].position_mm);
  }
}

TEST(CampaignSession, BadAnswersAndForeignJournalsAreRefused) {
  const Fixture f;
  EXPECT_REFUSED(parse_answer("1 2", f.steps[0], "t"), InputError,
                 "reading (" + f.steps[0].key + "): expected 'x y z' in mm");
  EXPECT_REFUSED(parse_answer("1 2 x", f.steps[0], "t"), InputError,
                 "reading (z): 'x' is not a number: expected a coordinate in mm");
  EXPECT_FALSE(parse_answer(" skip ", f.steps[0], "t").position_mm.has_value());
  const SessionReading r = parse_answer("1,2.5,-3, 21.5", f.steps[0], "t");
  EXPECT_EQ(*r.position_mm, Eigen::Vector3d(1, 2.5, -3));
  EXPECT_EQ(*r.temperature_c, 21.5);
  // A journal whose second line is another plan's step.
  std::string journal = f.journal(0, 1) + "C99/1,1,2,3,t\n";
  try {
    replay_journal(journal, "session.journal", f.steps);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("session.journal:2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("another plan"), std::string::npos) << e.what();
  }
}

/// The session workflow on files (run_point_session), with the operator's lines from a list.
struct SessionFiles {
  std::filesystem::path dir;
  PointSessionRequest request;
  explicit SessionFiles(const Fixture& f, const std::string& name) {
    dir = std::filesystem::path(::testing::TempDir()) / ("robcal_session_" + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    request.configs = (dir / "plan.csv").string();
    write_file_atomically(request.configs,
                          write_configurations_csv(f.settings.configs, f.settings.tool));
    request.journal = (dir / "journal").string();
    request.out = (dir / "out.csv").string();
    request.reference = f.settings.configs[0].name;
    request.every = f.settings.every;
  }
  ~SessionFiles() { std::filesystem::remove_all(dir); }
  SessionFiles(const SessionFiles&) = delete;
  SessionFiles& operator=(const SessionFiles&) = delete;

  /// Runs the session on answers[from, to); the transcript in `said`.
  PointSessionRun run(const std::vector<std::string>& answers, size_t from, size_t to) {
    size_t next = from;
    const SessionIo io{[this](const std::string& text) { said += text; },
                       [this](const std::string& error) { refused.push_back(error); },
                       [&](std::string& line) {
                         if (next >= to) return false;
                         line = answers[next++];
                         return true;
                       },
                       [] { return std::string("t"); }};
    return run_point_session(request, io);
  }
  std::string said;
  std::vector<std::string> refused;
};

TEST(CampaignSessionWorkflow, PausedAndResumedGivesTheUninterruptedSessionsFile) {
  const Fixture f;
  SessionFiles whole(f, "whole");
  const PointSessionRun all = whole.run(f.answers, 0, f.answers.size());
  ASSERT_EQ(all.stop, SessionStop::Complete);
  EXPECT_EQ(all.steps, f.steps.size());
  EXPECT_EQ(all.answered, f.steps.size());
  EXPECT_EQ(all.configurations, 10u);
  EXPECT_EQ(all.result.missing, std::vector<std::string>{"R5"});
  ASSERT_EQ(all.result.drift.size(), 4u);
  EXPECT_NEAR(all.result.drift.back().drift_mm, 0.04, 1e-9);
  EXPECT_EQ(read_text_file(whole.request.out), all.csv);
  // The journal is the step functions' journal of the same answers.
  EXPECT_EQ(read_text_file(whole.request.journal), [&] {
    std::string text;
    for (size_t i = 0; i < f.steps.size(); ++i)
      text += journal_line(parse_answer(f.answers[i], f.steps[i], "t"));
    return text;
  }());
  // The file's positions are the typed ones, config by config.
  const MeasurementSet read =
      read_measurements_csv(whole.request.out, f.settings.tool).measurements;
  const SessionResult expected = session_result(
      f.settings, f.steps, replay_journal(read_text_file(whole.request.journal), "j", f.steps));
  ASSERT_EQ(read.points.size(), 9u);
  for (size_t i = 0; i < read.points.size(); ++i) {
    EXPECT_EQ(read.points[i].config, expected.measurements.points[i].config);
    EXPECT_LT((read.points[i].position_mm - expected.measurements.points[i].position_mm).norm(),
              1e-9);
  }

  for (const size_t k : {size_t{1}, size_t{6}, f.answers.size() - 1}) {
    SessionFiles split(f, "split");
    const PointSessionRun first = split.run(f.answers, 0, k);
    EXPECT_EQ(first.stop, SessionStop::EndOfInput);
    EXPECT_EQ(first.answered, k);
    EXPECT_FALSE(std::filesystem::exists(split.request.out));
    EXPECT_REFUSED(split.run(f.answers, k, f.answers.size()), InputError,
                   "the journal exists: pass --resume");
    split.request.resume = true;
    split.said.clear();
    const PointSessionRun second = split.run(f.answers, k, f.answers.size());
    EXPECT_EQ(second.stop, SessionStop::Complete);
    EXPECT_EQ(second.resumed, k);
    EXPECT_EQ(split.said.rfind(fmt::format("resumed {}: {} of {} steps answered\n",
                                           split.request.journal, k, f.steps.size()),
                               0),
              0u)
        << split.said;
    EXPECT_EQ(read_text_file(split.request.out), all.csv) << "paused after " << k;
  }
}

TEST(CampaignSessionWorkflow, RefusesBeforeTheFirstPromptAndAsksABadAnswerAgain) {
  const Fixture f;
  SessionFiles s(f, "refusals");
  s.request.reference = "R99";
  EXPECT_REFUSED(s.run(f.answers, 0, 0), InputError,
                 "--reference: configuration 'R99' is not in " + s.request.configs);
  s.request.reference.clear();
  EXPECT_REFUSED(s.run(f.answers, 0, 0), InputError,
                 "--every: drift checks need the reference (--reference NAME)");
  EXPECT_FALSE(std::filesystem::exists(s.request.journal));
  EXPECT_TRUE(s.said.empty());
  s.request.every = 0;
  std::vector<std::string> answers = {"1 2", "1 2 3", "skip"};
  const PointSessionRun run = s.run(answers, 0, answers.size());
  EXPECT_EQ(run.stop, SessionStop::EndOfInput);
  EXPECT_EQ(run.answered, 2u);
  ASSERT_EQ(s.refused.size(), 1u);
  EXPECT_NE(s.refused[0].find("expected 'x y z' in mm"), std::string::npos) << s.refused[0];
  // The first step is asked twice (the refused answer), then the second once, the third once.
  EXPECT_EQ(s.said.find("[1/10] move to R1"), 0u) << s.said;
  EXPECT_NE(s.said.find("[1/10]", 1), std::string::npos);
  EXPECT_NE(s.said.find("[3/10]"), std::string::npos);
}

TEST(CampaignSessionWorkflow, FollowsAGrowingExportAndPausesWhenItStops) {
  const Fixture f;
  SessionFiles s(f, "follow");
  s.request.follow = (s.dir / "export.txt").string();
  s.request.follow_timeout_s = 0.2;
  std::string text = "x y z\n";
  for (size_t i = 0; i < 3; ++i) text += f.answers[i].substr(0, f.answers[i].rfind(' ')) + "\n";
  write_file_atomically(s.request.follow, text);
  const PointSessionRun run = s.run({}, 0, 0);
  EXPECT_EQ(run.stop, SessionStop::FollowTimeout);
  EXPECT_EQ(run.answered, 3u);
  EXPECT_EQ(run.result.measurements.points.size(), 2u);  // the reference's reading is not one
  EXPECT_EQ(read_text_file(s.request.journal), [&] {
    std::string journal;
    for (size_t i = 0; i < 3; ++i) {
      SessionReading r = parse_answer(f.answers[i], f.steps[i], "t");
      r.temperature_c.reset();  // an export has no temperature
      journal += journal_line(r);
    }
    return journal;
  }());
}

}  // namespace
}  // namespace robcal::campaign
