#include "robcal/core/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace robcal {

namespace {
std::atomic<bool> g_enabled{false};
constexpr auto kRedrawInterval = std::chrono::milliseconds(100);
}  // namespace

void enable_terminal_progress(bool on) {
  g_enabled = on;
}

bool terminal_progress_active() {
  return g_enabled && ::isatty(STDERR_FILENO) == 1;
}

Progress::Progress(std::string label, std::int64_t total)
    : label_(std::move(label)),
      total_(std::max<std::int64_t>(total, 1)),
      active_(terminal_progress_active()) {
  if (active_) draw(0);
}

Progress::~Progress() {
  if (!active_) return;
  std::fprintf(stderr, "\r\033[K");  // erase the line: what follows is the command's output
  std::fflush(stderr);
}

void Progress::advance(std::int64_t steps) {
  const std::int64_t done = done_.fetch_add(steps, std::memory_order_relaxed) + steps;
  if (!active_) return;
  // A thread that finds another drawing skips: the next step draws soon enough.
  std::unique_lock lock(draw_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < kRedrawInterval && done < total_) return;
  last_draw_ = now;
  draw(done);
}

void Progress::draw(std::int64_t done) {
  const std::int64_t shown = std::min(done, total_);
  std::fprintf(stderr, "\r\033[K%s  %lld/%lld  %3d%%", label_.c_str(),
               static_cast<long long>(shown), static_cast<long long>(total_),
               static_cast<int>(100 * shown / total_));
  std::fflush(stderr);
}

}  // namespace robcal
