/// `robcal session`: the guided tracker/CMM-probe session (campaign/point_session.hpp): prompts,
/// readings typed or piped on stdin, every one journalled and synced at once, `--resume`.

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <thread>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/campaign/frames_world.hpp"
#include "robcal/campaign/instrument_import.hpp"
#include "robcal/campaign/point_session.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/journal_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal::cli {
namespace {

struct SessionOptions {
  std::string configs, tool, journal, out, reference, follow, map, world_frame;
  int every = 0;
  double follow_timeout_s = 600;
  bool resume = false;
};

std::string now_utc() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  std::tm tm{};
  gmtime_r(&t, &tm);
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  return fmt::format("{:04d}-{:02d}-{:02d}T{:02d}:{:02d}:{:02d}.{:03d}Z", tm.tm_year + 1900,
                     tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, ms);
}

void run_session(const SessionOptions& o) {
  campaign::SessionSettings settings;
  settings.tool = o.tool.empty() ? default_simulation_tool() : load_tool(o.tool);
  settings.configs = read_configurations_csv(o.configs, settings.tool);
  settings.every = o.every;
  if (!o.reference.empty()) {
    for (size_t c = 0; c < settings.configs.size(); ++c)
      if (settings.configs[c].name == o.reference) settings.reference = static_cast<int>(c);
    if (settings.reference < 0)
      throw InputError({"", 0, 0, "--reference"},
                       fmt::format("configuration '{}' is not in {}", o.reference, o.configs));
  } else if (o.every > 0) {
    throw InputError({"", 0, 0, "--every"}, "drift checks need the reference (--reference NAME)");
  }
  const std::vector<campaign::SessionStep> steps = campaign::session_steps(settings);
  // Read before the first prompt: a bad frame file must not wait for the end of the session.
  const std::optional<Pose<double>> instrument_T_world =
      o.world_frame.empty() ? std::nullopt
                            : std::optional(campaign::load_world_frame(o.world_frame));

  campaign::ExportFormat format;
  if (!o.map.empty()) format = campaign::parse_export_format(read_text_file(o.map), o.map);

  // The hexapod session's journal machinery (io/journal_file.hpp): exclusive create, lock,
  // append + sync per reading, torn last line cut on resume. Its lines are this session's.
  std::vector<campaign::SessionReading> readings;
  const bool resuming = std::filesystem::exists(o.journal);
  if (resuming && !o.resume)
    throw InputError({o.journal, 0, 0, "--journal"},
                     "the journal exists: pass --resume to continue it, or name a new journal");
  JournalFile journal =
      resuming ? JournalFile::open_for_resume(o.journal) : JournalFile::create(o.journal);
  if (resuming) {
    const std::string text = journal.text();
    size_t complete = 0;
    readings = campaign::replay_journal(text, o.journal, steps, &complete);
    if (complete < text.size()) journal.truncate(complete);
    fmt::print("resumed {}: {} of {} steps answered\n", o.journal, readings.size(), steps.size());
  }
  for (size_t i = readings.size(); i < steps.size();) {
    fmt::print("[{}/{}] {}\n> ", i + 1, steps.size(), steps[i].prompt);
    std::fflush(stdout);
    if (!o.follow.empty()) {
      // The k-th reading of the export answers the k-th step; wait for the software to write it.
      const auto deadline = std::chrono::steady_clock::now() +
                            std::chrono::milliseconds(static_cast<long>(1000 * o.follow_timeout_s));
      std::vector<Eigen::Vector3d> points;
      while (true) {
        if (std::filesystem::exists(o.follow))
          points = campaign::read_export_points({o.follow, read_text_file(o.follow)}, format);
        if (points.size() > i || std::chrono::steady_clock::now() > deadline) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
      }
      if (points.size() <= i) {
        fmt::print(
            "\nno reading {} in {} after {:g} s: paused after {} of {} steps; run again "
            "with --resume\n",
            i + 1, o.follow, o.follow_timeout_s, i, steps.size());
        return;
      }
      const Eigen::Vector3d& p = points[i];
      fmt::print("{} {} {} (from {})\n", p.x(), p.y(), p.z(), o.follow);
      readings.push_back({steps[i].key, p, now_utc(), std::nullopt});
      journal.append_line(campaign::journal_line(readings.back()));
      ++i;
      continue;
    }
    std::string line;
    if (!std::getline(std::cin, line)) {
      fmt::print("\npaused after {} of {} steps: every reading is in {}; run again with --resume\n",
                 i, steps.size(), o.journal);
      return;
    }
    try {
      readings.push_back(campaign::parse_answer(line, steps[i], now_utc()));
    } catch (const InputError& e) {
      fmt::print(stderr, "{}; try again\n", e.what());
      continue;
    }
    journal.append_line(campaign::journal_line(readings.back()));
    ++i;
  }
  const campaign::SessionResult result = campaign::session_result(settings, steps, readings);
  std::string comment = fmt::format("robcal session: {} of {} configurations read",
                                    result.measurements.points.size(), settings.configs.size());
  if (!result.missing.empty())
    comment +=
        "\nmissing (marked by the operator): " + fmt::format("{}", fmt::join(result.missing, ", "));
  if (instrument_T_world)
    comment +=
        fmt::format("\npositions in the world frame of {} (robcal frames world)", o.world_frame);
  write_file_atomically(
      o.out, write_measurements_csv(
                 instrument_T_world
                     ? campaign::measurements_in_frame(result.measurements, *instrument_T_world)
                     : result.measurements,
                 settings.tool, comment));
  fmt::print("\nsession complete: {} configurations read, {} missing{}\n",
             result.measurements.points.size(), result.missing.size(),
             result.missing.empty()
                 ? ""
                 : " (" + fmt::format("{}", fmt::join(result.missing, ", ")) + ")");
  for (const campaign::DriftCheck& d : result.drift)
    fmt::print("  drift {}: {:.4f} mm at {}{}\n", d.key, d.drift_mm, d.time,
               d.temperature_c ? fmt::format(", {:.1f} °C", *d.temperature_c) : "");
  fmt::print("wrote {}\n", o.out);
}

const bool registered = register_command(77, [](CLI::App& app) {
  auto o = std::make_shared<SessionOptions>();
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
