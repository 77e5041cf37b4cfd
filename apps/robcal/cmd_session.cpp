/// `robcal session`: the guided tracker/CMM-probe session (campaign/session_workflow.hpp): prompts,
/// readings typed or piped on stdin, every one journalled and synced at once, `--resume`.

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdio>
#include <iostream>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/campaign/session_workflow.hpp"

namespace robcal::cli {
namespace {

void run_session(const campaign::PointSessionRequest& request) {
  const campaign::SessionIo io{
      [](const std::string& text) {
        fmt::print("{}", text);
        std::fflush(stdout);
      },
      [](const std::string& error) { fmt::print(stderr, "{}; try again\n", error); },
      [](std::string& line) { return static_cast<bool>(std::getline(std::cin, line)); },
      {}};
  const campaign::PointSessionRun run = campaign::run_point_session(request, io);
  const campaign::SessionResult& result = run.result;
  if (run.stop == campaign::SessionStop::FollowTimeout) {
    fmt::print(
        "\nno reading {} in {} after {:g} s: paused after {} of {} steps; run again "
        "with --resume\n",
        run.answered + 1, request.follow, request.follow_timeout_s, run.answered, run.steps);
    return;
  }
  if (run.stop == campaign::SessionStop::EndOfInput) {
    fmt::print("\npaused after {} of {} steps: every reading is in {}; run again with --resume\n",
               run.answered, run.steps, request.journal);
    return;
  }
  fmt::print("\nsession complete: {} configurations read, {} missing{}\n",
             result.measurements.points.size(), result.missing.size(),
             result.missing.empty() ? "" : fmt::format(" ({})", fmt::join(result.missing, ", ")));
  for (const campaign::DriftCheck& d : result.drift)
    fmt::print("  drift {}: {:.4f} mm at {}{}\n", d.key, d.drift_mm, d.time,
               d.temperature_c ? fmt::format(", {:.1f} °C", *d.temperature_c) : "");
  fmt::print("wrote {}\n", request.out);
}

const bool session_registered = register_command(77, [](CLI::App& app) {
  auto o = std::make_shared<campaign::PointSessionRequest>();
  auto* cmd = app.add_subcommand(
      "session",
      "Guided tracker/CMM-probe session: prompts each configuration, readings typed or piped as "
      "'x y z [°C]' or 'skip', journalled at once (--resume continues)");
  cmd->add_option("--configs", o->configs, "Plan: config,target,j1..j6 (deg), e.g. robcal plan's")
      ->required();
  cmd->add_option("--tool", o->tool, "Tool file (default: the simulator's, SMRs 1, 2, 3)");
  cmd->add_option("--journal", o->journal, "Journal file (append-only)")->required();
  cmd->add_flag("--resume", o->resume, "Continue the journal's session");
  cmd->add_option("--reference", o->reference, "Reference configuration for drift checks");
  cmd->add_option("--every", o->every, "Re-measure the reference every N configurations");
  cmd->add_option("--follow", o->follow,
                  "Read the answers from this instrument export as its software appends to it "
                  "(the k-th reading answers the k-th step) instead of stdin");
  cmd->add_option("--map", o->map, "Mapping file of the --follow export (see robcal import)");
  cmd->add_option("--follow-timeout", o->follow_timeout_s,
                  "Seconds to wait for the next reading of --follow before pausing")
      ->capture_default_str();
  cmd->add_option("--out", o->out, "Measurement CSV written when the session is complete")
      ->required();
  cmd->add_option("--world-frame", o->world_frame,
                  "Frame file of `robcal frames world`: write the positions in that frame (the "
                  "nests' world) instead of the instrument's (the journal keeps the readings)");
  cmd->callback([o] { run_session(*o); });
});

}  // namespace
}  // namespace robcal::cli
