// Measurement programs (issue 17 item 2): what is written for each controller reads back to
// the planned configurations and their q − 5° approaches, split at the size limits, with the
// counts the controllers check; bad requests are refused by name.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <random>
#include <regex>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/robot_pulses.hpp"
#include "robcal/programs/measurement_program.hpp"

namespace robcal {
namespace {

const std::array<double, kJointCount> kPulses{1341.4, 1341.4, 1341.4, 1000.0, 1000.0, 640.0};

/// Seven configurations with awkward values (many digits, negative, near ±180°), seed 17.
MeasurementProgramRequest request_for(ProgramLanguage language) {
  MeasurementProgramRequest r;
  r.language = language;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-170.0, 170.0);
  for (int i = 0; i < 7; ++i) {
    Vector6d q_deg;
    for (int j = 0; j < kJointCount; ++j) q_deg[j] = u(rng);
    r.names.push_back(fmt::format("c{:03d}", i + 1));
    r.joints.push_back(q_deg * kDegToRad);
  }
  r.max_configs_per_file = 3;
  r.pulses_per_degree = kPulses;
  r.hook = language == ProgramLanguage::Krl || language == ProgramLanguage::Jbi
               ? MeasurementHook::WaitInput
               : MeasurementHook::LogLine;
  return r;
}

class MeasurementProgram : public ::testing::TestWithParam<ProgramLanguage> {};

TEST_P(MeasurementProgram, ReadsBackToTheConfigurationsAndTheirApproaches) {
  const ProgramLanguage language = GetParam();
  const MeasurementProgramRequest r = request_for(language);
  const std::vector<ProgramFile> files = write_measurement_program(r);
  ASSERT_EQ(files.size(), 3u);  // 7 configurations, 3 per file
  std::vector<JointMove> moves;
  for (size_t f = 0; f < files.size(); ++f) {
    const std::string& name = files[f].name;
    EXPECT_EQ(program_language_from_path(name), language) << name;
    EXPECT_NE(name.find(fmt::format("{:02d}", f + 1)), std::string::npos) << name;
    const auto part = read_joint_moves(files[f].text, language, name, kPulses);
    EXPECT_EQ(part.size(), f < 2 ? 6u : 2u) << name;
    moves.insert(moves.end(), part.begin(), part.end());
  }
  ASSERT_EQ(moves.size(), 2 * r.joints.size());
  for (size_t i = 0; i < r.joints.size(); ++i) {
    const Vector6d q = r.joints[i] * kRadToDeg;
    const Vector6d approach = q - Vector6d::Constant(5.0);
    for (int j = 0; j < kJointCount; ++j) {
      if (language == ProgramLanguage::Jbi) {
        // Integer pulses: exactly the rounded count, within half a pulse of the plan.
        const double ppd = kPulses[static_cast<size_t>(j)];
        EXPECT_NEAR(moves[2 * i].joints_deg[j], std::round(approach[j] * ppd) / ppd, 1e-9);
        EXPECT_NEAR(moves[2 * i + 1].joints_deg[j], std::round(q[j] * ppd) / ppd, 1e-9);
        EXPECT_LE(std::abs(moves[2 * i + 1].joints_deg[j] - q[j]), 0.5 / ppd + 1e-12);
      } else {
        EXPECT_NEAR(moves[2 * i].joints_deg[j], approach[j], 1e-6) << i << " " << j;
        EXPECT_NEAR(moves[2 * i + 1].joints_deg[j], q[j], 1e-6) << i << " " << j;
      }
    }
  }
}

TEST_P(MeasurementProgram, EachConfigurationHasItsHookAndSettleWait) {
  const ProgramLanguage language = GetParam();
  MeasurementProgramRequest r = request_for(language);
  r.max_configs_per_file = 0;  // the language's default: one file
  r.hook = MeasurementHook::PulseOutput;
  r.signal = 7;
  const auto files = write_measurement_program(r);
  ASSERT_EQ(files.size(), 1u);
  const std::string& text = files[0].text;
  const auto count = [&](const std::string& pattern) {
    const std::regex re(pattern);
    return std::distance(std::sregex_iterator(text.begin(), text.end(), re),
                         std::sregex_iterator());
  };
  const std::map<ProgramLanguage, std::pair<std::string, std::string>> hook_and_wait{
      {ProgramLanguage::Rapid,
       {R"(PulseDO \\PLength:=0\.5, doRobcalMeasure;)", R"(WaitTime 1\.00;)"}},
      {ProgramLanguage::Krl, {R"(PULSE\(\$OUT\[7\], TRUE, 0\.5\))", R"(WAIT SEC 1\.00)"}},
      {ProgramLanguage::FanucLs, {R"(DO\[7\]=PULSE,0\.5sec ;)", R"(WAIT 1\.00\(sec\) ;)"}},
      {ProgramLanguage::Jbi, {R"(PULSE OT#\(7\) T=0\.50)", R"(TIMER T=1\.00)"}},
      {ProgramLanguage::UrScript, {R"(set_standard_digital_out\(7, True\))", R"(sleep\(1\.00\))"}},
  };
  EXPECT_EQ(count(hook_and_wait.at(language).first), 7) << text;
  EXPECT_EQ(count(hook_and_wait.at(language).second), 7) << text;
  // The configuration names are in the comments, in order.
  size_t at = 0;
  for (const std::string& name : r.names) {
    at = text.find(name, at);
    EXPECT_NE(at, std::string::npos) << name;
  }
}

// Per-configuration visits (issue 18, the vAP pre-poses): a configuration without approach is
// reached directly, one not measured has no settle wait and no hook; read back, the moves are
// exactly the visits' and the hooks sit only after the measured configurations' moves.
TEST_P(MeasurementProgram, PerConfigurationApproachAndHook) {
  const ProgramLanguage language = GetParam();
  MeasurementProgramRequest r = request_for(language);
  r.max_configs_per_file = 0;
  r.hook = MeasurementHook::PulseOutput;
  r.signal = 7;
  for (const auto& [approach, measure] :
       std::initializer_list<std::pair<bool, bool>>{{true, true},
                                                    {false, false},
                                                    {false, true},
                                                    {true, false},
                                                    {true, true},
                                                    {false, true},
                                                    {true, true}}) {
    ConfigurationVisit& visit = r.visits.emplace_back();
    visit.approach = approach;
    visit.measure = measure;
  }
  const auto files = write_measurement_program(r);
  ASSERT_EQ(files.size(), 1u);
  const std::string& text = files[0].text;
  const std::vector<JointMove> moves = read_joint_moves(text, language, files[0].name, kPulses);
  // The moves expected, and after which move (index) each hook must come.
  std::vector<Vector6d> want;
  std::vector<size_t> hook_after;
  for (size_t i = 0; i < r.joints.size(); ++i) {
    const Vector6d q = r.joints[i] * kRadToDeg;
    if (r.visits[i].approach) want.push_back(q - Vector6d::Constant(5.0));
    want.push_back(q);
    if (r.visits[i].measure) hook_after.push_back(want.size() - 1);
  }
  ASSERT_EQ(moves.size(), want.size());
  for (size_t k = 0; k < want.size(); ++k)
    for (int j = 0; j < kJointCount; ++j) {
      const double ppd = kPulses[static_cast<size_t>(j)];
      const double expected =
          language == ProgramLanguage::Jbi ? std::round(want[k][j] * ppd) / ppd : want[k][j];
      EXPECT_NEAR(moves[k].joints_deg[j], expected, 1e-6) << k << " " << j;
    }
  const std::map<ProgramLanguage, std::string> hook{
      {ProgramLanguage::Rapid, R"(PulseDO \\PLength:=0\.5, doRobcalMeasure;)"},
      {ProgramLanguage::Krl, R"(PULSE\(\$OUT\[7\], TRUE, 0\.5\))"},
      {ProgramLanguage::FanucLs, R"(DO\[7\]=PULSE,0\.5sec ;)"},
      {ProgramLanguage::Jbi, R"(PULSE OT#\(7\) T=0\.50)"},
      {ProgramLanguage::UrScript, R"(set_standard_digital_out\(7, True\))"},
  };
  // Lines of the hooks: each after its measured configuration's move, before the next move.
  const std::regex re(hook.at(language));
  std::vector<int> hook_lines;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator();
       ++it)
    hook_lines.push_back(
        1 + static_cast<int>(std::count(text.begin(), text.begin() + it->position(), '\n')));
  ASSERT_EQ(hook_lines.size(), hook_after.size()) << text;
  for (size_t h = 0; h < hook_lines.size(); ++h) {
    const size_t k = hook_after[h];
    // Fanuc: the move's line is the /MN instruction's, found by the reader in /MN order.
    EXPECT_GT(hook_lines[h], moves[k].line) << h;
    if (k + 1 < moves.size()) {
      EXPECT_LT(hook_lines[h], moves[k + 1].line) << h;
    }
  }
  EXPECT_NE(text.find("c002 (not measured)"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Languages, MeasurementProgram,
                         ::testing::Values(ProgramLanguage::Rapid, ProgramLanguage::Krl,
                                           ProgramLanguage::FanucLs, ProgramLanguage::Jbi,
                                           ProgramLanguage::UrScript),
                         [](const auto& info) { return program_language_name(info.param); });

TEST(MeasurementProgramFormat, RapidModuleWrittenByHand) {
  MeasurementProgramRequest r;
  r.names = {"c1"};
  r.joints = {Vector6d(10, -20.5, 30, 0, 45, -90) * kDegToRad};
  r.hook = MeasurementHook::WaitInput;
  const auto files = write_measurement_program(r);
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0].name, "RCMEAS.mod");
  EXPECT_EQ(files[0].text,
            "MODULE RCMEAS\n"
            "    ! robcal measurement program, part 1 of 1: configurations 1-1 of 1.\n"
            "    ! Each configuration is approached from q - 5 deg on every joint (backlash,\n"
            "    ! robcal method), reached at a fine point, then the arm settles 1 s where it "
            "measures.\n"
            "    PROC RCMEAS_run()\n"
            "        VelSet 10, 5000;\n"
            "        ! c1 joints 10.000000 -20.500000 30.000000 0.000000 45.000000 -90.000000\n"
            "        MoveAbsJ [[5.000000,-25.500000,25.000000,-5.000000,40.000000,-95.000000],"
            "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]]\\NoEOffs, v1000, fine, tool0;\n"
            "        MoveAbsJ [[10.000000,-20.500000,30.000000,0.000000,45.000000,-90.000000],"
            "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]]\\NoEOffs, v1000, fine, tool0;\n"
            "        WaitTime 1.00;\n"
            "        WaitDI diRobcalMeasured, 1;\n"
            "    ENDPROC\n"
            "ENDMODULE\n");
}

TEST(MeasurementProgramFormat, ControllerCountsMatchTheContent) {
  // Fanuc: LINE_COUNT is the number of /MN lines; Yaskawa: ///NPOS the number of C variables
  // (the JBI reader refuses a mismatch, so a wrong count cannot read back).
  MeasurementProgramRequest r = request_for(ProgramLanguage::FanucLs);
  r.max_configs_per_file = 0;
  const std::string ls = write_measurement_program(r)[0].text;
  const size_t mn = ls.find("/MN\n"), pos = ls.find("/POS\n");
  ASSERT_NE(mn, std::string::npos);
  ASSERT_NE(pos, std::string::npos);
  const auto lines =
      std::count(ls.begin() + static_cast<long>(mn) + 4, ls.begin() + static_cast<long>(pos), '\n');
  // 2 frame lines + per configuration: comment, 2 moves, wait, message.
  EXPECT_EQ(lines, 2 + 7 * 5);
  EXPECT_NE(ls.find(fmt::format("LINE_COUNT\t= {};", lines)), std::string::npos);
  EXPECT_TRUE(ls.ends_with("};\n/END\n"));
  for (const char* numbered :
       {"   1:  UFRAME_NUM=0 ;\n", "   4:J P[1] 10% FINE ;\n", "  37:  MESSAGE[robcal c007] ;\n"})
    EXPECT_NE(ls.find(numbered), std::string::npos) << numbered;

  r.language = ProgramLanguage::Jbi;
  r.hook = MeasurementHook::WaitInput;
  std::string jbi = write_measurement_program(r)[0].text;
  EXPECT_NE(jbi.find("///NPOS 14,0,0,0,0,0\n"), std::string::npos);
  EXPECT_NE(jbi.find("\nC00013="), std::string::npos);
  EXPECT_EQ(jbi.find("\nC00014="), std::string::npos);
  jbi.replace(jbi.find("///NPOS 14"), 10, "///NPOS 15");
  EXPECT_REFUSED(read_joint_moves(jbi, ProgramLanguage::Jbi, "x.jbi", kPulses), InputError,
                 "x.jbi:4:9 (///NPOS): ///NPOS declares 15 C positions (count 1 of c,bc,ec,p,bp,"
                 "ex), the job defines 14");
  // Split jobs: each part counts its own positions (3, 3 and 1 configurations, two each).
  r.max_configs_per_file = 3;
  const std::vector<ProgramFile> parts = write_measurement_program(r);
  ASSERT_EQ(parts.size(), 3u);
  for (size_t k = 0; k < parts.size(); ++k)
    EXPECT_NE(parts[k].text.find(fmt::format("///NPOS {},0,0,0,0,0\n", k < 2 ? 6 : 2)),
              std::string::npos)
        << parts[k].name;
}

std::string refusal(const MeasurementProgramRequest& r) {
  try {
    write_measurement_program(r);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MeasurementProgramFormat, RefusesWhatTheControllerCannotTake) {
  MeasurementProgramRequest r = request_for(ProgramLanguage::Rapid);
  r.name = "MEASURE_2";
  EXPECT_EQ(refusal(r),
            "--name: program name 'MEASURE_2': expected a letter, then letters, digits or '_', at "
            "most 6 characters");
  r = request_for(ProgramLanguage::Rapid);
  r.names[2] = "c 3\"";
  EXPECT_NE(refusal(r).find("configuration name 'c 3\"'"), std::string::npos);
  // The IRB 120's axis 2 goes down to -110 deg: 107 deg is fine, its approach at -112 is not.
  r = request_for(ProgramLanguage::Rapid);
  r.limits = load_robot("abb-irb120").limits;
  r.joints = {Vector6d(0, -107, 0, 0, 30, 0) * kDegToRad};
  r.names = {"low"};
  EXPECT_NE(refusal(r).find("low: joint 2 at -112.0000 deg (approach) is outside its limits"),
            std::string::npos)
      << refusal(r);
  r = request_for(ProgramLanguage::Jbi);
  r.pulses_per_degree.reset();
  EXPECT_NE(refusal(r).find("--pulses-per-degree"), std::string::npos);
  r = request_for(ProgramLanguage::Krl);
  r.hook = MeasurementHook::LogLine;
  EXPECT_EQ(refusal(r), "--hook: no log instruction is written for krl; use wait or pulse");
}

TEST(MeasurementProgramFormat, RapidSignalIsARapidIdentifier) {
  MeasurementProgramRequest r = request_for(ProgramLanguage::Rapid);
  r.hook = MeasurementHook::WaitInput;
  r.rapid_signal = "diMeasured_2";
  EXPECT_NE(write_measurement_program(r).front().text.find("WaitDI diMeasured_2, 1;"),
            std::string::npos);
  for (const char* bad : {"a;b", "1di", "di-1", "di measured", "d\u00e9"}) {
    r.rapid_signal = bad;
    EXPECT_EQ(refusal(r), fmt::format("--rapid-signal: signal name '{}': expected a RAPID "
                                      "identifier, a letter then letters, digits or '_', at most "
                                      "32 characters",
                                      bad));
  }
  r.rapid_signal = std::string(33, 'd');
  EXPECT_NE(refusal(r).find("expected a RAPID identifier"), std::string::npos);
  r.hook = MeasurementHook::PulseOutput;
  r.language = ProgramLanguage::Krl;
  r.rapid_signal = "diMeasured";
  EXPECT_EQ(refusal(r),
            "--rapid-signal: a RAPID signal name, but the program is krl: give its input or "
            "output number with --signal");
  r = request_for(ProgramLanguage::Rapid);
  r.rapid_signal = "diMeasured";
  r.hook = MeasurementHook::LogLine;
  EXPECT_NE(refusal(r).find("--rapid-signal: the log hook writes a message, no signal"),
            std::string::npos);
}

TEST(MeasurementProgramFormat, PulsesPerDegreeFromTheRobotFile) {
  // A built-in robot without the key: zeros (unknown); a robot file with it: its six values.
  EXPECT_EQ(robot_pulses_per_degree("abb-irb120"), (std::array<double, kJointCount>{}));
  const std::string path = testing::TempDir() + "/robcal-pulses-robot.yaml";
  write_file_atomically(path, read_text_file(data_directory() / "robots" / "yaskawa-gp7.yaml") +
                                  "pulses_per_degree: [1341.2, 1341.2, 1341.2, 1092.3, 1092.3, "
                                  "614.4]\n");
  EXPECT_EQ(robot_pulses_per_degree(path),
            (std::array<double, kJointCount>{1341.2, 1341.2, 1341.2, 1092.3, 1092.3, 614.4}));
  EXPECT_EQ(load_robot(path).name, "Yaskawa Motoman GP7");  // the kinematic model is unchanged
}

// `robcal program` as a library call: the CSV read, the robot's limits checked, the files
// written; a bad CSV is located and writes nothing.
TEST(MeasurementProgramFormat, FromTheConfigurationsFile) {
  const std::string dir = testing::TempDir() + "/robcal-program-files";
  std::filesystem::remove_all(dir);
  MeasurementProgramFilesRequest request;
  request.program.language = ProgramLanguage::Krl;
  request.configs = dir + "/configs.csv";
  request.robot = "abb-irb120";
  request.out_dir = dir + "/out";
  write_file_atomically(request.configs,
                        "config,target,j1,j2,j3,j4,j5,j6\nc1,,10,20,-10,30,40,50\n"
                        "c2,,-30,35,5,-60,-50,20\n");
  const MeasurementProgramFilesResult r = write_measurement_program_from_files(request);
  ASSERT_EQ(r.paths, std::vector<std::string>{dir + "/out/rcmeas.src"});
  ASSERT_TRUE(r.program.limits.has_value());  // the IRB 120's
  const auto moves = read_joint_moves(read_text_file(r.paths[0]), ProgramLanguage::Krl, "x.src");
  ASSERT_EQ(moves.size(), 4u);
  EXPECT_LT((moves[1].joints_deg - Vector6d(10, 20, -10, 30, 40, 50)).norm(), 1e-9);
  EXPECT_LT((moves[2].joints_deg - Vector6d(-35, 30, 0, -65, -55, 15)).norm(), 1e-9);
  // Joint 2 of c2 beyond the IRB 120's limit (±110°): refused by name, nothing written.
  request.out_dir = dir + "/bad";
  write_file_atomically(request.configs,
                        "config,target,j1,j2,j3,j4,j5,j6\nc1,,10,20,-10,30,40,50\n"
                        "c2,,-30,135,5,-60,-50,20\n");
  EXPECT_REFUSED((void)write_measurement_program_from_files(request), InputError, "c2");
  write_file_atomically(request.configs,
                        "config,target,j1,j2,j3,j4,j5,j6\nc1,,10,x,-10,30,40,50\n");
  EXPECT_REFUSED((void)write_measurement_program_from_files(request), InputError, "configs.csv:2:");
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad"));
}

TEST(MeasurementProgramFormat, ReadersLocateBadText) {
  const auto error = [](const std::string& text, ProgramLanguage language, const char* file) {
    try {
      read_joint_moves(text, language, file, kPulses);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error("def p():\n  movej([0, 1.5.2, 0, 0, 0, 0], a=1, v=1)\nend\n",
                  ProgramLanguage::UrScript, "p.script"),
            "p.script:2:13: malformed number '1.5.2'");
  EXPECT_EQ(error("def p():\n  movej([0, 1, 0, 0, 0], a=1)\nend\n", ProgramLanguage::UrScript,
                  "p.script"),
            "p.script:2:23: movej: expected ',' after joint 5");
  EXPECT_EQ(error("/PROG X\n/MN\n 1:J P[1] 10% FINE ;\n/POS\nP[1]{\n GP1:\n UF : 0, UT : 1,\n"
                  " J1= 1e999 deg, J2= 0 deg\n};\n/END\n",
                  ProgramLanguage::FanucLs, "x.ls"),
            "x.ls:8:6: number '1e999' is out of range");
  EXPECT_EQ(error("/PROG X\n/MN\n 1:J P[1] 10% FINE ;\n/POS\nP[1]{\n GP1:\n UF : 0, UT : 1,\n"
                  " J1= 1 deg, J2= 0 deg\n};\n/END\n",
                  ProgramLanguage::FanucLs, "x.ls"),
            "x.ls:5:1 (P[1]): has 2 of the components J1..J6");
  EXPECT_EQ(error("/JOB\n//POS\n///NPOS 1,0,0,0,0,0\n///PULSE\nC00000=1,2,3\n//INST\n",
                  ProgramLanguage::Jbi, "x.jbi"),
            "x.jbi:5:8: C00000: expected six robot axis values, found 3");
}

}  // namespace
}  // namespace robcal
