// RAPID and KRL parsing and rewriting that bad or unusual text cannot corrupt (issue 21):
// components in any order, numbers read whole, no recursion on nesting depth, the input
// never overwritten.

#include <gtest/gtest.h>
#include <pthread.h>

#include <filesystem>
#include <fstream>

#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/programs/program_filter.hpp"

namespace robcal {
namespace {

/// Moves every Cartesian point by (1, 2, 3) mm, keeps orientation and configuration.
CorrectedPoint shift_123(const ProgramPoint& p) {
  CorrectedPoint c;
  c.base_T_tcp = p.base_T_tcp;
  c.base_T_tcp.p += Eigen::Vector3d(1, 2, 3);
  c.config = p.config;
  c.joints_deg = p.joints_deg;
  return c;
}

std::string error_of(const std::string& text, ProgramLanguage language,
                     const std::string& file = "bad.src") {
  try {
    filter_program(text, language, file, {}, shift_123);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ProgramParser, KrlComponentsInAnyOrderAreRewrittenInPlace) {
  // The issue-21 programs: Y before X, S and T first. Expected text written by hand: only the
  // X, Y, Z numbers change, in place; everything after them (END included) stays once.
  const std::string text =
      "DEF odd( )\n"
      "  LIN {Y 100,X 400,Z 300,A 10,B 20,C 30,S 2,T 2}\n"
      "  PTP {S 6,T 27,X 500.5,Y -20,Z 250,A -10,B 15,C 170} ; S and T first\n"
      "  LIN {C 30,B 20,A 10,Z 300,Y 100,X 400}\n"
      "END\n";
  const std::string want =
      "DEF odd( )\n"
      "  LIN {Y 102.0000,X 401.0000,Z 303.0000,A 10,B 20,C 30,S 2,T 2}\n"
      "  PTP {S 6,T 27,X 501.5000,Y -18.0000,Z 253.0000,A -10,B 15,C 170} ; S and T first\n"
      "  LIN {C 30,B 20,A 10,Z 303.0000,Y 102.0000,X 401.0000}\n"
      "END\n";
  const ProgramFilterResult r =
      filter_program(text, ProgramLanguage::Krl, "odd.src", {}, shift_123);
  EXPECT_EQ(r.text, want);
  EXPECT_EQ(r.cartesian_points, 3);
  const auto points = read_program_points(r.text, ProgramLanguage::Krl, "odd.src");
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[1].base_T_tcp.p, Eigen::Vector3d(501.5, -18, 253));
  EXPECT_EQ(points[1].config, (std::vector<int>{6, 27}));
}

TEST(ProgramParser, NumbersMustBeReadWhole) {
  EXPECT_EQ(error_of("DEF p( )\n  LIN {X 1e999,Y 0,Z 0,A 0,B 0,C 0}\nEND\n", ProgramLanguage::Krl),
            "bad.src:2:10: number '1e999' is out of range");
  EXPECT_EQ(error_of("CONST robtarget p:=[[364.35.4,0,594],[1,0,0,0],[0,0,0,0],"
                     "[9E9,9E9,9E9,9E9,9E9,9E9]];\n",
                     ProgramLanguage::Rapid, "bad.mod"),
            "bad.mod:1:22: malformed number '364.35.4'");
  EXPECT_EQ(error_of("CONST robtarget p:=[[1,2,3e],[1,0,0,0],[0,0,0,0],"
                     "[9E9,9E9,9E9,9E9,9E9,9E9]];\n",
                     ProgramLanguage::Rapid, "bad.mod"),
            "bad.mod:1:26: malformed number '3e'");
  // Valid spellings still read: exponent with sign, leading point, trailing point.
  const auto points = read_program_points(
      "CONST robtarget p:=[[1E+2,.5,3.],[1,0,0,0],[0,0,0,0],[9E+09,9E9,9E9,9E9,9E9,9E9]];\n",
      ProgramLanguage::Rapid, "ok.mod");
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0].base_T_tcp.p, Eigen::Vector3d(100, 0.5, 3));
}

TEST(ProgramParser, DuplicateComponentsAndTooManyDimensionsAreRefused) {
  EXPECT_EQ(error_of("DECL E6POS P={X 1,Y 2,Z 3,X 4,A 0,B 0,C 0}\n", ProgramLanguage::Krl),
            "bad.src:1:27: component X given twice");
  EXPECT_EQ(error_of("CONST robtarget p{1,1,1,1}:=[[[[[[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,"
                     "9E9,9E9,9E9]]]]]];\n",
                     ProgramLanguage::Rapid, "bad.mod"),
            "bad.mod:1:17: array 'p' has 4 dimensions; RAPID allows at most 3");
}

/// Runs `work` on a thread with a 256 KiB stack: parsing that recursed on nesting depth
/// would overflow it long before 300,000 levels.
void on_small_stack(void (*work)(void*), void* arg) {
  struct Job {
    void (*work)(void*);
    void* arg;
  } job{work, arg};
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, 256 * 1024);
  pthread_t thread;
  ASSERT_EQ(pthread_create(
                &thread, &attr,
                [](void* j) -> void* {
                  auto* job = static_cast<Job*>(j);
                  job->work(job->arg);
                  return nullptr;
                },
                &job),
            0);
  pthread_join(thread, nullptr);
  pthread_attr_destroy(&attr);
}

TEST(ProgramParser, DeepNestingNeitherRecursesNorCrashes) {
  struct Result {
    std::string unclosed, closed, krl;
    size_t closed_points = 99;
  } result;
  on_small_stack(
      [](void* r) {
        auto& out = *static_cast<Result*>(r);
        const int depth = 300000;
        const std::string open(depth, '[');
        out.unclosed = error_of("MODULE m\n  x := " + open + "\nENDMODULE\n",
                                ProgramLanguage::Rapid, "deep.mod");
        // Closed again: a valid aggregate that is no point.
        out.closed_points = read_program_points("MODULE m\n  x := " + open + "1" +
                                                    std::string(depth, ']') + ";\nENDMODULE\n",
                                                ProgramLanguage::Rapid, "deep.mod")
                                .size();
        out.krl =
            error_of("DECL E6POS P={X " + std::string(depth, '{') + "\n", ProgramLanguage::Krl);
      },
      &result);
  EXPECT_EQ(result.unclosed, "deep.mod:3:1: aggregate never closed");
  EXPECT_EQ(result.closed_points, 0u);
  EXPECT_EQ(result.krl, "bad.src:1:17: aggregate never closed");
}

TEST(ProgramParser, NonFiniteCorrectionIsRefused) {
  const std::string text =
      "CONST robtarget p:=[[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n";
  try {
    filter_program(text, ProgramLanguage::Rapid, "n.mod", {}, [](const ProgramPoint& p) {
      CorrectedPoint c;
      c.base_T_tcp = p.base_T_tcp;
      c.base_T_tcp.p.x() = std::nan("");
      return c;
    });
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "n.mod:1:20 (p): the corrected point is not finite (NaN or infinite)");
  }
}

TEST(ProgramParser, OutputMayNotBeTheInput) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("robcal_program_parser_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "sub");
  const std::string in = (dir / "prog.mod").string();
  const std::string text =
      "MODULE m\n  CONST robtarget p:=[[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];"
      "\nENDMODULE\n";
  write_file_atomically(in, text);
  std::filesystem::create_symlink(in, dir / "link.mod");
  for (const std::string& out :
       {in, (dir / "sub" / ".." / "prog.mod").string(), (dir / "link.mod").string()}) {
    try {
      filter_program_file(in, out, {}, shift_123);
      ADD_FAILURE() << out << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("the output is the input program"), std::string::npos)
          << e.what();
    }
    EXPECT_EQ(read_text_file(in), text);
  }
  const std::string out = (dir / "out.mod").string();
  EXPECT_EQ(filter_program_file(in, out, {}, shift_123).cartesian_points, 1);
  EXPECT_NE(read_text_file(out).find("[[2.0000,4.0000,6.0000]"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace robcal
