#pragma once
/// \file
/// Progress of long computations, for a person watching a terminal. The library's loops that
/// can take more than a second (candidate generation and selection, Monte Carlo runs, plan
/// studies, cross-validation folds) count their steps through a Progress; it draws one line on
/// stderr, at most ten times a second, only when terminal progress is enabled (the CLI enables
/// it; library users and Python stay quiet by default) and stderr is a terminal. Nothing it
/// does changes a result.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace robcal {

/// Turns the progress line on or off for the whole process (off by default).
void enable_terminal_progress(bool on);

/// True when progress lines are drawn: enabled and stderr is a terminal.
bool terminal_progress_active();

/// One task's progress: "label  123/500  25%". Counting is thread-safe; the line is cleared
/// when the task ends (destructor).
class Progress {
 public:
  Progress(std::string label, std::int64_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Counts `steps` more done (from any thread) and redraws when due.
  void advance(std::int64_t steps = 1);

 private:
  void draw(std::int64_t done);

  std::string label_;
  std::int64_t total_;
  bool active_;
  std::atomic<std::int64_t> done_{0};
  std::mutex draw_mutex_;
  std::chrono::steady_clock::time_point last_draw_{};
};

}  // namespace robcal
