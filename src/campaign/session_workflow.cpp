#include "robcal/campaign/session_workflow.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <ctime>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "robcal/campaign/frames_world.hpp"
#include "robcal/campaign/instrument_import.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/journal_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/true_robot.hpp"

namespace robcal::campaign {
namespace {

SessionSettings settings_of(const PointSessionRequest& request) {
  SessionSettings settings;
  settings.tool = request.tool.empty() ? default_simulation_tool() : load_tool(request.tool);
  settings.configs = read_configurations_csv(request.configs, settings.tool);
  settings.every = request.every;
  if (!request.reference.empty()) {
    for (size_t c = 0; c < settings.configs.size(); ++c)
      if (settings.configs[c].name == request.reference) settings.reference = static_cast<int>(c);
    if (settings.reference < 0)
      throw InputError({"", 0, 0, "--reference"}, fmt::format("configuration '{}' is not in {}",
                                                              request.reference, request.configs));
  } else if (request.every > 0) {
    throw InputError({"", 0, 0, "--every"}, "drift checks need the reference (--reference NAME)");
  }
  // The timeout becomes a count of milliseconds: NaN, negative or huge values would overflow it.
  if (!(request.follow_timeout_s >= 0 && request.follow_timeout_s <= 86400))
    throw InputError({"", 0, 0, "--follow-timeout"},
                     fmt::format("expected 0 to 86400 seconds, got {}", request.follow_timeout_s));
  return settings;
}

/// The k-th reading of the export answers the k-th step: waits (polling) until the export has
/// reading `step` or the timeout passes.
std::optional<Eigen::Vector3d> wait_for_reading(const PointSessionRequest& request,
                                                const ExportFormat& format, size_t step) {
  const auto deadline =
      std::chrono::steady_clock::now() +
      std::chrono::milliseconds(static_cast<long>(1000 * request.follow_timeout_s));
  while (true) {
    if (std::filesystem::exists(request.follow)) {
      const std::vector<Eigen::Vector3d> points =
          read_export_points({request.follow, read_text_file(request.follow)}, format);
      if (points.size() > step) return points[step];
    }
    if (std::chrono::steady_clock::now() > deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

std::string session_csv(const PointSessionRequest& request, const SessionSettings& settings,
                        const SessionResult& result,
                        const std::optional<Pose<double>>& instrument_T_world) {
  std::string comment = fmt::format("robcal session: {} of {} configurations read",
                                    result.measurements.points.size(), settings.configs.size());
  if (!result.missing.empty())
    comment +=
        fmt::format("\nmissing (marked by the operator): {}", fmt::join(result.missing, ", "));
  if (instrument_T_world) comment += "\n" + world_frame_comment(request.world_frame);
  return write_measurements_csv(
      instrument_T_world ? measurements_in_frame(result.measurements, *instrument_T_world)
                         : result.measurements,
      settings.tool, comment);
}

}  // namespace

std::string utc_now_iso() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  std::tm tm{};
  gmtime_r(&t, &tm);
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  return fmt::format("{:04d}-{:02d}-{:02d}T{:02d}:{:02d}:{:02d}.{:03d}Z", tm.tm_year + 1900,
                     tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, ms);
}

PointSessionRun run_point_session(const PointSessionRequest& request, const SessionIo& io) {
  const SessionSettings settings = settings_of(request);
  const std::vector<SessionStep> steps = session_steps(settings);
  // Read before the first prompt: a bad frame file must not wait for the end of the session.
  const std::optional<Pose<double>> instrument_T_world =
      request.world_frame.empty() ? std::nullopt
                                  : std::optional(load_world_frame(request.world_frame));
  ExportFormat format;
  if (!request.map.empty()) format = parse_export_format(read_text_file(request.map), request.map);
  const auto now = io.now ? io.now : utc_now_iso;

  PointSessionRun run;
  run.steps = steps.size();
  run.configurations = settings.configs.size();
  run.tool = settings.tool;
  std::vector<SessionReading> readings;
  const bool resuming = std::filesystem::exists(request.journal);
  if (resuming && !request.resume)
    throw InputError({request.journal, 0, 0, "--journal"},
                     "the journal exists: pass --resume to continue it, or name a new journal");
  JournalFile journal = resuming ? JournalFile::open_for_resume(request.journal)
                                 : JournalFile::create(request.journal);
  if (resuming) {
    const std::string text = journal.text();
    size_t complete = 0;
    readings = replay_journal(text, request.journal, steps, &complete);
    if (complete < text.size()) journal.truncate(complete);
    run.resumed = readings.size();
    io.say(fmt::format("resumed {}: {} of {} steps answered\n", request.journal, readings.size(),
                       steps.size()));
  }
  const auto finish = [&](SessionStop stop) {
    run.stop = stop;
    run.answered = readings.size();
    run.result = session_result(settings, steps, readings);
    return run;
  };
  for (size_t i = readings.size(); i < steps.size();) {
    io.say(fmt::format("[{}/{}] {}\n> ", i + 1, steps.size(), steps[i].prompt));
    if (!request.follow.empty()) {
      const std::optional<Eigen::Vector3d> p = wait_for_reading(request, format, i);
      if (!p) return finish(SessionStop::FollowTimeout);
      io.say(fmt::format("{} {} {} (from {})\n", p->x(), p->y(), p->z(), request.follow));
      readings.push_back({steps[i].key, *p, now(), std::nullopt});
    } else {
      std::string line;
      if (!io.read_line(line)) return finish(SessionStop::EndOfInput);
      try {
        readings.push_back(parse_answer(line, steps[i], now()));
      } catch (const InputError& e) {
        io.refuse(e.what());
        continue;
      }
    }
    journal.append_line(journal_line(readings.back()));
    ++i;
  }
  finish(SessionStop::Complete);
  run.csv = session_csv(request, settings, run.result, instrument_T_world);
  write_file_atomically(request.out, run.csv);
  return run;
}

nlohmann::json session_result_json(const SessionResult& result) {
  nlohmann::json drift = nlohmann::json::array();
  for (const DriftCheck& d : result.drift)
    drift.push_back({{"key", d.key},
                     {"drift_mm", d.drift_mm},
                     {"time", d.time},
                     {"temperature_c", d.temperature_c ? nlohmann::json(*d.temperature_c)
                                                       : nlohmann::json(nullptr)}});
  return {
      {"read", result.measurements.points.size()}, {"missing", result.missing}, {"drift", drift}};
}

nlohmann::json point_session_json(const PointSessionRun& run) {
  nlohmann::json j = session_result_json(run.result);
  j["status"] = run.stop == SessionStop::Complete     ? "complete"
                : run.stop == SessionStop::EndOfInput ? "paused-end-of-input"
                                                      : "paused-follow-timeout";
  j["steps"] = run.steps;
  j["answered"] = run.answered;
  j["resumed"] = run.resumed;
  j["configurations"] = run.configurations;
  return j;
}

}  // namespace robcal::campaign
