/// robcal: the command-line program. Each command lives in its own cmd_*.cpp and registers
/// itself; this file only runs CLI11 and turns errors into messages and exit codes.

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <iostream>
#include <utility>
#include <vector>

#include "command_registry.hpp"
#include "flag_checks.hpp"
#include "robcal/core/error.hpp"

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

void setup_commands(CLI::App& app) {
  auto& commands = registry();
  std::stable_sort(commands.begin(), commands.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [order, setup] : commands) setup(app);
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
    robcal::cli::setup_commands(app);
    robcal::cli::add_flag_checks(app);
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      // --help prints and succeeds; every malformed command line is bad input: exit code 2, as
      // for bad files (CLI11's own codes, 104 for a non-numeric value, would surprise scripts).
      const int code = app.exit(e);
      return code == 0 ? 0 : 2;
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
