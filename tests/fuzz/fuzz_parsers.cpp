/// A deterministic mutation fuzzer over every input parser (issue 21): each seed file of
/// tests/fuzz/corpus/<parser>/ is mutated (bytes flipped, inserted, deleted, chunks repeated,
/// hostile tokens such as 1e999, NaN, deep nesting, a BOM spliced in) and handed to the parser.
/// A parser may accept the text or refuse it with an InputError; anything else (another
/// exception, a crash, a sanitizer report) is a bug, and the input is written as a reproducer.
/// The inputs of tests/fuzz/crashes/<parser>/ (bugs found before) are replayed first.
///
///   robcal_fuzz [--iterations N] [--seconds S] [--seed K] [--parser NAME] [--out DIR] ROOT
///
/// ROOT is tests/fuzz. With --seconds the run goes on until that much time has passed per
/// parser (the long runs); else N mutations per parser (the smoke run of `make test`).

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "robcal/campaign/cell.hpp"
#include "robcal/campaign/frames_file.hpp"
#include "robcal/campaign/frames_world.hpp"
#include "robcal/campaign/instrument_import.hpp"
#include "robcal/campaign/point_session.hpp"
#include "robcal/core/error.hpp"
#include "robcal/hexapod/plan_file.hpp"
#include "robcal/hexapod/session.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/identify/cross_validation.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/opw_file.hpp"
#include "robcal/io/pose_list_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/ur_calibration_file.hpp"
#include "robcal/io/urdf_file.hpp"
#include "robcal/programs/frames_file.hpp"
#include "robcal/programs/measurement_program.hpp"
#include "robcal/programs/program_filter.hpp"
#include "robcal/sim/simulator.hpp"
#include "robcal/sim/true_robot.hpp"
#include "robcal/validate/axis_test.hpp"

namespace fs = std::filesystem;
using namespace robcal;

namespace {

std::string read_all(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void write_all(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

/// One parser: takes the text (and a scratch file holding it, for the readers that take a
/// path); returns normally or throws InputError.
using Target = std::function<void(const std::string& text, const fs::path& file)>;

std::map<std::string, Target> targets(const fs::path& root) {
  const Tool tool = load_tool((root / "corpus" / "tool" / "tool.yaml").string());
  const fs::path plan_file = root / "corpus" / "plan" / "plan.json";
  const auto correct = [](const ProgramPoint& p) {
    CorrectedPoint c;
    c.base_T_tcp = p.base_T_tcp;
    c.base_T_tcp.p.x() += 0.5;  // a real edit, so the rewriting runs
    c.joints_deg = p.joints_deg;
    return c;
  };
  // The tools and frames the seeds use but do not define (as a frames file gives them).
  ProgramFilterOptions options;
  options.joints = true;
  options.tools["TOOL_DATA[1]"] = Pose<double>{};
  options.tools["UT[2]"] = Pose<double>{};
  options.frames["UF[1]"] = Pose<double>{};
  options.tools["TOOL[1]"] = Pose<double>{};
  options.tools["TOOL[2]"] = Pose<double>{};
  options.frames["USER[1]"] = Pose<double>{};
  options.frames["BASE_DATA[1]"] = Pose<double>{};
  options.frames["BASE_DATA[2]"] = Pose<double>{};
  options.pulses_per_degree = {1341.2, 1341.2, 1341.2, 1092.3, 1092.3, 614.4};
  const auto program = [correct, options](ProgramLanguage language) {
    return [correct, options, language](const std::string& text, const fs::path& file) {
      (void)read_program_points(text, language, file.string(), options);
      (void)filter_program(text, language, file.string(), options, correct);
    };
  };
  // A KUKA module seed is the .src, this line, then the .dat (a mutant that loses the line
  // is all .src, with an empty .dat).
  const auto krl_module = [correct, options](const std::string& text, const fs::path& file) {
    static const std::string kSeparator = "\n&&& robcal_fuzz: the .dat follows &&&\n";
    const size_t at = text.find(kSeparator);
    const std::string src = text.substr(0, at);
    const std::string dat = at == std::string::npos ? "" : text.substr(at + kSeparator.size());
    const std::string src_file = file.string() + ".src", dat_file = file.string() + ".dat";
    (void)read_krl_module_points(src, dat, src_file, dat_file, options);
    (void)filter_krl_module(src, dat, src_file, dat_file, options, correct);
  };
  // The point session of corpus/candidates/configs.csv, a reference every 3 configurations.
  campaign::SessionSettings session;
  session.configs =
      read_configurations_csv((root / "corpus" / "candidates" / "configs.csv").string(), tool);
  session.tool = tool;
  session.reference = 0;
  session.every = 3;
  const std::vector<campaign::SessionStep> steps = campaign::session_steps(session);
  const auto joint_moves = [](ProgramLanguage language) {
    return [language](const std::string& text, const fs::path& f) {
      (void)read_joint_moves(
          text, language, f.string(),
          std::array<double, kJointCount>{1341.2, 1341.2, 1341.2, 1092.3, 1092.3, 614.4});
    };
  };
  return {
      {"ur_calibration", [](const std::string& text,
                            const fs::path& f) { (void)parse_ur_calibration(text, f.string()); }},
      {"krl_module", krl_module},
      {"session_journal",
       [session, steps](const std::string& text, const fs::path& f) {
         (void)campaign::session_result(session, steps,
                                        campaign::replay_journal(text, f.string(), steps));
       }},
      {"joint_moves_ls", joint_moves(ProgramLanguage::FanucLs)},
      {"joint_moves_jbi", joint_moves(ProgramLanguage::Jbi)},
      {"joint_moves_urscript", joint_moves(ProgramLanguage::UrScript)},
      {"robot", [](const std::string&, const fs::path& f) { (void)load_robot(f.string()); }},
      {"tool", [](const std::string&, const fs::path& f) { (void)load_tool(f.string()); }},
      {"model",
       [](const std::string&, const fs::path& f) { (void)load_calibrated_robot(f.string()); }},
      {"measurements",
       [tool](const std::string& text, const fs::path& f) {
         (void)parse_measurements_csv(text, f.string(), tool);
       }},
      {"poses",
       [](const std::string& text, const fs::path& f) { (void)parse_pose_list(text, f.string()); }},
      {"rapid", program(ProgramLanguage::Rapid)},
      {"krl", program(ProgramLanguage::Krl)},
      {"ls", program(ProgramLanguage::FanucLs)},
      {"urscript", program(ProgramLanguage::UrScript)},
      {"jbi", program(ProgramLanguage::Jbi)},
      {"plan", [](const std::string&, const fs::path& f) { (void)hexapod::load_session_plan(f); }},
      {"journal",
       [plan_file](const std::string&, const fs::path& f) {
         hexapod::Session session(hexapod::load_session_plan(plan_file));
         (void)hexapod::SessionJournal::replay_read_only(f, session);
       }},
      {"urdf",
       [](const std::string& text, const fs::path& f) { (void)robot_from_urdf(text, f.string()); }},
      {"opw", [](const std::string&, const fs::path& f) { (void)load_opw_robot(f.string()); }},
      {"cell", [](const std::string& text,
                  const fs::path& f) { (void)campaign::parse_cell(text, f.string()); }},
      {"frames", [](const std::string&, const fs::path& f) { (void)read_frames_file(f.string()); }},
      {"nests",
       [](const std::string& text, const fs::path& f) {
         (void)campaign::read_named_points({f.string(), text});
       }},
      {"candidates",
       [tool](const std::string&, const fs::path& f) {
         (void)read_configurations_csv(f.string(), tool);
       }},
      {"truth", [](const std::string&, const fs::path& f) { (void)load_truth(f.string()); }},
      {"world_frame",
       [](const std::string& text, const fs::path& f) {
         (void)campaign::parse_world_frame(text, f.string());
       }},
      {"axis_test", [](const std::string& text,
                       const fs::path& f) { (void)parse_axis_test_samples(text, f.string()); }},
      {"folds", [](const std::string&, const fs::path& f) { (void)read_folds_csv(f.string()); }},
      {"export_format",
       [](const std::string& text, const fs::path& f) {
         (void)campaign::parse_export_format(text, f.string());
       }},
      {"export",
       [](const std::string& text, const fs::path& f) {
         (void)campaign::read_export_points({f.string(), text}, {});
       }},
      {"hexapod_plan",
       [](const std::string&, const fs::path& f) { (void)hexapod::read_hexapod_plan(f); }},
  };
}

/// Tokens that broke parsers before or that parsers must refuse: numbers beyond range or
/// half-written, non-numbers, structure characters, a BOM, a NUL, long digit runs.
const std::vector<std::string>& hostile_tokens() {
  static const std::vector<std::string> kTokens{"1e999",
                                                "-1e999",
                                                "1e-999",
                                                "nan",
                                                "NaN",
                                                "inf",
                                                "-inf",
                                                ".inf",
                                                "364.35.4",
                                                "0x1F",
                                                "1e308",
                                                "99999999999999999999",
                                                "-1",
                                                "-0",
                                                "+",
                                                "e",
                                                "[",
                                                "]",
                                                "{",
                                                "}",
                                                ",",
                                                ":",
                                                "\n",
                                                "\r\n",
                                                "\"",
                                                "'",
                                                "~",
                                                "&a ",
                                                "*a",
                                                "- ",
                                                "# ",
                                                "\xEF\xBB\xBF",
                                                std::string(1, '\0'),
                                                "\t",
                                                "name",
                                                "B9-T9",
                                                "END",
                                                "ENDMODULE",
                                                ";",
                                                "=",
                                                "\\WObj:=wobj1",
                                                "{X 1e999}",
                                                "E6POS",
                                                "robtarget",
                                                "18446744073709551616",
                                                "2147483648"};
  return kTokens;
}

std::string mutate(std::string text, std::mt19937_64& rng) {
  const auto pick = [&](size_t n) {
    return n == 0 ? 0 : std::uniform_int_distribution<size_t>(0, n - 1)(rng);
  };
  const int edits = 1 + static_cast<int>(pick(4));
  for (int e = 0; e < edits; ++e) {
    const size_t at = pick(text.size() + 1);
    switch (pick(8)) {
      case 0:  // flip a byte
        if (!text.empty()) text[std::min(at, text.size() - 1)] = static_cast<char>(pick(256));
        break;
      case 1:  // insert a byte
        text.insert(at, 1, static_cast<char>(pick(256)));
        break;
      case 2:  // delete a range
        text.erase(at, pick(16) + 1);
        break;
      case 3: {  // repeat a chunk elsewhere
        const std::string chunk = text.substr(pick(text.size() + 1), pick(64) + 1);
        text.insert(pick(text.size() + 1), chunk);
        break;
      }
      case 4:
      case 5:  // a hostile token
        text.insert(at, hostile_tokens()[pick(hostile_tokens().size())]);
        break;
      case 6: {  // replace a number by a hostile token
        const size_t digit = text.find_first_of("0123456789", at);
        if (digit == std::string::npos) break;
        const size_t end = text.find_first_not_of("0123456789.eE+-", digit);
        text.replace(digit, (end == std::string::npos ? text.size() : end) - digit,
                     hostile_tokens()[pick(hostile_tokens().size())]);
        break;
      }
      default: {  // deep nesting or truncation
        if (pick(2) == 0)
          text.insert(at, std::string(pick(2) ? 5000 : 300, "[{("[pick(3)]));
        else
          text.resize(at);
      }
    }
  }
  return text;
}

struct Options {
  long iterations = 300;
  double seconds = 0;
  uint64_t seed = 1;
  std::string parser;
  fs::path out;
  fs::path root;
  double input_seconds = 60;  ///< longer on one input is a hang (the slowest take ~0.3 s)
};

/// Ends the run when one input takes longer than the limit: a parser that loops for ever would
/// otherwise stall the fuzz run without a word. The input (in the scratch file) is saved first.
class Watchdog {
 public:
  explicit Watchdog(double limit_seconds) : limit_(limit_seconds) {
    if (limit_ > 0) thread_ = std::thread([this] { watch(); });
  }
  ~Watchdog() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
  }
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

  void begin(const std::string& parser, const fs::path& scratch, const fs::path& save_dir) {
    const std::lock_guard<std::mutex> lock(mutex_);
    parser_ = parser;
    scratch_ = scratch;
    save_dir_ = save_dir;
    started_ = std::chrono::steady_clock::now();
    running_ = true;
  }
  void end() {
    const std::lock_guard<std::mutex> lock(mutex_);
    running_ = false;
  }

 private:
  void watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      wake_.wait_for(lock, std::chrono::milliseconds(500));
      if (!running_ ||
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count() <
              limit_)
        continue;
      fs::create_directories(save_dir_);
      const fs::path saved = save_dir_ / "found-hang";
      fs::copy_file(scratch_, saved, fs::copy_options::overwrite_existing);
      std::cerr << "FAIL " << parser_ << ": one input has run for more than " << limit_
                << " s (a hang?)\n  input saved as " << saved << "\n";
      std::_Exit(1);
    }
  }

  double limit_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false, running_ = false;
  std::string parser_;
  fs::path scratch_, save_dir_;
  std::chrono::steady_clock::time_point started_;
  std::thread thread_;  // last: started once the members it uses exist
};

/// Runs one input; returns false (and saves the input) when the parser failed other than by
/// an InputError. Counts the inputs accepted (a corpus whose mutants are all refused at the
/// first byte would test little).
bool run_one(const Target& target, const std::string& text, const fs::path& scratch,
             const std::string& parser, const Options& o, Watchdog& watchdog, long& accepted) {
  write_all(scratch, text);
  const fs::path dir = (o.out.empty() ? o.root / "crashes" : o.out) / parser;
  watchdog.begin(parser, scratch, dir);
  try {
    target(text, scratch);
    watchdog.end();
    ++accepted;
    return true;
  } catch (const InputError&) {
    watchdog.end();
    return true;
  } catch (const std::exception& e) {
    std::cerr << "FAIL " << parser << ": " << typeid(e).name() << ": " << e.what() << "\n";
  } catch (...) {
    std::cerr << "FAIL " << parser << ": unknown exception\n";
  }
  watchdog.end();
  fs::create_directories(dir);
  const fs::path saved = dir / ("found-" + std::to_string(std::hash<std::string>{}(text)));
  write_all(saved, text);
  std::cerr << "  input saved as " << saved << "\n";
  return false;
}

constexpr const char* kUsage =
    "usage: robcal_fuzz [--iterations N] [--seconds S] [--seed K] [--parser NAME] [--out DIR] "
    "ROOT\n"
    "  ROOT         tests/fuzz: its corpus/<parser>/ seeds are mutated, its crashes/<parser>/\n"
    "               inputs replayed\n"
    "  --iterations mutations per parser (default 300; the smoke run of `make test`)\n"
    "  --seconds    run this long per parser instead (the long runs)\n"
    "  --seed       seed of the mutations (default 1)\n"
    "  --parser     only this parser (a folder name of corpus/)\n"
    "  --out        folder for the reproducers of failing inputs (default ROOT/crashes)\n"
    "  --input-seconds  one input running longer is a failure, a hang (default 60; 0: no limit)\n";

/// A command line the runner cannot use: the message, then the usage, exit code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// `text` as a whole number >= 0 (or a number >= 0 when `fraction`), for `flag`.
double non_negative(const std::string& flag, const std::string& text, bool fraction) {
  size_t used = 0;
  double v = -1;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !(v >= 0 && v <= 1e15) || (!fraction && v != std::floor(v)))
    throw UsageError(flag + ": expected " + (fraction ? "a number" : "a whole number") +
                     " >= 0, found '" + text + "'");
  return v;
}

/// The options of the command line; nullopt for --help.
std::optional<Options> parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") return std::nullopt;
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw UsageError(arg + ": expected a value");
      return argv[++i];
    };
    if (arg == "--iterations")
      o.iterations = static_cast<long>(non_negative(arg, value(), false));
    else if (arg == "--seconds")
      o.seconds = non_negative(arg, value(), true);
    else if (arg == "--seed")
      o.seed = static_cast<uint64_t>(non_negative(arg, value(), false));
    else if (arg == "--parser")
      o.parser = value();
    else if (arg == "--out")
      o.out = value();
    else if (arg == "--input-seconds")
      o.input_seconds = non_negative(arg, value(), true);
    else if (arg.rfind('-', 0) == 0)
      throw UsageError(arg + ": unknown option");
    else if (!o.root.empty())
      throw UsageError("'" + arg + "': one ROOT only (already '" + o.root.string() + "')");
    else
      o.root = arg;
  }
  if (o.root.empty()) throw UsageError("expected ROOT, the tests/fuzz folder");
  std::error_code ec;
  if (!fs::is_directory(o.root / "corpus", ec))
    throw UsageError("'" + o.root.string() +
                     "' has no corpus/ folder: expected ROOT to be tests/fuzz");
  return o;
}

/// Fuzzes every parser (or --parser's); returns the number of failing inputs.
int run(const Options& o) {
  const std::map<std::string, Target> all = targets(o.root);
  if (!o.parser.empty() && all.count(o.parser) == 0) {
    std::string known;
    for (const auto& entry : all) known += (known.empty() ? "" : ", ") + entry.first;
    throw UsageError("--parser: unknown parser '" + o.parser + "': expected one of " + known);
  }
  const fs::path scratch_dir =
      fs::temp_directory_path() / ("robcal-fuzz-" + std::to_string(::getpid()));
  fs::create_directories(scratch_dir);
  // A crash ends the process before the input can be saved: it is left here.
  std::cerr << "inputs are written to " << scratch_dir << " before each run\n";
  int failures = 0;
  Watchdog watchdog(o.input_seconds);
  for (const auto& [parser, target] : all) {
    if (!o.parser.empty() && o.parser != parser) continue;
    const fs::path scratch = scratch_dir / ("input-" + parser);
    std::vector<std::string> seeds;
    for (const auto& entry : fs::directory_iterator(o.root / "corpus" / parser))
      seeds.push_back(read_all(entry.path()));
    std::sort(seeds.begin(), seeds.end());  // directory order is not deterministic
    if (seeds.empty())
      throw UsageError("'" + (o.root / "corpus" / parser).string() + "' holds no seed file");
    long runs = 0, accepted = 0, seeds_accepted = 0;
    for (const std::string& seed : seeds)
      failures += !run_one(target, seed, scratch, parser, o, watchdog, seeds_accepted);
    if (seeds_accepted != static_cast<long>(seeds.size())) {
      std::cerr << "FAIL " << parser << ": a seed of the corpus is refused\n";
      ++failures;
    }
    if (fs::is_directory(o.root / "crashes" / parser))
      for (const auto& entry : fs::directory_iterator(o.root / "crashes" / parser))
        failures +=
            !run_one(target, read_all(entry.path()), scratch, parser, o, watchdog, accepted);
    std::mt19937_64 rng(o.seed ^ std::hash<std::string>{}(parser));
    const auto start = std::chrono::steady_clock::now();
    const auto elapsed = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    while (o.seconds > 0 ? elapsed() < o.seconds : runs < o.iterations) {
      const std::string& seed =
          seeds[std::uniform_int_distribution<size_t>(0, seeds.size() - 1)(rng)];
      failures += !run_one(target, mutate(seed, rng), scratch, parser, o, watchdog, accepted);
      ++runs;
    }
    std::printf("%-13s %7ld inputs in %6.2f s (%.0f/s), %ld accepted, %zu seeds\n", parser.c_str(),
                runs, elapsed(), runs / std::max(elapsed(), 1e-9), accepted, seeds.size());
  }
  fs::remove_all(scratch_dir);
  return failures;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::optional<Options> o = parse_options(argc, argv);
    if (!o) {
      std::cout << kUsage;
      return 0;
    }
    const int failures = run(*o);
    if (failures > 0) std::printf("%d failing inputs\n", failures);
    return failures > 0 ? 1 : 0;
  } catch (const UsageError& e) {
    std::cerr << "robcal_fuzz: " << e.what() << "\n" << kUsage;
    return 2;
  } catch (const InputError& e) {
    // A corpus file the targets are built from (tool.yaml, plan.json...) is missing or broken.
    std::cerr << "robcal_fuzz: corpus: " << e.what() << "\n";
    return 2;
  } catch (const fs::filesystem_error& e) {
    std::cerr << "robcal_fuzz: corpus: " << e.what() << "\n";
    return 2;
  }
}
