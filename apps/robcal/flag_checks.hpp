#pragma once
/// \file
/// Checks every command's flags get before the command runs, by flag name, so that no command
/// can forget them.

#include <CLI/CLI.hpp>

namespace robcal::cli {

/// Refuses values that no command can mean: a negative σ, scale or count (--noise-mm,
/// --huber-scale, --candidates, …) and a seed that is not a whole number (--seed -1 would wrap
/// to 2^64 - 1).
void add_flag_checks(CLI::App& app);

}  // namespace robcal::cli
