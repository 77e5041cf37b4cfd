// Program filtering (issue 17): targets are corrected with the tool of the motion that uses
// them or not at all. A program in another language than its name says is refused; URScript
// poses take the tool of the motion naming their variable; RAPID targets given to instructions
// whose tool argument robcal does not know (ArcL, a user routine) are left uncorrected; KRL
// spline segments (SPL) and URScript joint lists (movej([...])) are corrected.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "robcal/compensate/corrected_targets.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/programs/program_filter.hpp"
#include "test_compensate_support.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

/// The message of the InputError `f` throws, "" when it throws none.
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// Moves every Cartesian point 1 mm along x and every joint by 0.5°; records the tools seen.
struct RecordingCorrector {
  std::vector<std::optional<Pose<double>>> tools;
  CorrectedPoint operator()(const ProgramPoint& p) {
    tools.push_back(p.flange_T_tcp);
    CorrectedPoint c;
    c.base_T_tcp = p.base_T_tcp;
    c.base_T_tcp.p.x() += 1;
    c.joints_deg = p.joints_deg + Vector6d::Constant(0.5);
    c.config = p.config;
    return c;
  }
};

TEST(ProgramUses, ProgramInAnotherLanguageIsRefusedNamingIt) {
  const std::vector<std::pair<std::string, ProgramLanguage>> samples = {
      {"pick_place.mod", ProgramLanguage::Rapid}, {"weld_seam.src", ProgramLanguage::Krl},
      {"weld_seam.dat", ProgramLanguage::Krl},    {"weld_cell.ls", ProgramLanguage::FanucLs},
      {"weld_cell.jbi", ProgramLanguage::Jbi},    {"pick.script", ProgramLanguage::UrScript}};
  const std::map<ProgramLanguage, std::string> looks = {
      {ProgramLanguage::Rapid, "begins an ABB RAPID module"},
      {ProgramLanguage::Krl, "begins a KUKA KRL program"},
      {ProgramLanguage::FanucLs, "begins a Fanuc LS program"},
      {ProgramLanguage::Jbi, "begins a Yaskawa JBI job"},
      {ProgramLanguage::UrScript, "begins a URScript program"}};
  for (const auto& [file, language] : samples) {
    const std::string text = read_text_file(test::data_path("programs/" + file));
    const auto marker = recognise_program_language(text);
    ASSERT_TRUE(marker.has_value()) << file;
    EXPECT_EQ(marker->language, language) << file;
    for (const auto& [other, description] : looks) {
      const std::string error = error_of(
          [&] { filter_program(text, other, "x", ProgramFilterOptions{}, RecordingCorrector{}); });
      if (other == language) {  // (its tools and frames are not given here: other errors)
        EXPECT_EQ(error.find("here begins"), std::string::npos) << file << ": " << error;
      } else {
        EXPECT_NE(error.find(fmt::format("x:{}:1: '{}' here {}", marker->line, marker->marker,
                                         looks.at(language))),
                  std::string::npos)
            << file << " as " << program_language_name(other) << ": " << error;
      }
    }
  }
  // The CLI's path: no output file.
  const auto dir = std::filesystem::temp_directory_path() / "robcal_program_uses";
  std::filesystem::create_directories(dir);
  const std::string in = (dir / "module.src").string(), out = (dir / "out.src").string();
  std::filesystem::remove(out);
  write_file_atomically(in, "! comment\nMODULE m\n  PROC main()\n  ENDPROC\nENDMODULE\n");
  EXPECT_EQ(error_of([&] { filter_program_file(in, out, {}, RecordingCorrector{}); }),
            in + ":2:1: 'MODULE' here begins an ABB RAPID module, not a KUKA KRL program (the "
                 "language of the file's name or --lang): nothing corrected; give the file its "
                 "own extension (.mod)");
  EXPECT_FALSE(std::filesystem::exists(out));
  // KRL and URScript both start with def: the colon tells them apart.
  EXPECT_EQ(recognise_program_language("def main():\n  movel(p[0,0,0,0,0,0])\nend\n")->language,
            ProgramLanguage::UrScript);
  EXPECT_EQ(recognise_program_language("&ACCESS RVP\nDEF main( )\nEND\n")->language,
            ProgramLanguage::Krl);
  EXPECT_EQ(recognise_program_language("DEF main( )\nEND\n")->language, ProgramLanguage::Krl);
  EXPECT_EQ(recognise_program_language("/JOB\r\n//NAME A\r\n")->language, ProgramLanguage::Jbi);
  EXPECT_FALSE(recognise_program_language("  movel(p[0,0,0,0,0,0])\n").has_value());
}

constexpr const char* kPose = "p[0.4, -0.1, 0.3, 0.0, 3.14159, 0.0]";
constexpr const char* kTcp = "set_tcp(p[0.0, 0.0, 0.2, 0.0, 0.0, 0.0])";

TEST(ProgramUses, UrScriptVariableTakesTheToolOfTheMotionUsingIt) {
  // wp assigned with no set_tcp before it, moved to after the set_tcp: the 200 mm tool.
  const std::string text = fmt::format(
      "def t():\n  wp = {0}\n  {1}\n  movel(wp, a=1.2, v=0.25)\n  wq = {0}\n  movej(wq)\nend\n",
      kPose, kTcp);
  RecordingCorrector record;
  const ProgramFilterResult result =
      filter_program(text, ProgramLanguage::UrScript, "t.script", {},
                     [&](const ProgramPoint& p) { return record(p); });
  ASSERT_EQ(record.tools.size(), 2u);
  for (const auto& tool : record.tools) {
    ASSERT_TRUE(tool.has_value());
    EXPECT_EQ(tool->p, Eigen::Vector3d(0, 0, 200));
  }
  EXPECT_TRUE(result.assumed.empty());
  // Only the two pose literals changed (x + 1 mm = 0.401 m).
  EXPECT_EQ(result.text,
            fmt::format("def t():\n  wp = p[0.4010000, -0.1, 0.3, 0.0, 3.14159, 0.0]\n  {0}\n  "
                        "movel(wp, a=1.2, v=0.25)\n  wq = p[0.4010000, -0.1, 0.3, 0.0, 3.14159, "
                        "0.0]\n  movej(wq)\nend\n",
                        kTcp));

  // Reassigned: each assignment takes the tool of the motion after it.
  const std::string twice = fmt::format(
      "def t():\n  wp = {0}\n  movel(wp)\n  {1}\n  wp = {0}\n  movel(wp)\nend\n", kPose, kTcp);
  const auto points = read_program_points(twice, ProgramLanguage::UrScript, "t.script");
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].tool, "");
  EXPECT_EQ(points[1].tool, "SET_TCP@4");

  // One assignment used under two tools: refused, both uses located.
  const std::string two_tools =
      fmt::format("def t():\n  wp = {0}\n  movel(wp)\n  {1}\n  movel(wp)\nend\n", kPose, kTcp);
  EXPECT_EQ(error_of([&] {
              filter_program(two_tools, ProgramLanguage::UrScript, "t.script", {},
                             RecordingCorrector{});
            }),
            "t.script:2:8 (wp): used under the default tool (no set_tcp before it) at "
            "t.script:3:9 and under SET_TCP@4 at t.script:5:9: one corrected value cannot serve "
            "both; give each use its own pose");

  // Named by no motion (only in pose_trans): the tool where it is assigned, listed as assumed.
  const std::string unused = fmt::format(
      "def t():\n  {1}\n  wp = {0}\n  movel(pose_trans(wp, p[0, 0, 0.05, 0, 0, 0]))\nend\n", kPose,
      kTcp);
  const ProgramFilterResult u =
      filter_program(unused, ProgramLanguage::UrScript, "t.script", {}, RecordingCorrector{});
  ASSERT_EQ(u.assumed.size(), 1u);
  EXPECT_EQ(u.assumed[0].where, "t.script:3:8 (wp)");
  EXPECT_EQ(u.assumed[0].reason,
            "no movel/movej/movep/movec names 'wp' after this assignment: corrected for the tool "
            "active here (SET_TCP@2)");
}

TEST(ProgramUses, UrScriptJointListsCorrectedWithJoints) {
  const std::string text =
      "def t():\n  movej([0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0], a=1.4, v=1.05)\nend\n";
  // Without `joints` the joint list is not a target.
  EXPECT_EQ(filter_program(text, ProgramLanguage::UrScript, "t.script", {}, RecordingCorrector{})
                .joint_points,
            0);
  ProgramFilterOptions options;
  options.joints = true;
  const ProgramFilterResult r =
      filter_program(text, ProgramLanguage::UrScript, "t.script", options, RecordingCorrector{});
  EXPECT_EQ(r.joint_points, 1);
  // + 0.5° = + 0.00872665 rad, printed with 8 decimals of a radian.
  EXPECT_EQ(r.text,
            "def t():\n  movej([0.00872665, -1.56207335, 1.57952665, -1.56207335, -1.56207335, "
            "0.00872665], a=1.4, v=1.05)\nend\n");
}

TEST(ProgramUses, RapidTargetsOfUnknownInstructionsAreNotCorrected) {
  const std::string text =
      "MODULE m\n"
      "  CONST robtarget p10 := [[400,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n"
      "  CONST robtarget p20 := [[410,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n"
      "  PROC main()\n"
      "    MoveL p10, v100, fine, tool0;\n"
      "    ArcL p20, v100, seam1, weld1, fine, tool0;\n"
      "    SpotL [[420,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], vmax, gun1, "
      "tool0;\n"
      "    IF reg1 > 0 THEN\n"
      "      MoveJ p10, v100, z10, tool0;\n"
      "    ENDIF\n"
      "  ENDPROC\n"
      "ENDMODULE\n";
  EXPECT_EQ(error_of([&] {
              filter_program(text, ProgramLanguage::Rapid, "m.mod", {}, RecordingCorrector{});
            }),
            "m.mod:3:26 (p20): ArcL (line 6) uses this target; robcal knows the tool argument of "
            "MoveL/MoveJ/MoveC/MoveAbsJ and their DO/Sync/Trigg/Search variants only, so the "
            "target is not corrected (--keep-going leaves it as written)");
  ProgramFilterOptions options;
  options.keep_going = true;
  const ProgramFilterResult r =
      filter_program(text, ProgramLanguage::Rapid, "m.mod", options, RecordingCorrector{});
  EXPECT_EQ(r.cartesian_points, 1);
  ASSERT_EQ(r.uncorrected.size(), 2u);
  EXPECT_EQ(r.uncorrected[0].where, "m.mod:3:26 (p20)");
  EXPECT_EQ(r.uncorrected[1].where, "m.mod:7:11");
  EXPECT_NE(r.uncorrected[1].reason.find("SpotL (line 7)"), std::string::npos);
  // Only p10's x changed.
  std::string want = text;
  want.replace(want.find("[[400,0,500]"), 12, "[[401.0000,0,500]");
  EXPECT_EQ(r.text, want);
}

TEST(ProgramUses, KrlSplineSegmentsAreCorrectedWithTheirTool) {
  const std::string text =
      "DEF s( )\n"
      "  BAS(#TOOL,1)\n"
      "  SPLINE WITH $VEL.CP = 0.2\n"
      "    SPL {X 900,Y 0,Z 900,A 180,B 0,C 180}\n"
      "    SLIN {X 910,Y 0,Z 900,A 180,B 0,C 180} WITH $VEL.CP = 0.1\n"
      "    SCIRC {X 920,Y 10,Z 900,A 180,B 0,C 180}, {X 930,Y 0,Z 900,A 180,B 0,C 180}\n"
      "  ENDSPLINE\n"
      "  PTP_SPLINE\n"
      "    SPTP {X 900,Y 0,Z 950,A 180,B 0,C 180}\n"
      "  ENDSPLINE\n"
      "END\n";
  ProgramFilterOptions options;
  Pose<double> tool;
  tool.p = Eigen::Vector3d(0, 0, 150);
  options.tools["TOOL_DATA[1]"] = tool;
  RecordingCorrector record;
  const ProgramFilterResult r = filter_program(text, ProgramLanguage::Krl, "s.src", options,
                                               [&](const ProgramPoint& p) { return record(p); });
  EXPECT_EQ(r.cartesian_points, 5);
  EXPECT_TRUE(r.assumed.empty());
  ASSERT_EQ(record.tools.size(), 5u);
  for (const auto& t : record.tools) {
    ASSERT_TRUE(t.has_value());
    EXPECT_EQ(t->p, tool.p);
  }
  for (const char* x : {"X 901.0000,", "X 911.0000,", "X 921.0000,", "X 931.0000,"})
    EXPECT_NE(r.text.find(x), std::string::npos) << x;
}

/// Joint targets in a closed loop: the controller drives the corrected joints; the true arm
/// (the calibrated model) puts the TCP where the nominal arm at the written joints did.
TEST(ProgramUses, JointTargetsClosedLoop) {
  for (const auto& [language, robot_name] :
       {std::pair{ProgramLanguage::UrScript, "universal-robots-ur10e"},
        std::pair{ProgramLanguage::Rapid, "abb-irb120"}}) {
    std::mt19937_64 rng(11);
    const CalibratedRobot robot = test::random_calibrated(robot_name, rng);
    const Compensator comp = make_compensator(robot);
    std::string body;
    std::vector<Vector6d> written;
    while (written.size() < 8) {
      const Vector6d q = test::random_joints(comp.model, rng);
      if (test::near_singular(comp.model, q, 10)) continue;
      bool near_limit = false;  // the calibrated answer may cross it
      for (int j = 0; j < kJointCount; ++j)
        near_limit |= q[j] < comp.model.limits[j].lower + deg2rad(5) ||
                      q[j] > comp.model.limits[j].upper - deg2rad(5);
      if (near_limit) continue;
      written.push_back(q);
      if (language == ProgramLanguage::UrScript) {
        body += fmt::format("  movej([{:.10f}, {:.10f}, {:.10f}, {:.10f}, {:.10f}, {:.10f}])\n",
                            q[0], q[1], q[2], q[3], q[4], q[5]);
      } else {
        const Vector6d d = q * kRadToDeg;
        body += fmt::format(
            "    MoveAbsJ [[{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}],[9E9,9E9,9E9,9E9,9E9,9E9]],"
            " v100, fine, tool0;\n",
            d[0], d[1], d[2], d[3], d[4], d[5]);
      }
    }
    const bool ur = language == ProgramLanguage::UrScript;
    const std::string text = ur ? "def loop():\n" + body + "end\n"
                                : "MODULE Loop\n  PROC main()\n" + body + "  ENDPROC\nENDMODULE\n";
    const std::string file = std::string("loop") + program_extension(language);
    ProgramFilterOptions options;
    options.joints = true;
    const auto result = filter_program(text, language, file, options,
                                       make_program_corrector(comp, language, &robot));
    ASSERT_EQ(result.joint_points, 8);
    const auto before = read_program_points(text, language, file, options);
    const auto after = read_program_points(result.text, language, file, options);
    ASSERT_EQ(after.size(), 8u);
    double worst = 0, uncompensated = 0;
    for (size_t i = 0; i < after.size(); ++i) {
      // Flange poses (nominal_tcp_pose is the TCP's, calibrated_tcp_pose · tcp_T_flange the
      // flange's).
      const Pose<double> wanted =
          nominal_tcp_pose(comp, before[i].joints_deg * kDegToRad) * comp.tcp_T_flange;
      const auto reached = [&](const ProgramPoint& p) {
        ChainState state;
        return Pose<double>(comp.base_T_world *
                            calibrated_tcp_pose(comp.chain, p.joints_deg * kDegToRad, state) *
                            comp.tcp_T_flange);
      };
      worst = std::max(worst, (reached(after[i]).p - wanted.p).norm());
      uncompensated = std::max(uncompensated, (reached(before[i]).p - wanted.p).norm());
    }
    // Printing: 8 decimals of a radian (UR) or 5 of a degree (RAPID): ≤ 1e-4 mm at 1.5 m.
    EXPECT_LT(worst, 2e-4) << robot_name << " uncompensated " << uncompensated;
    EXPECT_GT(uncompensated, 0.1) << robot_name;
  }
}

}  // namespace
}  // namespace robcal
