#pragma once
/// \file
/// Each command file registers itself at start-up, so adding a command touches one file.

#include <CLI/CLI.hpp>
#include <functional>

namespace robcal::cli {

/// Adds a subcommand (and its callback) to the application.
using CommandSetup = std::function<void(CLI::App& app)>;

/// Registers a command; `order` sorts them in the help text. Returns true (for static init).
bool register_command(int order, CommandSetup setup);

/// Calls every registered setup, in order.
void setup_commands(CLI::App& app);

}  // namespace robcal::cli
