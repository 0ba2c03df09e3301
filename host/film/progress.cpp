#include "host/film/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <utility>

namespace aw {
namespace {

constexpr auto kMinRedrawInterval = std::chrono::milliseconds(200);

std::string format_rate(double per_second) {
  if (!std::isfinite(per_second) || per_second < 0.0) return "-- samples/s";
  static const char* const prefixes[] = {"", "k", "M", "G", "T"};
  int i = 0;
  while (per_second >= 1000.0 && i < 4) {
    per_second /= 1000.0;
    ++i;
  }
  char buf[64];
  if (i == 0)
    std::snprintf(buf, sizeof buf, "%.0f samples/s", per_second);
  else
    std::snprintf(buf, sizeof buf, "%.2f %ssamples/s", per_second, prefixes[i]);
  return buf;
}

}  // namespace

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) != 0; }

std::string format_duration(double seconds, bool allow_subsecond) {
  // Beyond ~30 million years the integer conversion below could overflow.
  if (!std::isfinite(seconds) || seconds >= 1e15) return "--:--";
  if (seconds < 0.0) seconds = 0.0;
  char buf[64];
  if (allow_subsecond && seconds < 1.0) {
    if (seconds < 0.01)
      std::snprintf(buf, sizeof buf, "%.2f ms", seconds * 1000.0);
    else
      std::snprintf(buf, sizeof buf, "%.2f s", seconds);
    return buf;
  }
  const uint64_t total = uint64_t(seconds);
  const uint64_t h = total / 3600, m = (total / 60) % 60, s = total % 60;
  if (h > 0)
    std::snprintf(buf, sizeof buf, "%llu:%02llu:%02llu", (unsigned long long)h, (unsigned long long)m,
                  (unsigned long long)s);
  else
    std::snprintf(buf, sizeof buf, "%llu:%02llu", (unsigned long long)m, (unsigned long long)s);
  return buf;
}

ProgressLine::ProgressLine(std::string label, uint64_t total_samples, bool enabled)
    : label_(std::move(label)), total_(total_samples), enabled_(enabled), start_(Clock::now()) {
  last_draw_ = start_;
}

ProgressLine::~ProgressLine() {
  try {
    finish();
  } catch (...) {
    // A destructor must not throw; a lost newline is harmless.
  }
}

std::string ProgressLine::format_line(uint64_t done, double elapsed) const {
  if (done > total_) done = total_;
  // A zero-sample job is complete by definition.
  const double fraction = total_ ? double(done) / double(total_) : 1.0;
  std::string eta = "--:--";
  if (done == total_)
    eta = format_duration(0.0);
  else if (done > 0 && elapsed > 0.0)
    eta = format_duration(elapsed * double(total_ - done) / double(done));
  const double rate = elapsed > 0.0 ? double(done) / elapsed : std::nan("");

  char pct[16];
  std::snprintf(pct, sizeof pct, "%.1f%%", fraction * 100.0);
  return label_ + "  " + pct + "  elapsed " + format_duration(elapsed) + "  ETA " + eta + "  " +
         format_rate(rate) + (note_.empty() ? "" : "  " + note_);
}

void ProgressLine::set_note(const std::string& note) {
  std::lock_guard<std::mutex> lock(mutex_);
  note_ = note;
}

void ProgressLine::draw_locked(Clock::time_point now) {
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  std::string line = format_line(done_, elapsed);
  // A shorter line (e.g. the rate dropping a digit) would leave stale characters behind.
  const size_t len = line.size();
  if (len < last_len_) line.append(last_len_ - len, ' ');
  last_len_ = len;
  std::fprintf(stderr, "\r%s", line.c_str());
  std::fflush(stderr);
  last_draw_ = now;
  drawn_ = true;
}

void ProgressLine::update(uint64_t done_samples) {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  done_ = done_samples;
  const Clock::time_point now = Clock::now();
  if (drawn_ && now - last_draw_ < kMinRedrawInterval) return;
  draw_locked(now);
}

void ProgressLine::finish() {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  finished_ = true;
  draw_locked(Clock::now());
  std::fputc('\n', stderr);
  std::fflush(stderr);
}

}  // namespace aw
