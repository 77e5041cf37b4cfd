#pragma once
/// \file
/// The guided measurement session of the ballbar hexapod (docs/method/08-world-frame.md §3,
/// published procedure): the tool sides, the base sides once the robot has placed the base cups,
/// then the six legs of every planned configuration, with re-checks of the ballbar on its
/// calibrator. A plan with a fourth tool cup (tool_cup4_mm) adds its three distances after the tool
/// sides and its legs to each configuration's six; a fourth base cup (base_cup4_mm) likewise after
/// the base sides.
///
/// The session is a deterministic script: the next step depends only on the plan and the
/// readings so far. Every reading goes to an append-only journal (one JSON object per line,
/// flushed and synced at once), so replaying the journal restores the exact state after a crash
/// or Ctrl-C and `--resume` continues where it stopped.

#include <array>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robcal/hexapod/poses.hpp"
#include "robcal/io/journal_file.hpp"

namespace robcal::hexapod {

/// One robot configuration to measure: a pose of the device reached with given joints.
struct SessionConfiguration {
  int id = 0;                      ///< 1-based, as shown to the operator
  std::string pose;                ///< pose label ("P07")
  std::string labels;              ///< "front/up/no-flip" (may be empty)
  int mode = 0;                    ///< planned assembly mode 1..4 (0: not given)
  std::vector<double> joints_deg;  ///< controller joints (may be empty: pose-only plans)
  /// The six of the design in measurement order, then the extra legs (to a fourth cup).
  std::vector<PhysicalLeg> legs;
};

/// What the session needs from a plan.
struct SessionPlan {
  double tool_nominal_mm = 150;  ///< ballbar set-up for the tool sides
  double leg_mm = 300;           ///< ballbar set-up for the base sides and the legs
  double range_mm = 1.0;         ///< the ballbar reads only within ±range of its set-up length
  int recheck_every = 5;         ///< configurations between calibrator re-checks (0: never)
  /// The design distances d14, d24, d34 of a fourth tool cup T4 (the ballbar's set-up for each
  /// when the session measures them); legs may then name T4.
  std::optional<std::array<double, 3>> tool_cup4_mm{};
  /// The design distances d14, d24, d34 of a fourth base cup B4, as T4's; legs may then name B4.
  std::optional<std::array<double, 3>> base_cup4_mm{};
  std::vector<SessionConfiguration> configurations;
  /// The cell as planned, for calibrating from the session (absent from hand-written plans):
  /// where the robot put the setting ball for B1..B3 (robot frame, mm) and the tool fixture frame
  /// in the flange frame.
  std::optional<Cups<double>> setting_points;
  std::optional<Eigen::Vector3d> setting_point4;  ///< B4's, with setting_points and base_cup4_mm
  std::optional<Pose<double>> flange_T_tool;
  /// Fixture sides measured in an earlier session of the same cell (a re-plan): not asked again.
  std::optional<FixtureDistances> tool_sides;  ///< with T4's distances when the plan has T4
  std::optional<FixtureDistances> base_sides;  ///< with B4's distances when the plan has B4
};

/// Reads a plan file (JSON written by `robcal hexapod plan`); errors name the file and key.
SessionPlan load_session_plan(const std::filesystem::path& path);
SessionPlan parse_session_plan(const nlohmann::json& root, const std::string& file);

enum class StepKind { ToolSide, BaseSide, Leg, CalibratorCheck };

struct SessionStep {
  StepKind kind = StepKind::Leg;
  std::string key;        ///< stable identity, checked on resume: "tool/T1-T2", "leg/12/B1-T1"
  std::string prompt;     ///< what the operator is asked
  int configuration = 0;  ///< index into plan.configurations for legs (else -1)
  int item = 0;  ///< fixture distance (FixtureDistances::values order) or leg of the configuration
  double nominal_mm = 0;  ///< set-up length the reading must be within range of
};

/// Readings of one configuration.
struct ConfigurationReadings {
  std::vector<std::optional<double>> legs;  ///< mm, in the order of the configuration's legs
  bool retry =
      false;  ///< a leg was out of the ballbar's range: retry after preliminary calibration
};

/// The state of a session: everything read so far.
struct SessionState {
  std::vector<std::optional<double>> tool_sides;  ///< FixtureDistances::values order (3 or 6)
  std::vector<std::optional<double>> base_sides;  ///< FixtureDistances::values order (3 or 6)
  std::vector<ConfigurationReadings> configurations;
  std::vector<std::pair<int, double>> calibrator_checks;  ///< (after configuration id, reading)
};

/// The session script over a plan.
class Session {
 public:
  explicit Session(SessionPlan plan);

  /// The next step, or nullopt when the session is complete.
  [[nodiscard]] std::optional<SessionStep> next_step() const;

  /// Records the answer to the current step. `reading` is nullopt when the operator reports the
  /// ballbar out of range (for a leg). A leg reading outside ±range marks the configuration
  /// for retry and skips its remaining legs. Returns a message for the operator (may be empty).
  /// Throws InputError when a side or calibrator reading is missing or out of range.
  std::string record(const std::optional<double>& reading);

  [[nodiscard]] const SessionState& state() const { return state_; }
  [[nodiscard]] const SessionPlan& plan() const { return plan_; }

  /// The result as JSON: sides, every configuration's legs and status, calibrator checks.
  [[nodiscard]] nlohmann::json result_json() const;

 private:
  [[nodiscard]] bool configuration_done(size_t c) const;
  [[nodiscard]] bool recheck_due_after(size_t c) const;

  SessionPlan plan_;
  SessionState state_;
};

/// Append-only journal of a session. Each line: {"key": …, "reading": number | null}.
class SessionJournal {
 public:
  /// Creates a new journal (fails if the file exists, so a session is never overwritten) or
  /// opens an existing one for resuming. Throws InputError naming the path.
  static SessionJournal create(const std::filesystem::path& path);
  static SessionJournal open_for_resume(const std::filesystem::path& path);

  /// Replays the journal into a fresh session: returns how many entries were applied. A last
  /// line cut short by a crash is ignored (and removed); a key that does not match the script
  /// is an InputError (the journal belongs to another plan).
  int replay(Session& session);

  /// The same replay without opening the journal for writing (a cut-short last line is ignored
  /// and left in place): for reading a session's data.
  static int replay_read_only(const std::filesystem::path& path, Session& session);

  /// Appends one entry and flushes it to the disk before returning.
  void append(const std::string& key, const std::optional<double>& reading);

  SessionJournal(SessionJournal&& other) noexcept = default;
  SessionJournal& operator=(SessionJournal&&) = delete;

 private:
  explicit SessionJournal(JournalFile file) : file_(std::move(file)) {}
  JournalFile file_;  ///< create, lock, append + sync, resume: shared with the point session
};

}  // namespace robcal::hexapod
