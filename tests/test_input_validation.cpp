// Bad input never passes silently (issue 21): the shared number reader, unknown and duplicate
// YAML keys, plausible ranges, duplicate pose names, JSON numbers beyond the double range in a
// session plan or journal, the journal's lock, and the simulation folder written whole.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/hexapod/session.hpp"
#include "robcal/io/number_text.hpp"
#include "robcal/io/pose_list_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/yaml_checks.hpp"
#include "robcal/sim/simulation_files.hpp"
#include "robcal/sim/simulator.hpp"
#include "robcal/sim/true_robot.hpp"

namespace robcal {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("robcal_validation_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

TEST(NumberText, ReadsWholeFiniteDecimalsOnly) {
  EXPECT_EQ(parse_number("364.35"), 364.35);
  EXPECT_EQ(parse_number("-1.5e3"), -1500.0);
  EXPECT_EQ(parse_number("+2"), 2.0);
  EXPECT_EQ(parse_number(".5"), 0.5);
  for (const char* bad : {"364.35.4", "1e999", "-1e999", "nan", "inf", "-inf", "infinity", "0x10",
                          "12mm", "", "+", "+-1", "1,5", " 1", "1 ", "e5", "--1"})
    EXPECT_FALSE(parse_number(bad).has_value()) << bad;
  EXPECT_EQ(parse_integer("42"), 42);
  EXPECT_EQ(parse_integer("-7"), -7);
  EXPECT_FALSE(parse_integer("1.0").has_value());
  EXPECT_FALSE(parse_integer("99999999999999999999").has_value());
  EXPECT_EQ(describe_bad_number("1e999"),
            "'1e999' is outside the range of double-precision numbers");
  EXPECT_EQ(describe_bad_number("364.35.4"), "expected a number, found '364.35.4'");
}

const char* const kRobot = R"(name: r
mdh:
  - [0, 0, 0, 290]
  - [-90, 0, -90, 0]
  - [0, 270, 0, 0]
  - [-90, 70, 0, 302]
  - [90, 0, 0, 0]
  - [-90, 0, 180, 72]
joint_limits_deg: [[-165, 165], [-110, 110], [-110, 70], [-160, 160], [-120, 120], [-400, 400]]
masses:
  2: {mass_kg: 4.2, cog_mm: [140, 0, 0]}
)";

std::string robot_refusal(const std::string& old_text, const std::string& new_text) {
  std::string text = kRobot;
  const size_t at = text.find(old_text);
  EXPECT_NE(at, std::string::npos) << old_text;
  text.replace(at, old_text.size(), new_text);
  return test::refusal_message([&] { (void)parse_robot(yaml::parse(text, "r.yaml")); });
}

TEST(YamlValidation, RobotFileRefusesTyposDuplicatesAndAbsurdNumbers) {
  EXPECT_EQ(test::refusal_message([] { (void)parse_robot(yaml::parse(kRobot, "r.yaml")); }), "");
  struct Case {
    const char* old_text;
    const char* new_text;
    const char* message;
  };
  const Case cases[] = {
      {"masses:", "masess:",
       "r.yaml:10:1 (masess): unknown key 'masess': did you mean 'masses'? (expected one of: "
       "name, manufacturer, source, euler, mdh, joint_limits_deg, masses, gravity_m_s2, "
       "joint_map, reach_mm, pulses_per_degree, gravity_base_m_s2, mounting_deg, "
       "reference_temperature_c, gear_ratio, warmup_time_constant_s)"},
      {"masses:", "colour: red\nmasses:",
       "r.yaml:10:1 (colour): unknown key 'colour' (expected one of: name, manufacturer, source, "
       "euler, mdh, joint_limits_deg, masses, gravity_m_s2, joint_map, reach_mm, "
       "pulses_per_degree, gravity_base_m_s2, mounting_deg, reference_temperature_c, gear_ratio, "
       "warmup_time_constant_s)"},
      {"masses:", "name: s\nmasses:",
       "r.yaml:10:1 (name): key 'name' given twice in this map (first on line 1)"},
      {"[0, 270, 0, 0]", "[0, 270.5.1, 0, 0]",
       "r.yaml:5:9 (mdh[2][1]): expected a number, found '270.5.1'"},
      {"[0, 270, 0, 0]", "[0, 1e999, 0, 0]",
       "r.yaml:5:9 (mdh[2][1]): '1e999' is outside the range of double-precision numbers"},
      {"[0, 270, 0, 0]", "[0, 2.7e5, 0, 0]",
       "r.yaml:5:9 (mdh[2][1]): 2.7e5 is outside the plausible range [-20000, 20000] mm"},
      {"mass_kg: 4.2", "mass_kg: -4.2",
       "r.yaml:11:16 (masses.2.mass_kg): -4.2 is outside the plausible range [0, 10000] kg"},
      {"mass_kg: 4.2", "mas_kg: 4.2",
       "r.yaml:11:7 (masses.2.mas_kg): unknown key 'mas_kg': did you mean 'mass_kg'? (expected "
       "one of: mass_kg, cog_mm)"},
      {"  2: {", "  8: {", "r.yaml:11:6 (masses.8): mass key '8': expected a link number 1..6"},
  };
  for (const Case& c : cases) EXPECT_EQ(robot_refusal(c.old_text, c.new_text), c.message);
}

TEST(YamlValidation, ToolFileRefusesTyposAndDuplicateTargets) {
  const fs::path dir = fresh_dir("tool");
  const auto load = [&](const std::string& text) {
    write(dir / "t.yaml", text);
    return test::refusal_message([&] { (void)load_tool((dir / "t.yaml").string()); });
  };
  const std::string good =
      "payload: {mass_kg: 2.6, cog_mm: [0, 0, 100]}\ntargets:\n"
      "  \"1\": [0, 0, 125]\n  \"2\": [75, 93.675, 215]\n";
  EXPECT_EQ(load(good), "");
  EXPECT_NE(load("paylaod: {mass_kg: 2.6, cog_mm: [0, 0, 100]}\n")
                .find("t.yaml:1:1 (paylaod): unknown key 'paylaod': did you mean 'payload'?"),
            std::string::npos);
  EXPECT_EQ(load(good + "  \"1\": [1, 1, 1]\n"),
            (dir / "t.yaml").string() +
                ":5:3 (targets.1): key '1' given twice in this map (first on line 3)");
  EXPECT_NE(load("payload: {mass_kg: 26000, cog_mm: [0, 0, 100]}\n")
                .find("(payload.mass_kg): 26000 is outside the plausible range [0, 5000] kg"),
            std::string::npos);
  EXPECT_NE(load("just text\n").find("expected a map"), std::string::npos);
}

TEST(YamlValidation, NearestWordSuggestsOnlyTypos) {
  EXPECT_EQ(yaml::nearest_word("masess", {"name", "masses", "mdh"}), "masses");
  EXPECT_EQ(yaml::nearest_word("paylaod", {"payload", "targets", "tcp"}), "payload");
  EXPECT_EQ(yaml::nearest_word("colour", {"payload", "targets", "tcp"}), "");
}

TEST(YamlValidation, AliasesAreWalkedOnceNotExponentially) {
  // Nine levels of nine aliases would be 9^9 nodes if each alias were walked again.
  std::string text = "a0: &a0 [1, 2]\n";
  for (int i = 1; i < 10; ++i) {
    text += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 9; ++k) text += (k ? ", *a" : "*a") + std::to_string(i - 1);
    text += "]\n";
  }
  EXPECT_NO_THROW((void)yaml::parse(text, "alias.yaml"));
  EXPECT_EQ(test::refusal_message([&] { (void)yaml::parse(text + "a3: 1\n", "alias.yaml"); }),
            "alias.yaml:11:1 (a3): key 'a3' given twice in this map (first on line 4)");
}

TEST(PoseListValidation, RefusesDuplicateNamesAndAbsurdCoordinates) {
  const std::string header = "name,x,y,z,qw,qx,qy,qz\n";
  EXPECT_EQ(test::refusal_message([&] {
              (void)parse_pose_list(header + "p1,400,0,500,0,0,1,0\np1,410,0,500,0,0,1,0\n",
                                    "p.csv");
            }),
            "p.csv:3:1 (name): pose 'p1' is listed twice (first on line 2)");
  EXPECT_EQ(test::refusal_message(
                [&] { (void)parse_pose_list(header + "p1,364.35.4,0,500,0,0,1,0\n", "p.csv"); }),
            "p.csv:2:4 (x): expected a number, found '364.35.4'");
  EXPECT_EQ(test::refusal_message(
                [&] { (void)parse_pose_list(header + "p1,400,1e999,500,0,0,1,0\n", "p.csv"); }),
            "p.csv:2:8 (y): '1e999' is outside the range of double-precision numbers");
  EXPECT_EQ(test::refusal_message(
                [&] { (void)parse_pose_list(header + "p1,400,0,4e7,0,0,1,0\n", "p.csv"); }),
            "p.csv:2:10 (z): 4e7 mm is outside the plausible range [-20000, 20000] mm");
}

const char* const kPlan =
    R"({"ballbar": {"tool_mm": 150, "leg_mm": 300, "range_mm": 1},
 "configurations": [
  {"pose": "P01", "joints_deg": [10, 20, -5, 0, 45, 30],
   "legs": ["B1-T1","B1-T2","B2-T1","B2-T2","B2-T3","B3-T1"]}]}
)";

TEST(SessionValidation, JsonNumbersBeyondRangeAreLocated) {
  const fs::path dir = fresh_dir("plan");
  std::string plan = kPlan;
  plan.replace(plan.find("[10, 20"), 7, "[10, 1e999");
  write(dir / "plan.json", plan);
  EXPECT_EQ(test::refusal_message([&] { (void)hexapod::load_session_plan(dir / "plan.json"); }),
            (dir / "plan.json").string() +
                ":3:38: the number 1e999 is outside the range of double-precision numbers");
  write(dir / "plan.json", kPlan);
  write(dir / "journal.jsonl",
        "{\"key\":\"tool/T1-T2\",\"reading\":150}\n{\"key\":\"tool/T2-T3\",\"reading\":-2e999}\n");
  hexapod::Session session(hexapod::load_session_plan(dir / "plan.json"));
  EXPECT_EQ(test::refusal_message([&] {
              (void)hexapod::SessionJournal::replay_read_only(dir / "journal.jsonl", session);
            }),
            (dir / "journal.jsonl").string() +
                ":2:31: the number -2e999 is outside the range of double-precision numbers");
  write(dir / "journal.jsonl", "{\"key\":\"tool/T1-T2\",\"reading\":-150}\n");
  hexapod::Session again(hexapod::load_session_plan(dir / "plan.json"));
  EXPECT_EQ(test::refusal_message([&] {
              (void)hexapod::SessionJournal::replay_read_only(dir / "journal.jsonl", again);
            }),
            (dir / "journal.jsonl").string() + ":1: tool/T1-T2: expected a positive length in mm");
}

TEST(SessionValidation, ASecondWriterOfAJournalIsRefusedWithTheHoldersPid) {
  const fs::path dir = fresh_dir("lock");
  const fs::path path = dir / "journal.jsonl";
  {
    hexapod::SessionJournal first = hexapod::SessionJournal::create(path);
    first.append("tool/T1-T2", 150.0);
    const std::string expected = path.string() +
                                 " (--journal): the journal is in use by another session "
                                 "(process " +
                                 std::to_string(::getpid()) + "): finish or stop that one first";
    EXPECT_EQ(test::refusal_message([&] { (void)hexapod::SessionJournal::open_for_resume(path); }),
              expected);
    // Another process is refused too, and told this one's PID.
    const pid_t child = ::fork();
    if (child == 0) {
      const std::string message =
          test::refusal_message([&] { (void)hexapod::SessionJournal::open_for_resume(path); });
      ::_exit(message == expected ? 0 : 1);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  // Closed: the lock is gone, the journal can be continued.
  hexapod::SessionJournal resumed = hexapod::SessionJournal::open_for_resume(path);
  hexapod::SessionPlan plan;
  plan.configurations.resize(1);
  hexapod::Session session(plan);
  EXPECT_EQ(resumed.replay(session), 1);
}

TEST(SimulationFiles, TheFolderAppearsWholeOrNotAtAll) {
  const fs::path dir = fresh_dir("simulate");
  const RobotModel model = load_robot("abb-irb120");
  const Tool tool = default_simulation_tool();
  const TrueRobot truth = published_irb120_truth(model, tool);
  const VirtualInstrument tracker = standard_instrument(InstrumentKind::LaserTracker, truth, 0);
  std::mt19937_64 rng(3);
  const std::vector<PlannedConfiguration> configs =
      random_configurations(truth, tracker, 3, rng, RandomConfigurationOptions{});
  const SimulationResult result = simulate_measurements(truth, tracker, configs, rng);
  const SimulationFiles files =
      write_simulation(dir / "out", "m", result, tool, tracker, truth, "abb-irb120", "test");
  EXPECT_TRUE(fs::exists(files.measurements) && fs::exists(files.truth));
  // Only the folder itself beside it: no staging folder left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
  // Again into the same (now full) folder: replaced file by file, other files kept.
  write(dir / "out" / "notes.txt", "mine");
  (void)write_simulation(dir / "out", "m", result, tool, tracker, truth, "abb-irb120", "test");
  EXPECT_TRUE(fs::exists(dir / "out" / "notes.txt"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
  // A file in the way: refused, nothing written beside it.
  write(dir / "blocked", "x");
  EXPECT_EQ(test::refusal_message([&] {
              (void)write_simulation(dir / "blocked", "m", result, tool, tracker, truth,
                                     "abb-irb120", "test");
            }),
            (dir / "blocked").string() +
                " (--out): exists and is not a folder: expected a folder to write into, or a new "
                "path");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 2);
}

}  // namespace
}  // namespace robcal
