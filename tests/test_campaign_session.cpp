// The guided tracker session's journal (issue 16 item 5): cut at any byte (a crash mid-write)
// and resumed, it gives the same measurements as the uninterrupted session; drift checks and
// missing readings are kept; a journal of another plan is refused by line.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <random>

#include "refusal.hpp"
#include "robcal/campaign/point_session.hpp"
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

}  // namespace
}  // namespace robcal::campaign
