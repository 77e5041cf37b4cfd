#include "robcal/programs/measurement_program.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>

#include "measurement_writers.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/robot_pulses.hpp"
#include "robcal/programs/program_filter.hpp"
#include "robcal/sim/simulator.hpp"

namespace robcal {
namespace {

using detail::Visit;

/// Configuration names appear in comments and messages of every language: letters, digits,
/// '_', '-', '.' only (no quote, comment or statement character of any of them), at most 16
/// characters (Fanuc MESSAGE[] holds 24, with "robcal " in front).
constexpr size_t kMaxConfigName = 16;

void check_config_name(const std::string& name) {
  const bool ok = !name.empty() && name.size() <= kMaxConfigName &&
                  std::all_of(name.begin(), name.end(), [](unsigned char c) {
                    return std::isalnum(c) || c == '_' || c == '-' || c == '.';
                  });
  if (!ok)
    throw InputError(SourceLocation{"", 0, 0, name.empty() ? "config" : name},
                     fmt::format("configuration name '{}': expected 1 to {} letters, digits, '_', "
                                 "'-' or '.' (it is written into the program's comments)",
                                 name, kMaxConfigName));
}

void check_program_name(const std::string& name) {
  const bool ok = !name.empty() && name.size() <= 6 &&
                  std::isalpha(static_cast<unsigned char>(name[0])) &&
                  std::all_of(name.begin(), name.end(),
                              [](unsigned char c) { return std::isalnum(c) || c == '_'; });
  if (!ok)
    throw InputError(SourceLocation{"", 0, 0, "--name"},
                     fmt::format("program name '{}': expected a letter, then letters, digits or "
                                 "'_', at most 6 characters",
                                 name));
}

/// --rapid-signal names a signal of the controller's I/O configuration in a RAPID statement
/// (WaitDI / PulseDO): a RAPID identifier, a letter then letters, digits or '_', at most 32
/// characters; other languages and the log hook use no signal name.
void check_rapid_signal(const MeasurementProgramRequest& r) {
  const std::string& name = r.rapid_signal;
  if (name.empty()) return;
  if (r.language != ProgramLanguage::Rapid)
    throw InputError(SourceLocation{"", 0, 0, "--rapid-signal"},
                     fmt::format("a RAPID signal name, but the program is {}: give its input or "
                                 "output number with --signal",
                                 program_language_name(r.language)));
  if (r.hook == MeasurementHook::LogLine)
    throw InputError(SourceLocation{"", 0, 0, "--rapid-signal"},
                     "the log hook writes a message, no signal: drop --rapid-signal or choose "
                     "--hook wait or pulse");
  const bool identifier = name.size() <= 32 && std::isalpha(static_cast<unsigned char>(name[0])) &&
                          std::all_of(name.begin(), name.end(),
                                      [](unsigned char c) { return std::isalnum(c) || c == '_'; });
  if (!identifier)
    throw InputError(SourceLocation{"", 0, 0, "--rapid-signal"},
                     fmt::format("signal name '{}': expected a RAPID identifier, a letter then "
                                 "letters, digits or '_', at most 32 characters",
                                 name));
}

/// q and its approach inside the limits (the approach moves each joint by ∓approach_deg).
void check_limits(const MeasurementProgramRequest& r, const std::string& name,
                  const Vector6d& target_rad, const Vector6d& approach_rad) {
  if (!r.limits) return;
  for (int j = 0; j < kJointCount; ++j) {
    const JointLimit& l = (*r.limits)[static_cast<size_t>(j)];
    for (const auto& [what, q] : {std::pair{"", target_rad[j]}, {" (approach)", approach_rad[j]}})
      if (q < l.lower || q > l.upper)
        throw InputError(
            SourceLocation{"", 0, 0, name},
            fmt::format("joint {} at {:.4f} deg{} is outside its limits [{:.4f}, "
                        "{:.4f}] deg; the approach moves each joint by {} deg to the side it comes "
                        "from (docs/method/05-observability.md §4), so a configuration needs that "
                        "margin",
                        j + 1, rad2deg(q), what, rad2deg(l.lower), rad2deg(l.upper),
                        r.approach_deg));
  }
}

}  // namespace

int program_size_limit(ProgramLanguage language) {
  switch (language) {
    case ProgramLanguage::FanucLs:
      return 250;
    case ProgramLanguage::Jbi:
      return 400;
    case ProgramLanguage::UrScript:
      return 1000;
    default:
      return 500;
  }
}

std::vector<ProgramFile> write_measurement_program(const MeasurementProgramRequest& r) {
  check_program_name(r.name);
  check_rapid_signal(r);
  if (r.names.size() != r.joints.size() || (!r.visits.empty() && r.visits.size() != r.names.size()))
    throw std::invalid_argument(
        "write_measurement_program: names, joints and visits differ in size");
  if (r.joints.empty())
    throw InputError(SourceLocation{"", 0, 0, "configs"}, "no configuration to visit");
  if (!(r.approach_deg >= 0 && r.approach_deg <= 30))
    throw InputError(SourceLocation{"", 0, 0, "--approach-deg"},
                     fmt::format("expected 0 to 30 degrees, found {}", r.approach_deg));
  if (!(r.settle_s >= 0 && r.settle_s <= 600))
    throw InputError(SourceLocation{"", 0, 0, "--settle-s"},
                     fmt::format("expected 0 to 600 seconds, found {}", r.settle_s));
  if (!(r.joint_speed_percent > 0 && r.joint_speed_percent <= 100))
    throw InputError(
        SourceLocation{"", 0, 0, "--speed-percent"},
        fmt::format("expected more than 0 and at most 100, found {}", r.joint_speed_percent));
  if (r.signal < 0 || r.signal > 4096)
    throw InputError(SourceLocation{"", 0, 0, "--signal"},
                     fmt::format("expected a signal number 0 to 4096, found {}", r.signal));
  if (r.max_configs_per_file < 0)
    throw InputError(SourceLocation{"", 0, 0, "--max-configs-per-file"},
                     fmt::format("expected a positive count of configurations per program (0: "
                                 "the controller's limit, {} for {}), found {}",
                                 program_size_limit(r.language), program_language_name(r.language),
                                 r.max_configs_per_file));
  // Tool numbers: Fanuc UTOOL 0..10 (more on some options), KUKA TOOL_DATA[1..16], Yaskawa
  // TOOL 0..63: beyond 63 is none of them.
  if (r.tool_number < 0 || r.tool_number > 63)
    throw InputError(SourceLocation{"", 0, 0, "--tool-number"},
                     fmt::format("expected a tool number 0 to 63, found {}", r.tool_number));
  if (r.language == ProgramLanguage::Jbi && !r.pulses_per_degree)
    throw InputError(SourceLocation{"", 0, 0, "--pulses-per-degree"},
                     "a Yaskawa job stores joints in encoder pulses: give the pulses per degree "
                     "of the six axes");
  if (r.pulses_per_degree)
    for (int j = 0; j < kJointCount; ++j) {
      const double ppd = (*r.pulses_per_degree)[static_cast<size_t>(j)];
      if (!(ppd > 0 && ppd < 1e7))
        throw InputError(SourceLocation{"", 0, 0, "--pulses-per-degree"},
                         fmt::format("axis {}: expected a positive pulse count per degree", j + 1));
    }
  if (r.hook == MeasurementHook::LogLine &&
      (r.language == ProgramLanguage::Krl || r.language == ProgramLanguage::Jbi))
    throw InputError(SourceLocation{"", 0, 0, "--hook"},
                     fmt::format("no log instruction is written for {}; use wait or pulse",
                                 program_language_name(r.language)));
  const int limit =
      r.max_configs_per_file > 0 ? r.max_configs_per_file : program_size_limit(r.language);

  std::vector<Visit> visits;
  for (size_t i = 0; i < r.joints.size(); ++i) {
    check_config_name(r.names[i]);
    if (!r.joints[i].allFinite())
      throw InputError(SourceLocation{"", 0, 0, r.names[i]}, "joints are not finite");
    const ConfigurationVisit how = r.visits.empty() ? ConfigurationVisit{} : r.visits[i];
    std::string from_above;
    for (int j = 0; j < kJointCount; ++j) {
      if (how.side[j] != 1.0 && how.side[j] != -1.0)
        throw InputError(SourceLocation{"", 0, 0, r.names[i]},
                         fmt::format("joint {}: the approach side must be + or -, found {}", j + 1,
                                     how.side[j]));
      if (how.side[j] < 0) from_above += (from_above.empty() ? "" : ",") + std::to_string(j + 1);
    }
    const Vector6d approach_deg =
        r.joints[i] * kRadToDeg - r.approach_deg * how.side;  // 5° away on the side it comes from
    check_limits(r, r.names[i], r.joints[i], how.approach ? approach_deg * kDegToRad : r.joints[i]);
    visits.push_back(
        {r.names[i], approach_deg, r.joints[i] * kRadToDeg, how.approach, how.measure, from_above});
  }

  // Parts of at most `limit` configurations, a new one where the payload changes (the operator
  // mounts it between programs).
  std::vector<std::pair<size_t, size_t>> ranges;  // first, count
  for (size_t i = 0; i < visits.size(); ++i) {
    if (ranges.empty() || ranges.back().second == static_cast<size_t>(limit) ||
        (!r.visits.empty() && r.visits[i].payload != r.visits[ranges.back().first].payload))
      ranges.emplace_back(i, 0);
    ++ranges.back().second;
  }
  const int parts = static_cast<int>(ranges.size());
  if (parts > 99)
    throw InputError(
        SourceLocation{"", 0, 0, "--max-configs-per-file"},
        fmt::format("{} configurations would make {} programs; at most 99", visits.size(), parts));
  std::vector<ProgramFile> files;
  for (int p = 0; p < parts; ++p) {
    const auto [first, count] = ranges[static_cast<size_t>(p)];
    detail::MeasurementPart part{r,
                                 parts == 1 ? r.name : fmt::format("{}{:02d}", r.name, p + 1),
                                 p + 1,
                                 parts,
                                 first,
                                 std::span<const Visit>(visits).subspan(first, count),
                                 r.visits.empty() ? std::string() : r.visits[first].payload};
    // One writer per language, in ProgramLanguage order.
    using Writer = std::string (*)(const detail::MeasurementPart&);
    static constexpr Writer kWriters[] = {
        detail::write_rapid_measurement, detail::write_krl_measurement,
        detail::write_ls_measurement, detail::write_jbi_measurement,
        detail::write_urscript_measurement};
    std::string text = kWriters[static_cast<size_t>(r.language)](part);
    // KRL and URScript file names are in lower case by convention; the others keep the name.
    std::string file = part.program;
    if (r.language == ProgramLanguage::Krl || r.language == ProgramLanguage::UrScript)
      std::transform(file.begin(), file.end(), file.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    files.push_back({file + program_extension(r.language), std::move(text)});
  }
  return files;
}

std::vector<std::string> write_measurement_program_files(const MeasurementProgramRequest& request,
                                                         const std::string& out_dir) {
  const std::vector<ProgramFile> files = write_measurement_program(request);
  std::vector<std::string> paths;
  for (const ProgramFile& f : files) {
    paths.push_back((std::filesystem::path(out_dir) / f.name).string());
    write_file_atomically(paths.back(), f.text);
  }
  return paths;
}

MeasurementProgramFilesResult write_measurement_program_from_files(
    const MeasurementProgramFilesRequest& request) {
  MeasurementProgramFilesResult result;
  MeasurementProgramRequest& program = result.program;
  program = request.program;
  if (!request.robot.empty()) {
    program.limits = load_robot(request.robot).limits;
    if (const auto ppd = robot_pulses_per_degree(request.robot);
        !program.pulses_per_degree && ppd[0] > 0)
      program.pulses_per_degree = ppd;
  }
  const Tool tool = request.tool.empty() ? Tool{} : load_tool(request.tool);
  program.names.clear();
  program.joints.clear();
  program.visits.clear();
  for (const PlannedConfiguration& c : read_configurations_csv(request.configs, tool)) {
    program.names.push_back(c.name);
    program.joints.push_back(c.joints);
    ConfigurationVisit visit;
    visit.side = c.approach;
    if (c.payload >= 0) visit.payload = tool.payloads[static_cast<size_t>(c.payload)].name;
    program.visits.push_back(visit);
  }
  result.paths = write_measurement_program_files(program, request.out_dir);
  return result;
}

std::vector<JointMove> read_joint_moves(
    const std::string& text, ProgramLanguage language, const std::string& file,
    const std::optional<std::array<double, kJointCount>>& pulses_per_degree) {
  switch (language) {
    case ProgramLanguage::Rapid:
    case ProgramLanguage::Krl: {
      std::vector<JointMove> moves;
      for (const ProgramPoint& p : parse_program(text, language, file))
        if (p.is_joint_target) moves.push_back({p.joints_deg, p.line});
      return moves;
    }
    case ProgramLanguage::FanucLs:
      return detail::read_ls_joint_moves(text, file);
    case ProgramLanguage::Jbi:
      if (!pulses_per_degree)
        throw InputError(SourceLocation{file, 0, 0, "--pulses-per-degree"},
                         "reading a Yaskawa job's joints needs the pulses per degree");
      return detail::read_jbi_joint_moves(text, file, *pulses_per_degree);
    case ProgramLanguage::UrScript:
      return detail::read_urscript_joint_moves(text, file);
  }
  return {};
}

namespace detail {

std::string header_comment(const MeasurementPart& part, std::string_view prefix,
                           std::string_view stop) {
  const MeasurementProgramRequest& r = part.request;
  const auto approached = std::count_if(part.visits.begin(), part.visits.end(),
                                        [](const Visit& v) { return v.approach; });
  const bool some_above = std::any_of(part.visits.begin(), part.visits.end(), [](const Visit& v) {
    return v.approach && !v.from_above.empty();
  });
  const std::string which = approached == static_cast<long>(part.visits.size())
                                ? "Each configuration is"
                            : approached == 0 ? "No configuration is"
                                              : "Some configurations are";
  std::string out = fmt::format(
      "{0} robcal measurement program, part {1} of {2}: configurations {3}-{4} of {5}.\n"
      "{0} {6} approached from q - {7:g} deg on every joint{8} (backlash,\n"
      "{0} robcal method), {9}, then the arm settles {10:g} s where it measures.\n",
      prefix, part.part, part.parts, part.first + 1, part.first + part.visits.size(),
      r.joints.size(), which, r.approach_deg,
      some_above ? fmt::format(",\n{} or q + {:g} deg on the joints its comment names", prefix,
                               r.approach_deg)
                 : "",
      stop, r.settle_s);
  const bool payload_changes =
      std::any_of(r.visits.begin(), r.visits.end(),
                  [](const ConfigurationVisit& v) { return !v.payload.empty(); });
  if (payload_changes)
    out += fmt::format("{} Mount {} before running this part.\n", prefix,
                       part.payload.empty()
                           ? std::string("the tool's own payload")
                           : fmt::format("the payload '{}' (tool file)", part.payload));
  return out;
}

double read_number(std::string_view text, size_t& at, const std::string& file, int line,
                   size_t line_start) {
  const size_t begin = at;
  size_t end = at;
  if (end < text.size() && (text[end] == '-' || text[end] == '+')) ++end;
  while (end < text.size()) {
    const char c = text[end];
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '.' ||
        ((c == '+' || c == '-') && (text[end - 1] == 'e' || text[end - 1] == 'E')))
      ++end;
    else
      break;
  }
  std::string_view literal = text.substr(begin, end - begin);
  if (!literal.empty() && literal[0] == '+') literal.remove_prefix(1);
  double value = 0;
  const auto [ptr, ec] = std::from_chars(literal.data(), literal.data() + literal.size(), value);
  // Built for an error only: a copy of the file name per number would cost an allocation each
  // (six numbers per position) for a path longer than the short-string buffer.
  const auto where = [&] {
    return SourceLocation{file, line, static_cast<int>(begin - line_start) + 1, ""};
  };
  if (literal.empty() || ec == std::errc::invalid_argument)
    throw InputError(where(),
                     fmt::format("expected a number, found '{}'",
                                 text.substr(begin, std::min<size_t>(end - begin + 1, 20))));
  if (ec == std::errc::result_out_of_range)
    throw InputError(where(), fmt::format("number '{}' is out of range", literal));
  if (ptr != literal.data() + literal.size() || !std::isfinite(value))
    throw InputError(where(), fmt::format("malformed number '{}'", literal));
  at = end;
  return value;
}

}  // namespace detail
MeasurementHook measurement_hook_from_name(const std::string& name, const std::string& key) {
  if (name == "wait") return MeasurementHook::WaitInput;
  if (name == "pulse") return MeasurementHook::PulseOutput;
  if (name == "log") return MeasurementHook::LogLine;
  throw InputError({"", 0, 0, key}, "expected wait, pulse or log, found '" + name + "'");
}

}  // namespace robcal
