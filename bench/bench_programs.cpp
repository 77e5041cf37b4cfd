// Robot programs (issue 17): filtering a 100,000-target program in each language (RAPID, KRL,
// Fanuc LS, Yaskawa JBI, URScript), with a fixed shift as the corrector (the parsing,
// rewriting and re-parsing cost alone) and with the calibrated-IK corrector of a 31-parameter IRB
// 120 model (every target solved, tool and work object applied), and on the cobots (UR10e,
// CRX-10iA); writing the measurement program of
// 10,000 configurations in each language. Goal: < 1 s per 100,000 targets.

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <map>

#include "../tests/test_compensate_support.hpp"
#include "robcal/compensate/corrected_targets.hpp"
#include "robcal/kinematics/orientation.hpp"
#include "robcal/programs/measurement_program.hpp"
#include "robcal/programs/program_filter.hpp"

namespace robcal {
namespace {

constexpr uint64_t kSeed = 2026;
constexpr int kTargets = 100000;

/// A program of `targets` reachable Cartesian targets of the calibrated IRB 120 (nominal
/// poses of random joints ≥ 5° from singularities, configuration data written), each used in
/// one motion, seed kSeed: the flange pose with tool0 (RAPID), tool 0 (KRL), UT 0 (Fanuc), TOOL 0
/// (Yaskawa, given as the flange); the TCP pose without set_tcp (URScript: the installation's TCP,
/// the compensator's tool). With `path_step_deg` > 0 the targets follow a path instead: each
/// joint moves by at most that from the previous target.
std::string big_program(ProgramLanguage language, const Compensator& comp, int targets,
                        double path_step_deg = 0) {
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> step(-deg2rad(path_step_deg), deg2rad(path_step_deg));
  std::string decl, moves;
  int n = 0;
  Vector6d q = test::random_joints(comp.model, rng);
  while (n < targets) {
    if (path_step_deg > 0 && n > 0) {
      Vector6d next = q;
      for (int i = 0; i < kJointCount; ++i) next[i] += step(rng);
      if (!comp.model.within_limits(next)) continue;
      q = next;
    } else {
      q = test::random_joints(comp.model, rng);
    }
    if (test::near_singular(comp.model, q)) continue;
    const Pose<double> tcp = nominal_tcp_pose(comp, q);
    const Pose<double> pose = tcp * comp.tcp_T_flange;
    const std::vector<int> cf = maker_configuration(comp, language, q);
    const Eigen::Vector3d abc = euler_angles_deg(pose.R, EulerConvention::ZyxABC);
    switch (language) {
      case ProgramLanguage::Rapid: {
        const Eigen::Quaterniond r(pose.R);
        decl += fmt::format(
            "  CONST robtarget p{}:=[[{:.4f},{:.4f},{:.4f}],[{:.9f},{:.9f},{:.9f},{:.9f}],"
            "[{},{},{},{}],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];  ! target {}\n",
            n, pose.p.x(), pose.p.y(), pose.p.z(), r.w(), r.x(), r.y(), r.z(), cf[0], cf[1], cf[2],
            cf[3], n);
        moves += fmt::format("    MoveL p{}, v100, z10, tool0;\n", n);
        break;
      }
      case ProgramLanguage::Krl:
        moves += fmt::format(
            "  LIN {{X {:.4f},Y {:.4f},Z {:.4f},A {:.5f},B {:.5f},C {:.5f},S {},T {}}} ; {}\n",
            pose.p.x(), pose.p.y(), pose.p.z(), abc[0], abc[1], abc[2], cf[0], cf[1], n);
        break;
      case ProgramLanguage::Jbi:
        // RCONF before each position (it holds for the positions after it).
        decl += fmt::format(
            "///RCONF {},{},{},{},{},{},0,0\nC{:05d}={:.3f},{:.3f},{:.3f},{:.4f},"
            "{:.4f},{:.4f}\n",
            cf[0], cf[1], cf[2], cf[3], cf[4], cf[5], n, pose.p.x(), pose.p.y(), pose.p.z(), abc[2],
            abc[1], abc[0]);
        moves += fmt::format("MOVL C{:05d} V=100.0\n", n);
        break;
      case ProgramLanguage::FanucLs:
        moves += fmt::format("{:>6}:L P[{}] 100mm/sec FINE ;\n", n + 1, n + 1);
        decl += fmt::format(
            "P[{}]{{\n   GP1:\n\tUF : 0, UT : 0,\t\tCONFIG : '{} {} {}, {}, {}, {}',\n"
            "\tX = {:.3f} mm,\tY = {:.3f} mm,\tZ = {:.3f} mm,\n"
            "\tW = {:.3f} deg,\tP = {:.3f} deg,\tR = {:.3f} deg\n}};\n",
            n + 1, cf[0] ? 'F' : 'N', cf[1] ? 'D' : 'U', cf[2] ? 'B' : 'T', cf[3], cf[4], cf[5],
            pose.p.x(), pose.p.y(), pose.p.z(), abc[2], abc[1], abc[0]);
        break;
      default: {
        const Eigen::AngleAxisd r(tcp.R);
        const Eigen::Vector3d v = r.angle() * r.axis();
        moves += fmt::format(
            "  movel(p[{:.7f}, {:.7f}, {:.7f}, {:.8f}, {:.8f}, {:.8f}], a=1.2, v=0.25)\n",
            tcp.p.x() / 1000, tcp.p.y() / 1000, tcp.p.z() / 1000, v.x(), v.y(), v.z());
      }
    }
    ++n;
  }
  switch (language) {
    case ProgramLanguage::Rapid:
      return "MODULE Big\n" + decl + "  PROC main()\n" + moves + "  ENDPROC\nENDMODULE\n";
    case ProgramLanguage::Krl:
      return "DEF big( )\n  BAS(#TOOL,0)\n" + moves + "END\n";
    case ProgramLanguage::FanucLs:
      return "/PROG  BIG\n/ATTR\n/MN\n" + moves + "/POS\n" + decl + "/END\n";
    case ProgramLanguage::Jbi:
      // C00000..C99999: 100,000 positions is the format's own limit.
      return fmt::format(
                 "/JOB\n//NAME BIG\n//POS\n///NPOS {},0,0,0,0,0\n///TOOL 0\n"
                 "///POSTYPE ROBOT\n///RECTAN\n",
                 targets) +
             decl + "//INST\n///DATE 2026/01/01 00:00\n///ATTR SC,RW\n///GROUP1 RB1\nNOP\n" +
             moves + "END\n";
    default:
      return "def big():\n" + moves + "end\n";
  }
}

constexpr ProgramLanguage kFiltered[] = {ProgramLanguage::Rapid, ProgramLanguage::Krl,
                                         ProgramLanguage::FanucLs, ProgramLanguage::Jbi,
                                         ProgramLanguage::UrScript};

struct Fixture {
  CalibratedRobot robot;
  Compensator comp;
  std::map<ProgramLanguage, std::string> programs;
  Fixture()
      : robot([] {
          std::mt19937_64 rng(kSeed);
          return test::random_calibrated("abb-irb120", rng);
        }()),
        comp(make_compensator(robot)) {
    for (ProgramLanguage l : kFiltered) programs[l] = big_program(l, comp, kTargets);
  }
};
const Fixture& fixture() {
  static const Fixture f;
  return f;
}

void BM_FilterProgram100k(benchmark::State& state) {
  const auto language = static_cast<ProgramLanguage>(state.range(0));
  const bool calibrated = state.range(1) != 0;
  const Fixture& f = fixture();
  const std::string& text = f.programs.at(language);
  for (auto _ : state) {
    const PointCorrector shift = [](const ProgramPoint& p) {
      CorrectedPoint c{p.base_T_tcp, p.config, p.joints_deg, ""};
      c.base_T_tcp.p.x() += 0.25;
      return c;
    };
    // Targets whose calibrated solution leaves the joint limits stay as written (listed).
    ProgramFilterOptions options;
    options.keep_going = true;
    options.tools["TOOL[0]"] = Pose<double>{};  // Yaskawa tool 0 = the flange here
    const auto result =
        filter_program(text, language, "big", options,
                       calibrated ? make_program_corrector(f.comp, language) : shift);
    if (result.cartesian_points + static_cast<int>(result.uncorrected.size()) != kTargets)
      state.SkipWithError("targets lost");
    state.counters["uncorrected"] = static_cast<double>(result.uncorrected.size());
    benchmark::DoNotOptimize(result.text.data());
  }
  state.SetLabel(fmt::format("{} {}", program_language_name(language),
                             calibrated ? "calibrated IK" : "fixed shift"));
  state.counters["bytes"] = static_cast<double>(text.size());
}
BENCHMARK(BM_FilterProgram100k)
    ->ArgsProduct(
        {{static_cast<int>(ProgramLanguage::Rapid), static_cast<int>(ProgramLanguage::Krl),
          static_cast<int>(ProgramLanguage::FanucLs), static_cast<int>(ProgramLanguage::Jbi),
          static_cast<int>(ProgramLanguage::UrScript)},
         {0, 1}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

/// The cobots, where the nominal solves cost most: URScript on a UR10e (three parallel axes,
/// offset wrist: no configuration data, every solution solved for the nearest) and Fanuc LS
/// on a CRX-10iA (general 6R: the written branch solved alone), calibrated IK per target;
/// the CRX also with its targets on a path (1° steps: the calibrated inverse continues from the
/// previous target's joints).
struct CobotFixture {
  CalibratedRobot robot;
  Compensator comp;
  std::string program;
  CobotFixture(const char* name, ProgramLanguage language, double path_step_deg = 0)
      : robot([name] {
          std::mt19937_64 rng(kSeed);
          return test::random_calibrated(name, rng);
        }()),
        comp(make_compensator(robot)),
        program(big_program(language, comp, kTargets, path_step_deg)) {}
};

void BM_FilterCobotProgram100k(benchmark::State& state) {
  const bool crx = state.range(0) != 0, path = state.range(0) == 2;
  const ProgramLanguage language = crx ? ProgramLanguage::FanucLs : ProgramLanguage::UrScript;
  static const CobotFixture ur("universal-robots-ur10e", ProgramLanguage::UrScript);
  static const CobotFixture fanuc("fanuc-crx10ia", ProgramLanguage::FanucLs);
  static const CobotFixture fanuc_path("fanuc-crx10ia", ProgramLanguage::FanucLs, 1.0);
  const CobotFixture& f = path ? fanuc_path : crx ? fanuc : ur;
  for (auto _ : state) {
    ProgramFilterOptions options;
    options.keep_going = true;
    const auto result = filter_program(f.program, language, "big", options,
                                       make_program_corrector(f.comp, language));
    if (result.cartesian_points + static_cast<int>(result.uncorrected.size()) != kTargets)
      state.SkipWithError("targets lost");
    state.counters["uncorrected"] = static_cast<double>(result.uncorrected.size());
    benchmark::DoNotOptimize(result.text.data());
  }
  state.SetLabel(path  ? "ls fanuc-crx10ia calibrated IK, path"
                 : crx ? "ls fanuc-crx10ia calibrated IK"
                       : "urscript ur10e calibrated IK");
}
BENCHMARK(BM_FilterCobotProgram100k)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

/// The KRL program's targets as a module (issue 17 item 3): each inline point of big_program
/// declared in the .dat as XP<n> and used by `LIN XP<n>` in the .src, under BAS(#TOOL,0).
std::pair<std::string, std::string> big_krl_module(const std::string& krl) {
  std::string src = "DEF big( )\n  BAS(#TOOL,0)\n", dat = "DEFDAT big\n";
  int n = 0;
  for (size_t at = krl.find("  LIN {"); at != std::string::npos; at = krl.find("  LIN {", at)) {
    const size_t close = krl.find('}', at);
    dat += fmt::format("DECL E6POS XP{}={}\n", n, krl.substr(at + 6, close - at - 5));
    src += fmt::format("  LIN XP{}\n", n++);
    at = close;
  }
  return {src + "END\n", dat + "ENDDAT\n"};
}

void BM_FilterKrlModule100k(benchmark::State& state) {
  const bool calibrated = state.range(0) != 0;
  const Fixture& f = fixture();
  static const auto module = big_krl_module(f.programs.at(ProgramLanguage::Krl));
  for (auto _ : state) {
    ProgramFilterOptions options;
    options.keep_going = true;
    const PointCorrector shift = [](const ProgramPoint& p) {
      CorrectedPoint c{p.base_T_tcp, p.config, p.joints_deg, ""};
      c.base_T_tcp.p.x() += 0.25;
      return c;
    };
    const auto result = filter_krl_module(
        module.first, module.second, "big.src", "big.dat", options,
        calibrated ? make_program_corrector(f.comp, ProgramLanguage::Krl) : shift);
    if (result.cartesian_points + static_cast<int>(result.uncorrected.size()) != kTargets)
      state.SkipWithError("targets lost");
    benchmark::DoNotOptimize(result.dat_text->data());
  }
  state.SetLabel(calibrated ? "krl module calibrated IK" : "krl module fixed shift");
}
BENCHMARK(BM_FilterKrlModule100k)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);

void BM_MeasurementProgram10k(benchmark::State& state) {
  MeasurementProgramRequest r;
  r.language = static_cast<ProgramLanguage>(state.range(0));
  r.pulses_per_degree = std::array<double, kJointCount>{1000, 1000, 1000, 800, 800, 500};
  std::mt19937_64 rng(kSeed);
  const RobotModel model = load_robot("abb-irb120");
  for (int i = 0; i < 10000; ++i) {
    r.names.push_back(fmt::format("c{}", i));
    r.joints.push_back(test::random_joints(model, rng));
  }
  r.max_configs_per_file = 200;
  r.hook = MeasurementHook::PulseOutput;
  for (auto _ : state) benchmark::DoNotOptimize(write_measurement_program(r).size());
  state.SetLabel(program_language_name(r.language));
}
BENCHMARK(BM_MeasurementProgram10k)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace robcal
