/// robcal: the command-line program. Each command lives in its own cmd_*.cpp and registers
/// itself; this file only runs CLI11 and turns errors into messages and exit codes.

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "flag_checks.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/progress.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal::cli {

namespace {
std::vector<std::pair<int, CommandSetup>>& registry() {
  static std::vector<std::pair<int, CommandSetup>> commands;
  return commands;
}
}  // namespace

bool register_command(int order, CommandSetup setup) {
  registry().emplace_back(order, std::move(setup));
  return true;
}

namespace {
/// The headings of --help, in pipeline order, and the commands under each.
struct Stage {
  const char* heading;
  std::vector<std::string> commands;
};
const std::vector<Stage>& stages() {
  static const std::vector<Stage> kStages = {
      {"1. Model", {"robots", "robot", "fk", "ik", "model"}},
      {"2. Plan", {"plan", "plan-study"}},
      {"3. Measure", {"program", "simulate", "import", "frames", "session"}},
      {"4. Identify", {"calibrate"}},
      {"5. Validate", {"validate", "iso9283", "axis-test", "ballbar-path"}},
      {"6. Compensate", {"compensate", "compensate-program"}},
      {"Ballbar hexapod (every stage)", {"hexapod"}},
      {"Reports", {"report"}},
      {"Simulation studies", {"demo", "montecarlo", "experiments"}}};
  return kStages;
}

/// Index of the stage of `command` in stages(); unknown commands come last, under "Other".
size_t stage_index(const std::string& command) {
  const auto& list = stages();
  for (size_t i = 0; i < list.size(); ++i)
    if (std::find(list[i].commands.begin(), list[i].commands.end(), command) !=
        list[i].commands.end())
      return i;
  return list.size();
}

/// The stage of the commands a setup adds (set up on a scratch application to learn their
/// names): CLI11 lists the groups in the order their first command was added. A setup that
/// extends another command (`hexapod calibrate`) fails on the empty application and runs last.
size_t stage_of_setup(const CommandSetup& setup) {
  CLI::App scratch;
  try {
    setup(scratch);
  } catch (const CLI::Error&) {
    return stages().size();
  }
  size_t stage = stages().size();
  for (const CLI::App* command : scratch.get_subcommands({}))
    stage = std::min(stage, stage_index(command->get_name()));
  return stage;
}

/// The outputs (--out, --*-out) of the command line never overwrite its inputs: every other
/// option value or argument naming an existing file is an input.
void refuse_outputs_over_inputs(const CLI::App& app) {
  std::vector<std::pair<std::string, std::filesystem::path>> outputs;  // flag, path
  std::vector<std::filesystem::path> inputs;
  for (const CLI::App* command = &app; command != nullptr;) {
    for (const CLI::Option* option : command->get_options()) {
      const std::string flag = option->get_name();
      const bool output = (flag.size() > 3 && flag.compare(flag.size() - 3, 3, "out") == 0) ||
                          flag.rfind("--out-", 0) == 0;
      for (const std::string& value : option->results()) {
        std::error_code ec;
        if (output)
          outputs.emplace_back(flag, value);
        else if (std::filesystem::is_regular_file(value, ec))
          inputs.emplace_back(value);
      }
    }
    const auto chosen = command->get_subcommands();
    command = chosen.empty() ? nullptr : chosen.front();
  }
  for (const auto& [flag, path] : outputs) robcal::refuse_overwriting_inputs(path, inputs, flag);
  robcal::refuse_shared_outputs(outputs);
  for (const auto& output : outputs) {
    std::error_code ec;
    if (output.second == "-" || std::filesystem::equivalent(output.second, "/dev/stdout", ec))
      return reserve_stdout_for_data();
  }
}

/// The deepest command of the command line (`robcal hexapod plan` → plan) and its words.
std::pair<const CLI::App*, std::string> chosen_command(const CLI::App& app) {
  const CLI::App* command = &app;
  std::string words = "robcal";
  for (auto chosen = app.get_subcommands(); !chosen.empty(); chosen = command->get_subcommands()) {
    command = chosen.front();
    words += " " + command->get_name();
  }
  return {command, words};
}

/// CLI11's messages about the command line's words, located: the unknown command or flag is
/// named first and what was expected follows ("A subcommand is required" and "The following
/// arguments were not expected: red --colour" name neither). Empty for the other errors,
/// which CLI11 words well enough ("--out is required", "--seed: seed '-1': expected ...").
std::string located_parse_error(const CLI::App& app, const CLI::ParseError& error) {
  const auto [command, words] = chosen_command(app);
  const std::vector<std::string> extra = app.remaining(true);
  if (dynamic_cast<const CLI::RequiredError*>(&error) != nullptr &&
      std::string(error.what()).rfind("A subcommand", 0) == 0) {
    std::vector<std::string> names;
    for (const CLI::App* sub : command->get_subcommands({})) names.push_back(sub->get_name());
    const std::string expected =
        fmt::format("{} (`{} --help` describes them)", fmt::join(names, ", "), words);
    if (extra.empty()) return fmt::format("{}: expected a command: {}", words, expected);
    if (extra.front().rfind('-', 0) == 0)
      return fmt::format("{}: expected a command before the flags: {}", extra.front(), expected);
    return fmt::format("'{}': unknown command of `{}`: expected {}", extra.front(), words,
                       expected);
  }
  if (dynamic_cast<const CLI::ExtrasError*>(&error) != nullptr && !extra.empty()) {
    const auto flag = std::find_if(extra.begin(), extra.end(),
                                   [](const std::string& word) { return word.rfind('-', 0) == 0; });
    if (flag != extra.end())
      return fmt::format("{}: unknown flag of `{}` (`{} --help` lists its flags)", *flag, words,
                         words);
    return fmt::format("'{}': unexpected argument: `{}` takes its values after flags (`{} --help`)",
                       extra.front(), words, words);
  }
  return {};
}

/// The message of `error`, preceded by the flag that named its file when the error is about the
/// whole file (it cannot be opened, is empty or a directory: no line to point at), so that the
/// user reads which of the command's files it is.
std::string naming_the_flag(const CLI::App& app, const robcal::InputError& error) {
  const robcal::SourceLocation& where = error.where();
  if (where.file.empty() || where.line > 0 || !where.key.empty()) return error.what();
  for (const CLI::App* command = &app; command != nullptr;) {
    for (const CLI::Option* option : command->get_options()) {
      const auto& values = option->results();
      if (std::find(values.begin(), values.end(), where.file) != values.end())
        return fmt::format("{}: {}", option->get_name(), error.what());
    }
    const auto chosen = command->get_subcommands();
    command = chosen.empty() ? nullptr : chosen.front();
  }
  return error.what();
}
}  // namespace

void setup_commands(CLI::App& app) {
  // Sorted by stage, then by each command's order.
  std::vector<std::pair<std::pair<size_t, int>, CommandSetup*>> sorted;
  for (auto& [order, setup] : registry())
    sorted.push_back({{stage_of_setup(setup), order}, &setup});
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [key, setup] : sorted) (*setup)(app);
  for (CLI::App* command : app.get_subcommands({})) {
    const size_t stage = stage_index(command->get_name());
    command->group(stage < stages().size() ? stages()[stage].heading : "Other");
  }
}

}  // namespace robcal::cli

int main(int argc, char** argv) {
  // Everything inside the try: building the command set can throw too, and nothing may escape.
  try {
    CLI::App app{
        "robcal — absolute calibration of six-axis industrial robots.\n"
        "Units: millimetres and degrees in every file, flag and printout."};
    app.require_subcommand(1);
    app.set_help_all_flag("--help-all", "Show help for every command");
    app.set_version_flag("--version", "robcal " ROBCAL_VERSION, "Print the version and exit");
    app.footer(
        "Commands are listed by pipeline stage: model → plan → measure → identify → validate → "
        "compensate.\nA file argument '-' reads standard input; --out - writes standard "
        "output.\n`robcal COMMAND --help` for a command's flags.");
    // Long computations show their progress on stderr when it is a terminal.
    robcal::enable_terminal_progress(true);
    // Runs after parsing, before the command's callback.
    app.parse_complete_callback([&app] { robcal::cli::refuse_outputs_over_inputs(app); });
    robcal::cli::setup_commands(app);
    robcal::cli::add_flag_checks(app);
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      if (const std::string located = robcal::cli::located_parse_error(app, e); !located.empty()) {
        std::cerr << "error: " << located << "\n";
        return 2;
      }
      // --help prints and succeeds; every malformed command line is bad input: exit code 2, as
      // for bad files (CLI11's own codes, 104 for a non-numeric value, would surprise scripts).
      const int code = app.exit(e);
      return code == 0 ? 0 : 2;
    } catch (const robcal::InputError& e) {
      std::cerr << "error: " << robcal::cli::naming_the_flag(app, e) << "\n";
      return 2;
    }
  } catch (const robcal::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
