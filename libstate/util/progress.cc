#include "util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace hapstate {

std::string format_duration(double seconds) {
  char buf[64];
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  if (seconds >= 1000 * 3600.0) return ">1000h";  // an estimate that long says nothing more
  if (seconds < 60) {
    std::snprintf(buf, sizeof buf, "%.1fs", seconds);
  } else if (seconds < 3600) {
    std::snprintf(buf, sizeof buf, "%dm%02ds", int(seconds / 60), int(seconds) % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%dh%02dm", int(seconds / 3600), int(seconds / 60) % 60);
  }
  return buf;
}

Progress::Progress(std::string label, long long total, std::FILE* out, double interval_s)
    : label_(std::move(label)),
      total_(total),
      out_(out),
      tty_(out != nullptr && isatty(fileno(out))),
      interval_s_(tty_ ? interval_s : std::max(interval_s, 10.0)),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

void Progress::set_resumed(long long done_before) {
  done_before_ = done_before;
  if (done_ < done_before) done_ = done_before;
}

void Progress::set_total(long long total, bool estimate) {
  total_ = total;
  estimate_ = estimate;
}

void Progress::set_eta(double seconds) {
  eta_ = std::isfinite(seconds) ? seconds : -1;
  eta_set_ = std::chrono::steady_clock::now();
}

void Progress::update(long long done, long long failures) {
  done_ = done;
  failures_ = failures;
  if (out_ == nullptr) return;
  const auto now = std::chrono::steady_clock::now();
  samples_.emplace_back(std::chrono::duration<double>(now - start_).count(), done);
  if (samples_.size() > 4096) recent_rate(now);  // drops the samples older than the window
  if (done_ < total_ && std::chrono::duration<double>(now - last_print_).count() >= interval_s_) {
    last_print_ = now;
    print(false);
  }
}

void Progress::finish() { print(true); }

double Progress::recent_rate(std::chrono::steady_clock::time_point now) {
  constexpr double kWindowFraction = 0.25, kShortestWindow = 5.0;
  const double t = std::chrono::duration<double>(now - start_).count();
  const double window = std::max(kShortestWindow, kWindowFraction * t);
  // Keep the newest sample at or before the window's start, drop the older ones.
  while (samples_.size() > 1 && samples_[1].first <= t - window) samples_.pop_front();
  if (samples_.empty() || t - samples_.front().first < kShortestWindow ||
      samples_.front().second < done_before_)
    return t > 0 ? (done_ - done_before_) / t : 0;
  const double span = t - samples_.front().first;
  return span > 0 ? (done_ - samples_.front().second) / span : 0;
}

void Progress::print(bool final) {
  if (out_ == nullptr) return;
  std::fprintf(out_, "%s%s%s", tty_ ? "\r" : "", line(final).c_str(),
               tty_ && !final ? "   " : "\n");
  std::fflush(out_);
}

std::string Progress::line(bool final) {
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate =
      final ? (elapsed > 0 ? (done_ - done_before_) / elapsed : 0) : recent_rate(now);
  const long long total = std::max(total_, done_);
  // Never backwards: a grown estimate holds the percentage; 100 % only when done.
  double pct = total > 0 ? 100.0 * done_ / total : 100.0;
  if (!final && done_ < total) pct = std::min(99.0, std::max(pct, shown_pct_));
  shown_pct_ = std::max(shown_pct_, pct);
  const char* approx = estimate_ && done_ < total ? "~" : "";
  double left = rate > 0 ? (total - done_) / rate : -1;
  if (eta_ >= 0) left = std::max(0.0, eta_ - std::chrono::duration<double>(now - eta_set_).count());
  const std::string tail = final ? "elapsed " + format_duration(elapsed)
                                 : std::string("ETA ") + approx + format_duration(left);
  std::string failures = failures_ > 0 ? ", failures " + std::to_string(failures_) : "";
  char text[512];
  std::snprintf(text, sizeof text, "%s: %lld/%s%lld (%.0f%%), %.2f/s, %s%s%s%s", label_.c_str(),
                done_, approx, total, pct, rate, tail.c_str(), failures.c_str(),
                note_.empty() ? "" : ", ", note_.c_str());
  return text;
}

}  // namespace hapstate
