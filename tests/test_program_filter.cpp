// Program filtering: only the points' numbers change, every other byte stays (issue 7).

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <regex>
#include <set>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/programs/program_filter.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  size_t at = 0;
  while (at <= text.size()) {
    const size_t end = text.find('\n', at);
    if (end == std::string::npos) {
      lines.push_back(text.substr(at));
      break;
    }
    lines.push_back(text.substr(at, end - at + 1));  // keeps "\r\n" / "\n" as written
    at = end + 1;
  }
  return lines;
}

/// The line with every number literal replaced by '#': two lines that differ only in their
/// numbers have the same skeleton.
std::string skeleton(const std::string& line) {
  static const std::regex number(R"(-?\d+(\.\d*)?([eE][-+]?\d+)?)");
  return std::regex_replace(line, number, "#");
}

/// A known correction, independent of any robot: shift, small rotation about a skew axis,
/// joints + 0.1°, and the first configuration value + 1 for points written with cf1 = -1.
const Eigen::Vector3d kShift(0.5, -1.25, 2.0);
Eigen::Matrix3d known_rotation() {
  return Eigen::AngleAxisd(deg2rad(0.02), Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
}
CorrectedPoint known_correction(const ProgramPoint& p) {
  CorrectedPoint c;
  c.base_T_tcp.p = p.base_T_tcp.p + kShift;
  c.base_T_tcp.R = known_rotation() * p.base_T_tcp.R;
  c.joints_deg = p.joints_deg + Vector6d::Constant(0.1);
  c.config = p.config;
  if (!c.config.empty() && c.config[0] == -1) c.config[0] = 0;
  return c;
}

/// Yaskawa pulses per degree for weld_cell.jbi (any positive values exercise the conversion).
constexpr std::array<double, kJointCount> kPulses{1341.2, 1341.2, 1341.2, 1092.3, 1092.3, 614.4};

/// The tools and frames the sample programs use without defining them, all identity.
void sample_frames(ProgramFilterOptions& options) {
  options.tools["TOOL_DATA[1]"] = Pose<double>{};  // weld_seam.dat's FDAT FP1 names tool 1
  options.tools["UT[2]"] = Pose<double>{};         // weld_cell.ls: UT 2 and UF 1
  options.frames["UF[1]"] = Pose<double>{};
  options.tools["TOOL[1]"] = Pose<double>{};  // weld_cell.jbi: tools 1 and 2, user frame 1
  options.tools["TOOL[2]"] = Pose<double>{};
  options.frames["USER[1]"] = Pose<double>{};
  options.pulses_per_degree = kPulses;
}

/// Only the lines `changed` (1-based) differ, and only in their numbers.
void expect_only_numbers_change(const std::string& text, const std::string& corrected,
                                const std::set<int>& changed, const std::string& file) {
  const auto before = split_lines(text);
  const auto after = split_lines(corrected);
  ASSERT_EQ(before.size(), after.size());
  for (size_t i = 0; i < before.size(); ++i) {
    const int line = static_cast<int>(i) + 1;
    if (changed.count(line)) {
      EXPECT_NE(before[i], after[i]) << file << ":" << line << " should change";
      EXPECT_EQ(skeleton(before[i]), skeleton(after[i])) << file << ":" << line;
    } else {
      EXPECT_EQ(before[i], after[i]) << file << ":" << line << " must stay as written";
    }
  }
}

struct FilterCase {
  std::string file;
  bool joints;
  std::set<int> changed_lines;  // 1-based, read off the sample files by hand
  int cartesian, joint;
};

void check_filter(const FilterCase& fc) {
  const std::string path = test::data_path("programs/" + fc.file);
  const std::string text = read_text_file(path);
  const ProgramLanguage language = program_language_from_path(path);
  ProgramFilterOptions options;
  options.joints = fc.joints;
  sample_frames(options);
  const ProgramFilterResult result =
      filter_program(text, language, path, options, known_correction);
  EXPECT_EQ(result.cartesian_points, fc.cartesian);
  EXPECT_EQ(result.joint_points, fc.joint);

  expect_only_numbers_change(text, result.text, fc.changed_lines, fc.file);

  // The rewritten points read back as the known correction of the originals.
  const auto old_points = read_program_points(text, language, path, options);
  const auto new_points = read_program_points(result.text, language, path, options);
  ASSERT_EQ(old_points.size(), new_points.size());
  // Yaskawa prints whole pulses, 1 µm and 0.0001°; the others 4 decimals of a mm and 9
  // quaternion decimals (RAPID) or 5 decimals of a degree.
  const bool jbi = language == ProgramLanguage::Jbi;
  // URScript joints: radians with 8 decimals.
  const double ur_joint_deg = rad2deg(0.5e-8) + 1e-12;
  for (size_t i = 0; i < old_points.size(); ++i) {
    const CorrectedPoint want = known_correction(old_points[i]);
    const ProgramPoint& got = new_points[i];
    EXPECT_EQ(got.line, old_points[i].line);
    if (got.is_joint_target) {
      for (int j = 0; j < kJointCount; ++j)
        EXPECT_LE(std::abs(got.joints_deg[j] - want.joints_deg[j]),
                  jbi                                     ? 0.5 / kPulses[static_cast<size_t>(j)]
                  : language == ProgramLanguage::UrScript ? ur_joint_deg
                                                          : 1e-9)
            << got.line;
      continue;
    }
    EXPECT_LT((got.base_T_tcp.p - want.base_T_tcp.p).norm(), jbi ? 1e-3 : 1e-4) << got.line;
    const Eigen::AngleAxisd diff(got.base_T_tcp.R.transpose() * want.base_T_tcp.R);
    EXPECT_LT(rad2deg(std::abs(diff.angle())), jbi ? 2e-4 : 2e-5) << got.line;
    EXPECT_EQ(got.config, want.config) << got.line;
  }
}

TEST(ProgramFilter, RapidOnlyRobtargetLinesChange) {
  check_filter({"pick_place.mod", false, {5, 6, 7, 9, 10, 20}, 6, 0});
}

TEST(ProgramFilter, RapidJointTargetsWhenAsked) {
  check_filter({"pick_place.mod", true, {5, 6, 7, 9, 10, 11, 20, 23}, 6, 2});
}

TEST(ProgramFilter, KrlDatPointsChangeFramesStay) {
  check_filter({"weld_seam.dat", false, {4, 6, 7, 11}, 4, 0});
  check_filter({"weld_seam.dat", true, {4, 6, 7, 9, 11}, 4, 1});
}

// A KUKA module (glue_cell.src with glue_cell.dat): the .dat's points corrected with the tool
// and base active at the .src motions that use them (inline forms' FDAT_ACT + BAS, $TOOL = a
// FRAME of the .dat or of the .src, $BASE = BASE_DATA[n] or a FRAME of the .dat, TOOL_DATA[n]
// set in the .src then BAS(#TOOL, n), BAS(#BASE, n) of the frames file); only their numbers
// change, in both files.
TEST(ProgramFilter, KrlModuleDatPointsTakeTheSrcToolAndBase) {
  const std::string src_path = test::data_path("programs/glue_cell.src");
  const std::string dat_path = test::data_path("programs/glue_cell.dat");
  EXPECT_EQ(krl_companion_path(src_path), dat_path);
  EXPECT_EQ(krl_companion_path("A/WELD.DAT"), "A/WELD.SRC");
  const std::string src = read_text_file(src_path), dat = read_text_file(dat_path);
  ProgramFilterOptions options;
  options.joints = true;
  options.tools["TOOL_DATA[1]"] = Pose<double>{};
  options.frames["BASE_DATA[1]"] = Pose<double>{};
  options.frames["BASE_DATA[2]"] = Pose<double>{};
  std::vector<ProgramPoint> seen;
  const auto record = [&](const ProgramPoint& p) {
    seen.push_back(p);
    return known_correction(p);
  };
  const ProgramFilterResult result =
      filter_krl_module(src, dat, src_path, dat_path, options, record);
  ASSERT_TRUE(result.dat_text.has_value());
  EXPECT_EQ(result.cartesian_points, 11);
  EXPECT_EQ(result.joint_points, 1);
  // Read off the two files by hand: (line, tool, base) of each point, the .src's first.
  const std::vector<std::tuple<int, std::string, std::string>> want = {
      {54, "TNOZZLE", "BASE_DATA[2]"},       // inline, after $TOOL = TNOZZLE
      {63, "TOOL_DATA[3]", "XFIXTURE"},      // inline, after TOOL_DATA[3]={..}, BAS(#TOOL, 3)
      {16, "TOOL_DATA[1]", "BASE_DATA[1]"},  // XPRE: FDAT_ACT = FPRE, BAS(#PTP_PARAMS)
      {19, "TOOL_DATA[1]", "BASE_DATA[1]"},  // XP1: FP1, BAS(#CP_PARAMS)
      {22, "TOOL_DATA[1]", "BASE_DATA[1]"},  // XP2
      {28, "TNOZZLE", "BASE_DATA[2]"},       // XSEAM[1], used twice
      {29, "TNOZZLE", "BASE_DATA[2]"},       // XSEAM[2]
      {30, "TNOZZLE", "BASE_DATA[2]"},       // XSEAM[3], the CIRC target
      {31, "TNOZZLE", "BASE_DATA[2]"},       // XAUX, the CIRC auxiliary point
      {32, "", ""},                          // XSPARE: no motion uses it
      {35, "TOOL_DATA[3]", "XFIXTURE"},      // XFIX1: $BASE = XFIXTURE
      {36, "TCLAMP", "BASE_DATA[1]"}};       // XFIX2: $TOOL = TCLAMP (the .src's), BAS(#BASE,1)
  ASSERT_EQ(seen.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(seen[i].line, std::get<0>(want[i])) << i;
    EXPECT_EQ(seen[i].tool, std::get<1>(want[i])) << seen[i].line;
    EXPECT_EQ(seen[i].frame, std::get<2>(want[i])) << seen[i].line;
  }
  // TNOZZLE's literal value {X 0.0,Y 35.5,Z 180.0,A 0.0,B -15.0,C 0.0}: a turn about y.
  ASSERT_TRUE(seen[0].flange_T_tcp.has_value());
  EXPECT_LT((seen[0].flange_T_tcp->p - Eigen::Vector3d(0, 35.5, 180)).norm(), 1e-12);
  EXPECT_LT((seen[0].flange_T_tcp->R -
             Eigen::AngleAxisd(deg2rad(-15), Eigen::Vector3d::UnitY()).toRotationMatrix())
                .norm(),
            1e-12);
  // The tool set in the .src, TOOL_DATA[3] = {X -2.5, Y 0, Z 215}; the .src's own TCLAMP
  // {X 0, Y -12, Z 150, B 10}; XFIX1 {X 40, Y 25, Z 110} in XFIXTURE {X 900, Y -250, Z 12.5,
  // A -30} handed over in the base frame.
  ASSERT_TRUE(seen[1].flange_T_tcp && seen[11].flange_T_tcp);
  EXPECT_LT((seen[1].flange_T_tcp->p - Eigen::Vector3d(-2.5, 0, 215)).norm(), 1e-12);
  EXPECT_TRUE(seen[1].flange_T_tcp->R.isIdentity(1e-12));
  const Pose<double>& clamp = *seen[11].flange_T_tcp;
  EXPECT_LT((clamp.p - Eigen::Vector3d(0, -12, 150)).norm(), 1e-12);
  EXPECT_LT((clamp.R - Eigen::AngleAxisd(deg2rad(10), Eigen::Vector3d::UnitY()).toRotationMatrix())
                .norm(),
            1e-12);
  Pose<double> fixture;
  fixture.p = Eigen::Vector3d(900, -250, 12.5);
  fixture.R = Eigen::AngleAxisd(deg2rad(-30), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_LT((seen[10].base_T_tcp.p - fixture * Eigen::Vector3d(40, 25, 110)).norm(), 1e-9);
  ASSERT_EQ(result.assumed.size(), 1u);
  EXPECT_EQ(result.assumed[0].where, dat_path + ":32:19 (XSPARE)");
  expect_only_numbers_change(src, result.text, {54, 63}, "glue_cell.src");
  expect_only_numbers_change(dat, *result.dat_text, {16, 19, 22, 28, 29, 30, 31, 32, 35, 36},
                             "glue_cell.dat");
  // The rewritten points read back as the known correction of the originals, made in the
  // base frame (the frames file's bases are identity here; the fixture is not).
  const auto old_points = read_krl_module_points(src, dat, src_path, dat_path, options);
  const auto new_points =
      read_krl_module_points(result.text, *result.dat_text, src_path, dat_path, options);
  ASSERT_EQ(new_points.size(), old_points.size());
  for (size_t i = 0; i < old_points.size(); ++i) {
    const Pose<double> frame = old_points[i].frame == "XFIXTURE" ? fixture : Pose<double>{};
    ProgramPoint in_base = old_points[i];
    in_base.base_T_tcp = frame * in_base.base_T_tcp;
    CorrectedPoint c = known_correction(in_base);
    c.base_T_tcp = frame.inverse() * c.base_T_tcp;
    if (old_points[i].is_joint_target) {
      EXPECT_LT((new_points[i].joints_deg - c.joints_deg).norm(), 1e-9);
      continue;
    }
    EXPECT_LT((new_points[i].base_T_tcp.p - c.base_T_tcp.p).norm(), 1e-4);
    EXPECT_LT((new_points[i].base_T_tcp.R - c.base_T_tcp.R).norm(), 1e-6);
    EXPECT_EQ(new_points[i].config, c.config);
  }
  // A second pass with an identity correction changes no byte of either file.
  const auto same = [](const ProgramPoint& p) {
    return CorrectedPoint{p.base_T_tcp, p.config, p.joints_deg, "", std::nullopt};
  };
  const ProgramFilterResult again =
      filter_krl_module(result.text, *result.dat_text, src_path, dat_path, options, same);
  EXPECT_EQ(again.text, result.text);
  EXPECT_EQ(*again.dat_text, *result.dat_text);
  EXPECT_EQ(result.confidence_csv.substr(0, result.confidence_csv.find('\n')),
            "file,line,column,name,confidence95_mm");
}

TEST(ProgramFilter, KrlSrcInlinePointsChange) {
  check_filter({"weld_seam.src", false, {4, 7}, 2, 0});
  check_filter({"weld_seam.src", true, {4, 7, 8}, 2, 1});
}

TEST(ProgramFilter, FanucPositionsChangeEverythingElseStays) {
  // P[2]'s GP2 (an external axis, mm) and the comment in /MN with "X = 1.0 mm" stay.
  check_filter({"weld_cell.ls", false, {34, 35, 40, 41, 49, 50}, 3, 0});
  check_filter({"weld_cell.ls", true, {34, 35, 40, 41, 49, 50, 55, 56}, 3, 1});
}

TEST(ProgramFilter, UrScriptPosesChangeOffsetsAndToolsStay) {
  // Targets: the assigned pose (line 5), the inline movel (8), both poses of movec (12); the
  // set_tcp poses, the pose_trans offset, the joint list and the text stay.
  check_filter({"pick.script", false, {5, 8, 12}, 4, 0});
  // With joints, the movej joint list (line 6) too.
  check_filter({"pick.script", true, {5, 6, 8, 12}, 4, 1});
}

TEST(ProgramFilter, YaskawaPositionsChangeBaseAxesAndInstructionsStay) {
  // weld_cell.jbi (CR LF): C00000..C00003 Cartesian (user frame 1 with tool 1, then the robot
  // frame with tool 2), C00004 in pulses; BC00000 (a base axis), the comment quoting
  // "C00000=1,2,3" and the instructions stay.
  check_filter({"weld_cell.jbi", false, {10, 11, 13, 16}, 4, 0});
  check_filter({"weld_cell.jbi", true, {10, 11, 13, 16, 19}, 4, 1});
}

TEST(ProgramFilter, YaskawaPointsReadWithTheirToolFrameAndRconf) {
  const std::string path = test::data_path("programs/weld_cell.jbi");
  ProgramFilterOptions options;
  options.joints = true;
  options.pulses_per_degree = kPulses;
  const auto points =
      read_program_points(read_text_file(path), ProgramLanguage::Jbi, path, options);
  ASSERT_EQ(points.size(), 5u);
  EXPECT_EQ(points[0].name, "C00000");
  EXPECT_EQ(points[0].tool, "TOOL[1]");
  EXPECT_EQ(points[0].frame, "USER[1]");
  EXPECT_EQ(points[0].config, (std::vector<int>{0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(points[2].config, (std::vector<int>{1, 0, 0, 0, 0, 0}));
  EXPECT_EQ(points[3].tool, "TOOL[2]");
  EXPECT_EQ(points[3].frame, "");
  EXPECT_EQ(points[0].column, 8);
  // C00000 = 412.5, -85.25, 230 mm, (Rx, Ry, Rz) = (180, 0, -15.5)°: R = Rz·Ry·Rx.
  EXPECT_NEAR((points[0].base_T_tcp.p - Eigen::Vector3d(412.5, -85.25, 230)).norm(), 0, 1e-12);
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(deg2rad(-15.5), Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(deg2rad(180.0), Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  EXPECT_LT((points[0].base_T_tcp.R - R).norm(), 1e-12);
  // C00004 = 0, -12000, 8500, 0, -32000, 1500 pulses.
  EXPECT_TRUE(points[4].is_joint_target);
  EXPECT_NEAR(points[4].joints_deg[1], -12000 / 1341.2, 1e-12);
  EXPECT_NEAR(points[4].joints_deg[5], 1500 / 614.4, 1e-12);
}

TEST(ProgramFilter, YaskawaRefusals) {
  const auto jbi = [](const std::string& pos) {
    try {
      ProgramFilterOptions options;
      options.joints = true;
      filter_program("/JOB\r\n//NAME T\n//POS\n" + pos + "//INST\nNOP\nEND\n", ProgramLanguage::Jbi,
                     "t.jbi", options, known_correction);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string rectan = "///POSTYPE ROBOT\n///RECTAN\n";
  EXPECT_EQ(jbi("///NPOS 2,0,0,0,0,0\n" + rectan + "///RCONF 0,0,0,0,0,0\nC00000=1,2,3,4,5,6\n"),
            "t.jbi:4:9 (///NPOS): ///NPOS declares 2 C positions (count 1 of c,bc,ec,p,bp,ex), "
            "the job defines 1");
  // Every count is checked: position variables P, BP, EX (kept as written) included.
  const std::string one = rectan + "///RCONF 0,0,0,0,0,0\nC00000=1,2,3,4,5,6\n";
  EXPECT_EQ(jbi("///NPOS 1,0,0,2,0,0\n" + one + "P0001=1,2,3,4,5,6\n"),
            "t.jbi:4:9 (///NPOS): ///NPOS declares 2 P positions (count 4 of c,bc,ec,p,bp,ex), "
            "the job defines 1");
  EXPECT_EQ(jbi("///NPOS 1,0,0,0,1,0\n" + one + "EX0001=100\n"),
            "t.jbi:4:9 (///NPOS): ///NPOS declares 1 BP positions (count 5 of c,bc,ec,p,bp,ex), "
            "the job defines 0");
  EXPECT_EQ(jbi("///NPOS 1,2,0,0,0,0\n" + one + "///PULSE\nBC00000=100\n"),
            "t.jbi:4:9 (///NPOS): ///NPOS declares 2 BC positions (count 2 of c,bc,ec,p,bp,ex), "
            "the job defines 1");
  EXPECT_EQ(jbi("///NPOS 1,0,0,0,0,0\n" + one + "///PULSE\nEC00000=100\n"),
            "t.jbi:4:9 (///NPOS): ///NPOS declares 0 EC positions (count 3 of c,bc,ec,p,bp,ex), "
            "the job defines 1");
  // A name defined twice: the counts agree, but one position would hold two values.
  EXPECT_EQ(jbi("///NPOS 2,0,0,0,0,0\n" + one + "C00000=1,2,3,4,5,7\n"),
            "t.jbi:9:1: C00000 is defined twice (first at line 8)");
  EXPECT_EQ(jbi("///NPOS 1,0,0,2,0,0\n" + one + "P0001=1,2,3,4,5,6\nP0001=1,2,3,4,5,6\n"),
            "t.jbi:10:1: P0001 is defined twice (first at line 9)");
  EXPECT_EQ(jbi("///NPOS 1,0,0,1,1,1\n" + one + "P0001=1,2,3,4,5,6\nBP001=5\nEX0001=100\n"), "");
  EXPECT_EQ(jbi(one),
            "t.jbi (///NPOS): the job defines positions but has no ///NPOS line in //POS");
  EXPECT_EQ(jbi("///NPOS 1,0,0,0,0,0\n///NPOS 1,0,0,0,0,0\n"),
            "t.jbi:5:1: second ///NPOS line (the first at line 4)");
  EXPECT_EQ(
      jbi("///NPOS 1,0,-1,0,0,0\n"),
      "t.jbi:4:13: ///NPOS: expected a whole EC count 0..100000 (the EC names have 5 digits)");
  // The names bound the counts: C00000..C99999 are 100,000 positions, P0000..P9999 10,000.
  std::string all_c;
  for (int i = 0; i < 100000; ++i) all_c += fmt::format("C{:05d}=1,2,3,4,5,6\n", i);
  EXPECT_EQ(jbi("///NPOS 100000,0,0,0,0,0\n" + rectan + "///RCONF 0,0,0,0,0,0\n" + all_c), "");
  EXPECT_EQ(jbi("///NPOS 100001,0,0,0,0,0\n"),
            "t.jbi:4:9: ///NPOS: expected a whole C count 0..100000 (the C names have 5 digits)");
  EXPECT_EQ(jbi("///NPOS 1,0,0,10001,0,0\n"),
            "t.jbi:4:15: ///NPOS: expected a whole P count 0..10000 (the P names have 4 digits)");
  EXPECT_EQ(jbi("///NPOS 1,0,0,0,0,0\n///POSTYPE PULSE\n///PULSE\nC00000=1,2,3,4,5,6\n"),
            "t.jbi:7:8: pulse positions need the robot's pulses per degree (robot file key "
            "pulses_per_degree)");
  EXPECT_EQ(jbi(rectan + "C00000=1,2,3,4,5,6\n"),
            "t.jbi:6:1: Cartesian position without a ///RCONF line before it");
  EXPECT_EQ(jbi(rectan + "///RCONF 0,0,0,0,0,0\nC00000=1,2,3,4,5,6,7\n"),
            "t.jbi:7:8: C00000 has seven robot axis values: a seven-axis arm (SIA/SDA series); "
            "robcal calibrates six-axis arms, the job is refused");
  EXPECT_EQ(jbi(rectan + "///RCONF 0,0,0,0,0,0\nC00000=1,2,3,4,5\n"),
            "t.jbi:7:8: C00000: expected six robot axis values, found 5");
  EXPECT_EQ(jbi(rectan + "///RCONF 0,2,0,0,0,0\n"), "t.jbi:6:12: ///RCONF: expected flags 0 or 1");
  EXPECT_EQ(jbi("///POSTYPE TOOL\n///RECTAN\n///RCONF 0,0,0,0,0,0\nC00000=1,2,3,4,5,6\n"),
            "t.jbi:7:1: Cartesian position of type 'TOOL': expected ROBOT, BASE or USER");
  EXPECT_EQ(jbi("///POSTYPE BASE\n///RECTAN\n///RCONF 0,0,0,0,0,0\nC00000=1,2,3,4,5,6\n"
                "///PULSE\nBC00000=100\n"),
            "t.jbi:7:1: Cartesian position in the BASE frame of a robot on a base axis (the job "
            "has BC positions): the frame moves, the position is not corrected");
  EXPECT_EQ(jbi(rectan + "///RCONF 0,0,0,0,0,0\nC00000=1,2,3.5.1,4,5,6\n"),
            "t.jbi:7:12: malformed number '3.5.1'");
  EXPECT_EQ(jbi(rectan + "///RCONF 0,0,0,0,0,0\nC0000=1,2,3,4,5,6\n"),
            "t.jbi:7:2: expected a position name with five digits and '=' (C00000=...)");
  EXPECT_EQ(jbi("MOVL C00000\n"),
            "t.jbi:4:1: expected a ///pseudo-instruction, a C, BC or EC position or a P, BP or "
            "EX variable in //POS");
}

TEST(ProgramFilter, IdentityCorrectionKeepsEveryByte) {
  for (const char* file : {"pick_place.mod", "weld_seam.dat", "weld_seam.src", "weld_cell.ls",
                           "pick.script", "weld_cell.jbi"}) {
    const std::string path = test::data_path(std::string("programs/") + file);
    const std::string text = read_text_file(path);
    ProgramFilterOptions options;
    options.joints = true;
    sample_frames(options);
    const auto result = filter_program(
        text, program_language_from_path(path), path, options, [](const ProgramPoint& p) {
          return CorrectedPoint{p.base_T_tcp, p.config, p.joints_deg, ""};
        });
    EXPECT_EQ(result.text, text) << file;
  }
}

TEST(ProgramFilter, ReadsValuesAsWritten) {
  const std::string path = test::data_path("programs/pick_place.mod");
  const auto points = read_program_points(read_text_file(path), ProgramLanguage::Rapid, path);
  ASSERT_EQ(points.size(), 6u);
  EXPECT_EQ(points[1].name, "pPick");
  EXPECT_EQ(points[1].line, 6);
  EXPECT_NEAR(points[1].base_T_tcp.p.x(), 400.5, 1e-12);
  EXPECT_NEAR(points[1].base_T_tcp.p.y(), -120.25, 1e-12);
  EXPECT_EQ(points[1].config, (std::vector<int>{-1, 0, 0, 0}));
  // q = (0, √½, √½, 0): a half turn about (1,1,0)/√2 maps x to y.
  EXPECT_NEAR((points[1].base_T_tcp.R * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(),
              0, 1e-6);
  EXPECT_EQ(points[3].name, "pPath{1}");
  EXPECT_EQ(points[4].name, "pPath{2}");
  EXPECT_EQ(points[5].name, "");  // inline in MoveL

  const std::string dat = test::data_path("programs/weld_seam.dat");
  const auto krl = read_program_points(read_text_file(dat), ProgramLanguage::Krl, dat);
  ASSERT_EQ(krl.size(), 4u);
  EXPECT_EQ(krl[1].config, (std::vector<int>{2, 10}));  // 'B010', 'B1010'
  EXPECT_EQ(krl[3].name, "XSEAM[1]");
  // A -45, B 60, C 170 → R = Rz(-45)·Ry(60)·Rx(170).
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(deg2rad(-45), Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(deg2rad(60), Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(deg2rad(170), Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  EXPECT_LT((krl[1].base_T_tcp.R - R).norm(), 1e-12);
}

/// The error message of filtering `text`, or "" when it is accepted.
std::string filter_error(const std::string& text, ProgramLanguage language) {
  try {
    filter_program(text, language, "bad.prg", {}, known_correction);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ProgramFilter, RefusesWhatItCannotCorrectNamingLineAndColumn) {
  const auto rapid = ProgramLanguage::Rapid;
  EXPECT_EQ(filter_error("MODULE m\n  CONST robtarget p:=[[x0,0,0],[1,0,0,0],[0,0,0,0],"
                         "[9E9,9E9,9E9,9E9,9E9,9E9]];\nENDMODULE\n",
                         rapid),
            "bad.prg:2:22: 'p' is declared robtarget but its value is not a literal "
            "[[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[e1,...,e6]]");
  EXPECT_EQ(filter_error("MODULE m\n  CONST robtarget p10:=[[1,2,3],[1,0,0,0],[0,0,0,0],"
                         "[9E9,9E9,9E9,9E9,9E9,9E9]];\nPROC main()\n  MoveL p10, v100, fine, "
                         "tool0\\WObj:=wobjTable;\n",
                         rapid),
            "bad.prg:2:24 (p10): unknown work object 'WOBJTABLE': the program does not "
            "define it with literal values; give it in a frames file");
  EXPECT_NE(filter_error("MODULE m\n  MoveL [[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]"
                         ", v100, fine, tool0;\n",
                         rapid)
                .find("bad.prg:2:82: expected ',' or ']', found ';'"),
            std::string::npos);
  EXPECT_NE(
      filter_error("CONST robtarget p:=[[1,2,3],[0.9,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];",
                   rapid)
          .find("bad.prg:1:29: quaternion"),
      std::string::npos);
  EXPECT_NE(
      filter_error("CONST string s:=\"never closed;\n", rapid).find("bad.prg:1:17: unterminated"),
      std::string::npos);
  const auto krl = ProgramLanguage::Krl;
  EXPECT_NE(
      filter_error("DEF p()\n  LIN {X 100, Y 0}\nEND\n", krl).find("bad.prg:2:7: point has no Z"),
      std::string::npos);
  EXPECT_NE(filter_error("DECL E6POS P1={X 1,Y 2,Z 3,A 0,B 0,C $VAR,S 2,T 2}\n", krl)
                .find("bad.prg:1:38: C is not a number literal"),
            std::string::npos);
  EXPECT_NE(
      filter_error("DECL POS P1={X 1,Y 2,Z 3,A 0,B 0,C 0,S 2}\n", krl).find("only one of S and T"),
      std::string::npos);
  // A relative motion and a frame are not points: accepted untouched.
  EXPECT_EQ(filter_error(
                "DEF p()\n  LIN_REL {Z 50}\n  DECL FRAME F={X 1,Y 2,Z 3,A 0,B 0,C 0}\nEND\n", krl),
            "");
}

TEST(ProgramFilter, CorrectorFailureNamesThePoint) {
  const std::string text =
      "CONST robtarget pFar:=[[5000,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n";
  try {
    filter_program(text, ProgramLanguage::Rapid, "far.mod", {}, [](const ProgramPoint&) {
      CorrectedPoint c;
      c.failure = "out of reach";
      return c;
    });
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "far.mod:1:23 (pFar): out of reach");
  }
}

TEST(ProgramFilter, LanguageFromExtension) {
  EXPECT_EQ(program_language_from_path("a/b/MAIN.MOD"), ProgramLanguage::Rapid);
  EXPECT_EQ(program_language_from_path("x.dat"), ProgramLanguage::Krl);
  EXPECT_EQ(program_language_from_path("WELD.JBI"), ProgramLanguage::Jbi);
  EXPECT_REFUSED(program_language_from_path("x.txt"), InputError,
                 "x.txt: unknown program type: expected an ABB RAPID module");
}

}  // namespace
}  // namespace robcal
