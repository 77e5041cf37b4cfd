// Program filtering with the tool and work object active at each instruction (issue 17
// item 3): RAPID tooldata and \WObj read from the program or given by the user, a target used
// with two tools refused, uncorrectable targets left as written under keep_going, and the
// closed loop: the filtered program, executed by a nominal controller on the calibrated
// (true) robot with its tool and work object, puts the tool where the original program meant.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <numbers>

#include "robcal/compensate/corrected_targets.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/programs/program_filter.hpp"
#include "test_compensate_support.hpp"

namespace robcal {
namespace {

// tGun: TCP (10, 20, 150) turned 30° about y; wTable: uframe (1000, -200, 300) turned 90°
// about z, oframe (10, 0, 5).
const char* const kTool =
    "[TRUE,[[10,20,150],[0.965925826,0,0.258819045,0]],"
    "[1,[0,0,50],[1,0,0,0],0,0,0]]";
const char* const kWobj =
    "[FALSE,TRUE,\"\",[[1000,-200,300],[0.707106781,0,0,0.707106781]],"
    "[[10,0,5],[1,0,0,0]]]";

Pose<double> tool_pose() {
  Pose<double> t;
  t.p = Eigen::Vector3d(10, 20, 150);
  t.R = Eigen::AngleAxisd(deg2rad(30), Eigen::Vector3d::UnitY()).toRotationMatrix();
  return t;
}
Pose<double> frame_pose() {
  Pose<double> f;
  f.R = Eigen::AngleAxisd(deg2rad(90), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  f.p = Eigen::Vector3d(1000, -200, 300) + f.R * Eigen::Vector3d(10, 0, 5);
  return f;
}

std::string robtarget(const Pose<double>& pose, const std::vector<int>& cf) {
  const Eigen::Quaterniond q(pose.R);
  return fmt::format(
      "[[{:.6f},{:.6f},{:.6f}],[{:.9f},{:.9f},{:.9f},{:.9f}],[{},{},{},{}],"
      "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]]",
      pose.p.x(), pose.p.y(), pose.p.z(), q.w(), q.x(), q.y(), q.z(), cf[0], cf[1], cf[2], cf[3]);
}

TEST(ProgramFrames, CorrectorSeesTheActiveToolAndWorkObjectInTheBaseFrame) {
  const std::string text = fmt::format(
      "MODULE Cell\n"
      "  PERS tooldata tGun:={};\n"
      "  TASK PERS wobjdata wTable:={};\n"
      "  CONST robtarget pA:=[[100,50,20],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n"
      "  CONST robtarget pB:=[[400,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n"
      "  PROC main()\n"
      "    MoveJ pB, v100, z10, tool0;\n"
      "    MoveL \\Conc, Offs(pA,0,0,10), v100\\V:=50, fine, tGun\\WObj:=wTable;\n"
      "    MoveL pA, v100, fine, tGun \\WObj:=wTable;\n"
      "    MoveL [[5,6,7],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v10, fine, "
      "tGun\\WObj:=wTable;\n"
      "  ENDPROC\n"
      "ENDMODULE\n",
      kTool, kWobj);
  std::vector<ProgramPoint> seen;
  const Eigen::Vector3d shift(1, 2, 3);
  const auto result =
      filter_program(text, ProgramLanguage::Rapid, "cell.mod", {}, [&](const ProgramPoint& p) {
        seen.push_back(p);
        CorrectedPoint c{p.base_T_tcp, p.config, p.joints_deg, ""};
        c.base_T_tcp.p += shift;  // in the base frame
        return c;
      });
  ASSERT_EQ(seen.size(), 3u);
  const Pose<double> F = frame_pose(), T = tool_pose();
  // pA: in wTable with tGun; pB: base frame, tool0 (the flange); the inline point: wTable.
  EXPECT_EQ(seen[0].name, "pA");
  EXPECT_EQ(seen[0].tool, "TGUN");
  EXPECT_EQ(seen[0].frame, "WTABLE");
  EXPECT_LT((seen[0].base_T_tcp.p - F * Eigen::Vector3d(100, 50, 20)).norm(), 1e-6);
  ASSERT_TRUE(seen[0].flange_T_tcp.has_value());
  EXPECT_LT((seen[0].flange_T_tcp->p - T.p).norm(), 1e-9);
  EXPECT_LT((seen[0].flange_T_tcp->R - T.R).norm(), 1e-8);
  EXPECT_EQ(seen[1].tool, "TOOL0");
  EXPECT_LT((seen[1].base_T_tcp.p - Eigen::Vector3d(400, 0, 500)).norm(), 1e-12);
  ASSERT_TRUE(seen[1].flange_T_tcp.has_value());
  EXPECT_LT((seen[1].flange_T_tcp->p).norm(), 1e-12);
  EXPECT_LT((seen[2].base_T_tcp.p - F * Eigen::Vector3d(5, 6, 7)).norm(), 1e-6);
  // A base-frame shift (1, 2, 3) is (2, -1, 3) in wTable (turned 90° about z).
  const auto points = read_program_points(result.text, ProgramLanguage::Rapid, "cell.mod");
  EXPECT_LT((points[0].base_T_tcp.p - Eigen::Vector3d(102, 49, 23)).norm(), 1e-4);
  EXPECT_LT((points[1].base_T_tcp.p - Eigen::Vector3d(401, 2, 503)).norm(), 1e-4);
  EXPECT_LT((points[2].base_T_tcp.p - Eigen::Vector3d(7, 5, 10)).norm(), 1e-4);
}

std::string error_of(const std::string& text, const ProgramFilterOptions& options = {}) {
  try {
    filter_program(text, ProgramLanguage::Rapid, "cell.mod", options, [](const ProgramPoint& p) {
      return CorrectedPoint{p.base_T_tcp, p.config, p.joints_deg, ""};
    });
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ProgramFrames, ToolsAndFramesMustBeKnownAndUnambiguous) {
  const std::string decl =
      "  CONST robtarget pA:=[[100,50,20],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n";
  EXPECT_EQ(error_of(decl + "  MoveL pA, v100, fine, tGun;\n  MoveL pA, v100, fine, tool0;\n"),
            "cell.mod:1:23 (pA): used with tool TGUN and work object WOBJ0 (line 2) and with tool "
            "TOOL0 and work object WOBJ0 (line 3): one corrected value cannot serve both; give "
            "each use its own target");
  EXPECT_EQ(error_of(decl + "  MoveL pA, v100, fine, tGun;\n"),
            "cell.mod:1:23 (pA): unknown tool 'TGUN': the program does not define it with literal "
            "values; give it in a frames file");
  ProgramFilterOptions given;
  given.tools["tgun"] = tool_pose();
  EXPECT_EQ(error_of(decl + "  MoveL pA, v100, fine, tGun;\n", given), "");
  // Defined in the program and given with another value.
  given.tools["tgun"].p.x() += 1;
  EXPECT_NE(error_of(fmt::format("  PERS tooldata tGun:={};\n", kTool) + decl +
                         "  MoveL pA, v100, fine, tGun;\n",
                     given)
                .find("tool 'tgun' is defined in the program and in the frames file with other "
                      "values"),
            std::string::npos);
  EXPECT_EQ(error_of("  PERS tooldata tFix:=[FALSE,[[0,0,100],[1,0,0,0]],[1,[0,0,1],[1,0,0,0],0,"
                     "0,0]];\n"),
            "cell.mod:1:17: tool 'tFix' is stationary (robhold FALSE): targets of a stationary "
            "tool are not corrected");
}

TEST(ProgramFrames, KrlToolAndBaseFromBasCallsAssignmentsAndFdat) {
  const std::string dat =
      "DEFDAT CELL\n"
      "DECL E6POS XP1={X 100,Y 50,Z 20,A 0,B 0,C 0,S 2,T 2}\n"
      "DECL FDAT FP1={TOOL_NO 2,BASE_NO 1,IPO_FRAME #BASE}\n"
      "ENDDAT\n";
  const std::string src =
      "DEF CELL( )\n"
      "  BAS(#TOOL,2)\n"
      "  BAS (#BASE, 1)\n"
      "  LIN {X 5,Y 6,Z 7,A 0,B 0,C 0}\n"
      "  $TOOL=TOOL_DATA[0]\n"
      "  $BASE=BASE_DATA[0]\n"
      "  LIN {X 400,Y 0,Z 500,A 0,B 0,C 0}\n"
      "  $BASE=MY_FRAME\n"
      "  LIN {X 1,Y 2,Z 3,A 0,B 0,C 0}\n"
      "END\n";
  ProgramFilterOptions options;
  options.tools["TOOL_DATA[2]"] = tool_pose();
  options.frames["BASE_DATA[1]"] = frame_pose();
  std::vector<ProgramPoint> seen;
  const auto record = [&](const ProgramPoint& p) {
    seen.push_back(p);
    return CorrectedPoint{p.base_T_tcp, p.config, p.joints_deg, ""};
  };
  filter_program(dat, ProgramLanguage::Krl, "cell.dat", options, record);
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].tool, "TOOL_DATA[2]");
  EXPECT_EQ(seen[0].frame, "BASE_DATA[1]");
  EXPECT_LT((seen[0].base_T_tcp.p - frame_pose() * Eigen::Vector3d(100, 50, 20)).norm(), 1e-9);
  seen.clear();
  try {
    filter_program(src, ProgramLanguage::Krl, "cell.src", options, record);
    ADD_FAILURE() << "an expression base was accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "cell.src:9:7: unknown base 'MY_FRAME': the program does not define it with "
                 "literal values; give it in a frames file");
  }
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].tool, "TOOL_DATA[2]");
  EXPECT_LT((seen[0].base_T_tcp.p - frame_pose() * Eigen::Vector3d(5, 6, 7)).norm(), 1e-9);
  EXPECT_EQ(seen[1].tool, "TOOL_DATA[0]");
  EXPECT_LT(seen[1].flange_T_tcp->p.norm(), 1e-12);
  EXPECT_LT((seen[1].base_T_tcp.p - Eigen::Vector3d(400, 0, 500)).norm(), 1e-12);
}

TEST(ProgramFrames, KeepGoingLeavesRefusedTargetsAsWrittenAndListsThem) {
  const std::string text =
      "  CONST robtarget pA:=[[100,50,20],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n"
      "  CONST robtarget pFar:=[[9000,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n";
  ProgramFilterOptions options;
  options.keep_going = true;
  const auto result =
      filter_program(text, ProgramLanguage::Rapid, "k.mod", options, [](const ProgramPoint& p) {
        CorrectedPoint c{p.base_T_tcp, p.config, p.joints_deg, ""};
        if (p.base_T_tcp.p.x() > 5000) c.failure = "out of reach";
        c.base_T_tcp.p.z() += 1;
        c.confidence95_mm = 0.0123;
        return c;
      });
  EXPECT_EQ(result.cartesian_points, 1);
  ASSERT_EQ(result.uncorrected.size(), 1u);
  EXPECT_EQ(result.uncorrected[0].where, "k.mod:2:25 (pFar)");
  EXPECT_EQ(result.uncorrected[0].reason, "out of reach");
  EXPECT_EQ(result.text.substr(result.text.find('\n') + 1), text.substr(text.find('\n') + 1));
  EXPECT_NE(result.text.find("[[100,50,21.0000]"), std::string::npos);
  EXPECT_EQ(result.confidence_csv, "line,column,name,confidence95_mm\n1,23,pA,0.0123\n");
  // No instruction uses pA: its tool and work object are an assumption, and said so.
  ASSERT_EQ(result.assumed.size(), 1u);
  EXPECT_EQ(result.assumed[0].where, "k.mod:1:23 (pA)");
}

/// The error filtering a KUKA module gives ("" when it is accepted).
std::string module_error(const std::string& src, const std::string& dat, bool keep_going = false) {
  ProgramFilterOptions options;
  options.keep_going = keep_going;
  options.tools["TOOL_DATA[1]"] = options.tools["TOOL_DATA[2]"] = Pose<double>{};
  try {
    filter_krl_module(src, dat, "m.src", "m.dat", options, [](const ProgramPoint& p) {
      return CorrectedPoint{p.base_T_tcp, p.config, p.joints_deg, "", std::nullopt};
    });
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ProgramFrames, KrlModuleRefusesWhatItCannotCorrectWithBothLocations) {
  const std::string dat =
      "DEFDAT M\n"
      "DECL E6POS XP1={X 100,Y 50,Z 20,A 0,B 0,C 0,S 2,T 2}\n"
      "DECL FRAME TGRIP={X 0,Y 0,Z 120,A 0,B 0,C 0}\n"
      "ENDDAT\n";
  // One point under two tools: refused at the point, naming both motions.
  EXPECT_EQ(
      module_error("DEF M( )\n  BAS(#TOOL,1)\n  LIN XP1\n  BAS(#TOOL,2)\n  LIN XP1\nEND\n", dat),
      "m.dat:2:16 (XP1): used with tool TOOL_DATA[1] and base ? at m.src:3:7 and with tool "
      "TOOL_DATA[2] and base ? at m.src:5:7: one corrected value cannot serve both; give "
      "each use its own point");
  // The same tool twice, once as a FRAME of the .dat: accepted.
  EXPECT_EQ(module_error("DEF M( )\n  $TOOL=TGRIP\n  LIN XP1\n  LIN XP1 C_DIS\nEND\n", dat), "");
  // A point used but declared in neither file.
  EXPECT_EQ(module_error("DEF M( )\n  BAS(#TOOL,1)\n  LIN XP9\nEND\n", dat),
            "m.src:3:7: 'XP9' is used here but declared neither in this .src nor in its .dat: a "
            "point defined elsewhere is not corrected");
  EXPECT_EQ(module_error("DEF M( )\n  BAS(#TOOL,1)\n  LIN XP9\nEND\n", dat, true), "");
  // The home position of $config.dat is not the module's: skipped.
  EXPECT_EQ(module_error("DEF M( )\n  PTP XHOME\nEND\n", dat), "");
  // A malformed FRAME in the .dat, located there.
  EXPECT_EQ(module_error("DEF M( )\nEND\n",
                         "DEFDAT M\nDECL FRAME TGRIP={X 0,Y 0,Z abc,A 0,B 0,C 0}\nENDDAT\n"),
            "m.dat:2:29: FRAME 'TGRIP': Z is not a number literal");
  EXPECT_EQ(module_error("DEF M( )\nEND\n",
                         "DEFDAT M\nDECL FRAME TGRIP={X 0,Y 0,Z 120,A 0,B 0}\nENDDAT\n"),
            "m.dat:2:18: FRAME 'TGRIP' has no C: expected {X, Y, Z, A, B, C} (mm, deg)");
  // A tool or base made active by a name nobody defines, or whose value is known only at run
  // time: refused at the point, saying which and why.
  EXPECT_EQ(
      module_error("DEF M( )\n  $TOOL=TGRIP\n  $BASE = XTABLE   ; nowhere\n  LIN XP1\nEND\n", dat),
      "m.dat:2:16 (XP1): unknown base 'XTABLE': the program does not define it with "
      "literal values; give it in a frames file");
  EXPECT_EQ(module_error("DEF M( )\n  $TOOL=TGRIP\n  $TOOL.Z=$TOOL.Z+5\n  LIN XP1\nEND\n", dat),
            "m.dat:2:16 (XP1): unknown tool '$TOOL (changed at line 3)': $TOOL.Z is assigned at "
            "m.src:3: its value is known only at run time");
  EXPECT_EQ(module_error("DEF M( )\n  TGRIP.X = 2.5\n  $TOOL=TGRIP\n  LIN XP1\nEND\n", dat),
            "m.dat:2:16 (XP1): unknown tool 'TGRIP': its component X is assigned at m.src:2: its "
            "value is known only at run time");
  EXPECT_EQ(
      module_error("DEF M( )\n  TOOL_DATA[1]={X 0,Y 0,Z 99,A 0,B 0,C 0}\n  "
                   "TOOL_DATA[1]={X 0,Y 0,Z 98,A 0,B 0,C 0}\n  BAS(#TOOL,1)\n  LIN XP1\nEND\n",
                   dat),
      "m.dat:2:16 (XP1): unknown tool 'TOOL_DATA[1]': it is given one value at m.src:2 and "
      "another at m.src:3: which one is active at a point depends on the run");
  EXPECT_EQ(module_error("DEF M( )\n  $TOOL = TOOL_DATA[I]\n  LIN XP1\nEND\n", dat),
            "m.dat:2:16 (XP1): unknown tool '$TOOL (set at line 2)': $TOOL is assigned an "
            "expression at m.src:2 (a FRAME name, TOOL_DATA[n], BASE_DATA[n] or a literal frame "
            "is read; anything else is known only at run time)");
  // Reading a component (a comparison, the right side of another assignment) changes nothing.
  EXPECT_EQ(module_error("DEF M( )\n  $TOOL=TGRIP\n  IF $TOOL.Z == 120 THEN\n    LIN XP1\n  "
                         "ENDIF\n  XP1.Z = TGRIP.Z\nEND\n",
                         dat),
            "");
  // An inline form whose FDAT the module does not declare: its tool is unknown.
  EXPECT_EQ(module_error("DEF M( )\n  FDAT_ACT=FP7\n  BAS(#CP_PARAMS,0.2)\n  LIN XP1\nEND\n", dat),
            "m.dat:2:16 (XP1): unknown base 'FDAT_ACT=FP7 (line 2, no DECL FDAT FP7 in the "
            "module)': the inline form's FDAT_ACT=FP7 at m.src:2 names no DECL FDAT of the "
            "module, so its tool and base numbers are unknown");
}

/// One target written in `language` for the tool and frame of the closed-loop programs
/// (RAPID tGun / wTable, KRL tool 1 / base 1, Fanuc UT 1 / UF 1).
std::string loop_target(ProgramLanguage language, int i, const Pose<double>& written,
                        const std::vector<int>& cf) {
  const Eigen::Vector3d& p = written.p;
  const Eigen::Vector3d abc = euler_angles_deg(written.R, EulerConvention::ZyxABC);
  switch (language) {
    case ProgramLanguage::Rapid:
      return fmt::format("  CONST robtarget p{}:={};\n", i, robtarget(written, cf));
    case ProgramLanguage::Krl:
      return fmt::format(
          "  LIN {{X {:.6f},Y {:.6f},Z {:.6f},A {:.6f},B {:.6f},C {:.6f},S {},T {}}}\n", p.x(),
          p.y(), p.z(), abc[0], abc[1], abc[2], cf[0], cf[1]);
    case ProgramLanguage::Jbi:
      // Each position with its own ///RCONF (the configuration of the positions after it).
      return fmt::format(
          "///RCONF {},{},{},{},{},{},0,0\nC{:05d}={:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n",
          cf[0], cf[1], cf[2], cf[3], cf[4], cf[5], i, p.x(), p.y(), p.z(), abc[2], abc[1], abc[0]);
    case ProgramLanguage::UrScript: {
      // Assigned before the set_tcp of the program: the tool is the one at the movel using it.
      const Eigen::AngleAxisd r(written.R);
      const Eigen::Vector3d v = r.angle() * r.axis();
      return fmt::format("  p{} = p[{:.7f}, {:.7f}, {:.7f}, {:.8f}, {:.8f}, {:.8f}]\n", i,
                         p.x() / 1000, p.y() / 1000, p.z() / 1000, v.x(), v.y(), v.z());
    }
    default:
      return fmt::format(
          "P[{}]{{\n   GP1:\n\tUF : 1, UT : 1,\t\tCONFIG : '{} {} {}, {}, {}, {}',\n"
          "\tX = {:.6f} mm,\tY = {:.6f} mm,\tZ = {:.6f} mm,\n"
          "\tW = {:.6f} deg,\tP = {:.6f} deg,\tR = {:.6f} deg\n}};\n",
          i + 1, cf[0] ? 'F' : 'N', cf[1] ? 'D' : 'U', cf[2] ? 'B' : 'T', cf[3], cf[4], cf[5],
          p.x(), p.y(), p.z(), abc[2], abc[1], abc[0]);
  }
}

class ProgramClosedLoop : public ::testing::TestWithParam<std::pair<ProgramLanguage, const char*>> {
};

TEST_P(ProgramClosedLoop, FilteredProgramPutsTheToolWhereTheOriginalMeantIt) {
  const auto [language, robot_name] = GetParam();
  std::mt19937_64 rng(5);
  const CalibratedRobot robot = test::random_calibrated(robot_name, rng);
  const Compensator comp = make_compensator(robot);
  // URScript has no user frames: its targets are in the base frame.
  const Pose<double> F = language == ProgramLanguage::UrScript ? Pose<double>{} : frame_pose();
  const Pose<double> T = tool_pose();
  ProgramFilterOptions options;  // KRL and Fanuc: the tool and frame from a frames file
  options.tools = {{"TOOL_DATA[1]", T}, {"UT[1]", T}, {"TOOL[1]", T}};
  options.frames = {{"BASE_DATA[1]", F}, {"UF[1]", F}, {"USER[1]", F}};
  // Targets the nominal controller reaches with the tool in the frame: nominal flange poses
  // of random joints ≥ 10° from singularities, written in the frame.
  std::string body, moves;
  std::vector<Pose<double>> wanted_base;  // where the original program means the TCP to be
  while (wanted_base.size() < 12) {
    const Vector6d q = test::random_joints(comp.model, rng);
    if (test::near_singular(comp.model, q, 10)) continue;
    const Pose<double> base_T_tcp = nominal_tcp_pose(comp, q) * comp.tcp_T_flange * T;
    const int i = static_cast<int>(wanted_base.size());
    body +=
        loop_target(language, i, F.inverse() * base_T_tcp, maker_configuration(comp, language, q));
    moves += language == ProgramLanguage::UrScript
                 ? fmt::format("  movel(p{}, a=1.2, v=0.25)\n", i)
                 : fmt::format("    MoveL p{}, v100, fine, tGun\\WObj:=wTable;\n", i);
    wanted_base.push_back(base_T_tcp);
  }
  std::string text;
  if (language == ProgramLanguage::Rapid)
    text = fmt::format("MODULE Loop\n  PERS tooldata tGun:={};\n  PERS wobjdata wTable:={};\n",
                       kTool, kWobj) +
           body + "  PROC main()\n" + moves + "  ENDPROC\nENDMODULE\n";
  else if (language == ProgramLanguage::Krl)
    text = "DEF loop( )\n  BAS(#TOOL,1)\n  BAS(#BASE,1)\n" + body + "END\n";
  else if (language == ProgramLanguage::FanucLs)
    text = "/PROG  LOOP\n/ATTR\n/MN\n   1:  UFRAME_NUM=1 ;\n/POS\n" + body + "/END\n";
  else if (language == ProgramLanguage::Jbi)
    text =
        "/JOB\n//NAME LOOP\n//POS\n///NPOS 12,0,0,0,0,0\n///USER 1\n///TOOL 1\n"
        "///POSTYPE USER\n///RECTAN\n" +
        body + "//INST\n///DATE 2026/01/01 00:00\n///ATTR SC,RW\n///GROUP1 RB1\nNOP\nEND\n";
  else
    text = "def loop():\n" + body + "  set_tcp(p[0.010, 0.020, 0.150, 0.0, 0.5235987756, 0.0])\n" +
           moves + "end\n";
  const std::string file = std::string("loop") + program_extension(language);
  const auto result =
      filter_program(text, language, file, options, make_program_corrector(comp, language, &robot));
  ASSERT_EQ(result.cartesian_points, 12);
  ASSERT_TRUE(result.uncorrected.empty());
  // A second pass with a model equal to nominal changes nothing beyond the last printed digit.
  const Compensator nominal = make_compensator(CalibratedRobot::nominal(comp.model, robot.tool));
  EXPECT_EQ(
      filter_program(text, language, file, options, make_program_corrector(nominal, language)).text,
      text);

  // The controller: nominal inverse of each target with the tool in the frame, in the written
  // configuration; the arm: the calibrated model (the true robot of this simulation).
  // URScript has no configuration data: the controller takes the solution nearest to the
  // joints it is at (the previous target's), as the corrector does.
  Vector6d previous = Vector6d::Zero();
  const auto execute = [&](const ProgramPoint& p) {
    const Pose<double> base_T_flange = F * p.base_T_tcp * T.inverse();
    const IkResult all = nominal_ik(comp.geometry, base_T_flange, previous);
    const IkSolution* chosen = nullptr;
    for (const IkSolution& s : all)
      if (p.config.empty() ? (!chosen || (s.joints - previous).squaredNorm() <
                                             (chosen->joints - previous).squaredNorm())
                           : maker_configuration(comp, language, s.joints) == p.config)
        chosen = &s;
    if (!chosen) {
      ADD_FAILURE() << "no nominal solution in the configuration of line " << p.line;
      return Pose<double>{};
    }
    previous = chosen->joints;
    ChainState state;
    return Pose<double>(comp.base_T_world * calibrated_tcp_pose(comp.chain, chosen->joints, state) *
                        comp.tcp_T_flange * T);
  };
  const auto before = read_program_points(text, language, file);
  const auto after = read_program_points(result.text, language, file);
  double worst = 0, worst_deg = 0, uncompensated = 0;
  for (size_t i = 0; i < after.size(); ++i) {
    const Vector6d start = previous;
    uncompensated = std::max(uncompensated, (execute(before[i]).p - wanted_base[i].p).norm());
    previous = start;
    const Pose<double> reached = execute(after[i]);
    worst = std::max(worst, (reached.p - wanted_base[i].p).norm());
    worst_deg = std::max(
        worst_deg, rad2deg(Eigen::AngleAxisd(reached.R.transpose() * wanted_base[i].R).angle()));
  }
  // Printing limits: 4 decimals of mm; orientation 9 quaternion decimals (RAPID) or 5 of a
  // degree (KRL, Fanuc: 1e-5° ≈ 3e-5 mm at 200 mm); Yaskawa 3 decimals of mm (≤ 0.87 µm) and 4
  // of a degree (≈ 1e-4° ≈ 4e-4 mm at 200 mm).
  const bool jbi = language == ProgramLanguage::Jbi;
  EXPECT_LT(worst, jbi ? 2e-3 : 2e-4) << "uncompensated " << uncompensated;
  EXPECT_LT(worst_deg, jbi ? 2e-4 : 2e-5);
  EXPECT_GT(uncompensated, 0.1);
  RecordProperty("worst_mm", fmt::format("{:.3g}", worst));
}

// The closed loop over a KUKA module: the points declared in the .dat, used in the .src under
// a FRAME of the .dat ($TOOL = TGUN) in base 1 (BAS), under an inline form's FDAT (tool 2
// of the frames file, base 0), and under tool 3 set in the .src (TOOL_DATA[3] = {..},
// BAS(#TOOL, 3)) in a FRAME base of the .dat ($BASE = XFIX); the filtered pair, executed on
// the true robot with each point's tool and base, puts the tool where the original meant it.
TEST(ProgramClosedLoopKrl, ModuleDatPointsCorrectedWithTheSrcToolAndBase) {
  std::mt19937_64 rng(11);
  const CalibratedRobot robot = test::random_calibrated("kuka-kr6-r900-sixx", rng);
  const Compensator comp = make_compensator(robot);
  const Pose<double> F = frame_pose(), T = tool_pose();  // TGUN: A 0, B 30, C 0
  Pose<double> T2, T3, X;
  T2.p = Eigen::Vector3d(-5, 0, 210);
  T3.p = Eigen::Vector3d(4, -6, 180);  // TOOL_DATA[3]: C 20 turns about x
  T3.R = Eigen::AngleAxisd(deg2rad(20), Eigen::Vector3d::UnitX()).toRotationMatrix();
  X.p = Eigen::Vector3d(350, -120, 40);  // XFIX: A 15 turns about z
  X.R = Eigen::AngleAxisd(deg2rad(15), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  ProgramFilterOptions options;
  options.tools["TOOL_DATA[2]"] = T2;
  options.frames["BASE_DATA[1]"] = F;
  std::string dat =
      "DEFDAT LOOP\nDECL FRAME TGUN={X 10.0,Y 20.0,Z 150.0,A 0.0,B 30.0,C 0.0}\n"
      "DECL FDAT FQ={TOOL_NO 2,BASE_NO 0,IPO_FRAME #BASE}\n"
      "DECL FRAME XFIX={X 350.0,Y -120.0,Z 40.0,A 15.0,B 0.0,C 0.0}\n";
  std::string gun = "DEF loop( )\n  $TOOL=TGUN\n  BAS(#BASE,1)\n", inline_form,
              fixture =
                  "  TOOL_DATA[3]={X 4.0,Y -6.0,Z 180.0,A 0.0,B 0.0,C 20.0}\n"
                  "  BAS(#TOOL,3)\n  $BASE=XFIX\n";
  const std::array<Pose<double>, 3> group_tool = {T, T2, T3}, group_frame = {F, Pose<double>{}, X};
  std::vector<Pose<double>> wanted_base;
  while (wanted_base.size() < 18) {
    const Vector6d q = test::random_joints(comp.model, rng);
    if (test::near_singular(comp.model, q, 10)) continue;
    const size_t i = wanted_base.size();
    const size_t group = i / 6;
    const Pose<double>& tool = group_tool[group];
    const Pose<double>& frame = group_frame[group];
    const Pose<double> base_T_tcp = nominal_tcp_pose(comp, q) * comp.tcp_T_flange * tool;
    const Pose<double> written = frame.inverse() * base_T_tcp;
    const Eigen::Vector3d abc = euler_angles_deg(written.R, EulerConvention::ZyxABC);
    const std::vector<int> st = maker_configuration(comp, ProgramLanguage::Krl, q);
    dat += fmt::format(
        "DECL E6POS XP{}={{X {:.6f},Y {:.6f},Z {:.6f},A {:.6f},B {:.6f},C {:.6f},S {},T {}}}\n", i,
        written.p.x(), written.p.y(), written.p.z(), abc[0], abc[1], abc[2], st[0], st[1]);
    (group == 0 ? gun : group == 1 ? inline_form : fixture) += fmt::format("  LIN XP{}\n", i);
    wanted_base.push_back(base_T_tcp);
  }
  dat += "ENDDAT\n";
  const std::string src =
      gun + "  FDAT_ACT=FQ\n  BAS(#CP_PARAMS,0.2)\n" + inline_form + fixture + "END\n";
  const auto corrector = make_program_corrector(comp, ProgramLanguage::Krl, &robot);
  const ProgramFilterResult result =
      filter_krl_module(src, dat, "loop.src", "loop.dat", options, corrector);
  ASSERT_EQ(result.cartesian_points, 18);
  EXPECT_EQ(result.text, src);  // the .src has no literal point: unchanged
  const Compensator nominal = make_compensator(CalibratedRobot::nominal(comp.model, robot.tool));
  EXPECT_EQ(*filter_krl_module(src, dat, "loop.src", "loop.dat", options,
                               make_program_corrector(nominal, ProgramLanguage::Krl))
                 .dat_text,
            dat);
  const std::map<std::string, Pose<double>> tools = {
      {"TGUN", T}, {"TOOL_DATA[2]", T2}, {"TOOL_DATA[3]", T3}};
  const std::map<std::string, Pose<double>> frames = {
      {"BASE_DATA[1]", F}, {"", Pose<double>{}}, {"XFIX", X}};
  const auto before = read_krl_module_points(src, dat, "loop.src", "loop.dat", options);
  const auto after =
      read_krl_module_points(result.text, *result.dat_text, "loop.src", "loop.dat", options);
  ASSERT_EQ(after.size(), 18u);
  double worst = 0, uncompensated = 0;
  for (size_t i = 0; i < after.size(); ++i) {
    // The controller: nominal inverse with the point's tool in its base, in the written S/T.
    const auto reached = [&](const ProgramPoint& p) {
      const Pose<double>& tool = tools.at(p.tool);
      const Pose<double>& frame = frames.at(p.frame == "BASE_DATA[0]" ? "" : p.frame);
      const Pose<double> base_T_flange = frame * p.base_T_tcp * tool.inverse();
      for (const IkSolution& s : nominal_ik(comp.geometry, base_T_flange, Vector6d::Zero()))
        if (maker_configuration(comp, ProgramLanguage::Krl, s.joints) == p.config) {
          ChainState state;
          return Pose<double>(comp.base_T_world * calibrated_tcp_pose(comp.chain, s.joints, state) *
                              comp.tcp_T_flange * tool);
        }
      ADD_FAILURE() << "no nominal solution in the configuration of line " << p.line;
      return Pose<double>{};
    };
    worst = std::max(worst, (reached(after[i]).p - wanted_base[i].p).norm());
    uncompensated = std::max(uncompensated, (reached(before[i]).p - wanted_base[i].p).norm());
  }
  EXPECT_LT(worst, 2e-4) << "uncompensated " << uncompensated;
  EXPECT_GT(uncompensated, 0.1);
  RecordProperty("worst_mm", fmt::format("{:.3g}", worst));
}

// On a general 6R arm (Fanuc CRX-10iA) the corrector starts the calibrated inverse from the
// previous target's joints when that target was near (a path): each corrected target must be the
// library's calibrated inverse of its written configuration seeded from the nominal solution
// nearest the previous joints (calibrated_ik), as for a target far from the previous one.
TEST(ProgramCorrector, PathOnAGeneralArmMatchesTheCalibratedInverse) {
  std::mt19937_64 rng(11);
  const CalibratedRobot robot = test::random_calibrated("fanuc-crx10ia", rng);
  const Compensator comp = make_compensator(robot);
  const auto corrector = make_program_corrector(comp, ProgramLanguage::FanucLs);
  std::uniform_real_distribution<double> step(-deg2rad(2), deg2rad(2));
  Vector6d q;
  do q = test::random_joints(comp.model, rng);
  while (test::near_singular(comp.model, q, 10));
  Vector6d previous = Vector6d::Zero();
  int points = 0, far = 0;
  for (int k = 0; k < 120; ++k) {
    Vector6d next = q;
    for (int i = 0; i < kJointCount; ++i) next[i] += step(rng);
    if (k % 40 == 39) next = test::random_joints(comp.model, rng);  // a jump: the full solve
    // Away from ±180°, where the written turn of a joint changes, and from the limits, beyond
    // which the calibrated answer may lie (then another turn is written).
    bool turn_edge = ((next.cwiseAbs().array() - std::numbers::pi).abs() < deg2rad(2)).any();
    for (int i = 0; i < kJointCount; ++i)
      turn_edge |= std::min(next[i] - comp.model.limits[i].lower,
                            comp.model.limits[i].upper - next[i]) < deg2rad(2);
    if (!comp.model.within_limits(next) || test::near_singular(comp.model, next, 10) || turn_edge)
      continue;
    far += k % 40 == 39;
    q = next;
    ProgramPoint point;
    point.base_T_tcp = nominal_tcp_pose(comp, q);
    point.config = maker_configuration(comp, ProgramLanguage::FanucLs, q);
    const CorrectedPoint got = corrector(point);
    ASSERT_TRUE(got.failure.empty()) << got.failure;
    const CalibratedIkResult want = calibrated_ik(comp, comp.world_T_base * point.base_T_tcp,
                                                  arm_config(comp.model, q), previous);
    ASSERT_TRUE(want.ok());
    EXPECT_LT((got.joints_deg - want.joints * kRadToDeg).cwiseAbs().maxCoeff(), 1e-6) << k;
    EXPECT_EQ(got.config, point.config) << k;
    previous = want.joints;
    ++points;
  }
  EXPECT_GT(points, 100);
  EXPECT_GE(far, 1);
}

INSTANTIATE_TEST_SUITE_P(
    Languages, ProgramClosedLoop,
    ::testing::Values(std::pair{ProgramLanguage::Rapid, "abb-irb120"},
                      std::pair{ProgramLanguage::Krl, "kuka-kr6-r900-sixx"},
                      std::pair{ProgramLanguage::FanucLs, "fanuc-lrmate200ic"},
                      std::pair{ProgramLanguage::Jbi, "yaskawa-gp7"},
                      // An offset wrist (three parallel axes) and the nearest-solution rule.
                      std::pair{ProgramLanguage::UrScript, "universal-robots-ur10e"},
                      // CONFIG letters and turns on a cobot with an offset wrist.
                      std::pair{ProgramLanguage::FanucLs, "fanuc-crx10ia"}),
    [](const auto& info) {
      std::string name =
          std::string(program_language_name(info.param.first)) + "_" + info.param.second;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

}  // namespace
}  // namespace robcal
