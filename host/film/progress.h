// Terminal progress line and the duration formatting shared with the stats summary.
#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace aw {

// isatty(2): the caller passes this as ProgressLine's `enabled`, so redirected/CI output
// stays free of carriage-return noise.
bool stderr_is_terminal();

// Whole seconds, truncated like a stopwatch: "0:03", "12:34", "1:02:03" (hours are not
// wrapped into days: "27:00:00"). With allow_subsecond, durations below one second are
// shown as "0.35 s", and below 10 ms as "3.20 ms", since "0:00" says nothing there.
// Negative values count as 0; NaN/Inf give "--:--".
std::string format_duration(double seconds, bool allow_subsecond = false);

// One stderr line rewritten in place with '\r':
//   "rendering  42.0%  elapsed 0:03  ETA 0:04  1.23 Msamples/s"
// update() redraws at most every 200 ms (the first call always draws); finish() draws the
// final state and ends the line with '\n'. With enabled == false nothing is ever written.
// update() may be called from any one thread at a time or concurrently; it is locked.
class ProgressLine {
 public:
  ProgressLine(std::string label, uint64_t total_samples, bool enabled);
  // Calls finish(), so an exception that unwinds past a render still leaves the terminal
  // on a fresh line for its error message.
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // done_samples is cumulative; values above total_samples are shown as 100%.
  void update(uint64_t done_samples);
  // Idempotent; update() after finish() is ignored.
  void finish();
  // Text shown after the rate, e.g. "checkpoint 3 written"; "" shows nothing.
  void set_note(const std::string& note);

  // The text update()/finish() would draw, without '\r'; exposed for tests.
  std::string format_line(uint64_t done_samples, double elapsed_seconds) const;

 private:
  using Clock = std::chrono::steady_clock;
  void draw_locked(Clock::time_point now);

  std::string label_;
  std::string note_;
  uint64_t total_;
  bool enabled_;
  bool finished_ = false;
  bool drawn_ = false;
  uint64_t done_ = 0;
  size_t last_len_ = 0;
  Clock::time_point start_, last_draw_;
  std::mutex mutex_;
};

}  // namespace aw
