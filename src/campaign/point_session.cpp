#include "robcal/campaign/point_session.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "robcal/campaign/text_table.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal::campaign {
namespace {

/// Fields of a journal or answer line: split at commas, or at blanks when there is no comma.
std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> fields;
  const bool commas = line.find(',') != std::string::npos;
  std::string field;
  for (char c : line) {
    if (commas ? c == ',' : (c == ' ' || c == '\t')) {
      if (commas || !field.empty()) fields.push_back(field);
      field.clear();
    } else if (c != '\r' && !(commas && (c == ' ' || c == '\t'))) {
      field += c;
    }
  }
  if (commas || !field.empty()) fields.push_back(field);
  return fields;
}

}  // namespace

std::vector<SessionStep> session_steps(const SessionSettings& s) {
  if (s.reference >= static_cast<int>(s.configs.size()))
    throw InputError(
        fmt::format("reference configuration {} of {}", s.reference + 1, s.configs.size()));
  const auto target_name = [&](int c) -> const std::string& {
    const PlannedConfiguration& config = s.configs[static_cast<size_t>(c)];
    if (config.target < 0 || config.target >= static_cast<int>(s.tool.targets.size()))
      throw InputError({"", 0, 0, "target"},
                       fmt::format("configuration {} names no target of the tool: a session "
                                   "needs the target to measure in every row",
                                   config.name));
    return s.tool.targets[static_cast<size_t>(config.target)].name;
  };
  std::vector<SessionStep> steps;
  int checks = 0;
  const auto reference = [&] {
    if (s.reference < 0) return;
    const PlannedConfiguration& r = s.configs[static_cast<size_t>(s.reference)];
    ++checks;
    steps.push_back({fmt::format("ref{}/{}/{}", checks, r.name, target_name(s.reference)),
                     fmt::format("drift check {}: move to the reference {} and measure target {}",
                                 checks, r.name, target_name(s.reference)),
                     s.reference, true});
  };
  reference();
  for (size_t c = 0; c < s.configs.size(); ++c) {
    if (s.every > 0 && c > 0 && c % static_cast<size_t>(s.every) == 0) reference();
    const PlannedConfiguration& config = s.configs[c];
    std::string joints;
    for (int j = 0; j < kJointCount; ++j)
      joints += fmt::format("{}{:.3f}", j ? ", " : "", rad2deg(config.joints[j]));
    // The plan's conditions for the backlash and several-payload groups
    // (docs/method/03-error-model.md §6–§7): the rows record them.
    std::string from_above;
    for (int j = 0; j < kJointCount; ++j)
      if (config.approach[j] < 0)
        from_above += (from_above.empty() ? "" : ",") + std::to_string(j + 1);
    const bool payload_changes =
        c == 0 ? config.payload >= 0 : config.payload != s.configs[c - 1].payload;
    steps.push_back(
        {fmt::format("{}/{}", config.name, target_name(static_cast<int>(c))),
         fmt::format(
             "{}move to {} (joints {} deg{}) and measure target {}",
             !payload_changes ? ""
             : config.payload < 0
                 ? "mount the tool's own payload, then "
                 : fmt::format("mount the payload '{}', then ",
                               s.tool.payloads[static_cast<size_t>(config.payload)].name),
             config.name, joints,
             from_above.empty()
                 ? ""
                 : fmt::format("; joints {} approached from above, from q + 5 deg", from_above),
             target_name(static_cast<int>(c))),
         static_cast<int>(c), false});
  }
  if (s.every > 0) reference();
  return steps;
}

SessionReading parse_answer(const std::string& line, const SessionStep& step,
                            const std::string& time) {
  SessionReading reading{step.key, std::nullopt, time, std::nullopt};
  std::string word = line;
  word.erase(0, word.find_first_not_of(" \t"));
  word.erase(word.find_last_not_of(" \t\r") + 1);
  if (word == "skip" || word == "missing") return reading;
  const std::vector<std::string> fields = fields_of(word);
  if (fields.size() != 3 && fields.size() != 4)
    throw InputError({"reading", 0, 0, step.key},
                     fmt::format("expected 'x y z' in mm (and optionally the temperature in °C) "
                                 "or 'skip', got '{}'",
                                 word));
  Eigen::Vector3d p;
  for (int k = 0; k < 3; ++k)
    p[k] = parse_number(fields[static_cast<size_t>(k)], '.',
                        {"reading", 0, k + 1, std::string(1, "xyz"[k])}, "a coordinate in mm");
  reading.position_mm = p;
  if (fields.size() == 4)
    reading.temperature_c =
        parse_number(fields[3], '.', {"reading", 0, 4, "temperature"}, "a temperature in °C");
  return reading;
}

std::string journal_line(const SessionReading& r) {
  std::string line = r.key;
  if (r.position_mm)
    line += fmt::format(",{},{},{},{}", r.position_mm->x(), r.position_mm->y(), r.position_mm->z(),
                        r.time);
  else
    line += ",missing," + r.time;
  if (r.temperature_c) line += fmt::format(",{}", *r.temperature_c);
  return line + "\n";
}

std::vector<SessionReading> replay_journal(const std::string& text, const std::string& file,
                                           const std::vector<SessionStep>& steps,
                                           size_t* complete_bytes) {
  std::vector<SessionReading> readings;
  size_t start = 0;
  int line_number = 0;
  while (start < text.size()) {
    const size_t newline = text.find('\n', start);
    if (newline == std::string::npos) break;  // torn by a crash: not an answer
    const std::string line = text.substr(start, newline - start);
    ++line_number;
    const SourceLocation where{file, line_number, 0, ""};
    const std::vector<std::string> f = fields_of(line);
    if (readings.size() >= steps.size())
      throw InputError(
          where, "more readings than the plan has steps: is this the journal of another plan?");
    const SessionStep& step = steps[readings.size()];
    if (f.empty() || f[0] != step.key)
      throw InputError(where, fmt::format("expected the reading of step '{}', found '{}': the "
                                          "journal belongs to another plan",
                                          step.key, f.empty() ? "" : f[0]));
    SessionReading r{step.key, std::nullopt, "", std::nullopt};
    if (f.size() >= 3 && f[1] == "missing") {
      r.time = f[2];
    } else if (f.size() == 5 || f.size() == 6) {
      Eigen::Vector3d p;
      for (size_t k = 0; k < 3; ++k)
        p[static_cast<Eigen::Index>(k)] = parse_number(f[k + 1], '.', where, "a coordinate in mm");
      r.position_mm = p;
      r.time = f[4];
      if (f.size() == 6) r.temperature_c = parse_number(f[5], '.', where, "a temperature in °C");
    } else {
      throw InputError(where, "expected key,x,y,z,time[,temperature] or key,missing,time");
    }
    readings.push_back(std::move(r));
    start = newline + 1;
  }
  if (complete_bytes) *complete_bytes = start;
  return readings;
}

SessionResult session_result(const SessionSettings& settings, const std::vector<SessionStep>& steps,
                             const std::vector<SessionReading>& readings) {
  SessionResult result;
  result.measurements.kind = MeasurementKind::Points;
  std::optional<Eigen::Vector3d> first_reference;
  for (size_t i = 0; i < readings.size() && i < steps.size(); ++i) {
    const SessionStep& step = steps[i];
    const SessionReading& r = readings[i];
    const PlannedConfiguration& config = settings.configs[static_cast<size_t>(step.config)];
    if (step.drift_check) {
      if (!r.position_mm) continue;
      if (!first_reference)
        first_reference = r.position_mm;
      else
        result.drift.push_back(
            {step.key, (*r.position_mm - *first_reference).norm(), r.time, r.temperature_c});
      continue;
    }
    if (!r.position_mm) {
      result.missing.push_back(config.name);
      continue;
    }
    PointMeasurement m;
    m.config = config.name;
    m.target = config.target;
    m.joints = config.joints;
    m.approach = config.approach;
    m.payload = config.payload;
    m.temperature_c = r.temperature_c;  // the thermal group's input (§8)
    m.position_mm = *r.position_mm;
    m.line = static_cast<int>(i) + 1;
    result.measurements.points.push_back(m);
  }
  return result;
}

}  // namespace robcal::campaign
