#pragma once
/// \file
/// Checks every command's flags get before the command runs, by flag name, so that no command
/// can forget them.

#include <CLI/CLI.hpp>

namespace robcal::cli {

/// Refuses values that no command can mean: a negative σ or scale (--noise-mm, --huber-scale),
/// a count that is not a whole number 0 .. 1e6 (--runs, --random, …) and a seed that is not a
/// whole number (--seed -1 would wrap to 2^64 - 1).
void add_flag_checks(CLI::App& app);

}  // namespace robcal::cli
