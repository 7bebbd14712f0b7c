#include "util/progress.h"

#include <unistd.h>

#include <cmath>

namespace hapstate {

std::string format_duration(double seconds) {
  char buf[64];
  if (!std::isfinite(seconds) || seconds < 0) return "?";
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
      interval_s_(interval_s),
      tty_(out != nullptr && isatty(fileno(out))),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

void Progress::update(long long done, long long failures) {
  done_ = done;
  failures_ = failures;
  const auto now = std::chrono::steady_clock::now();
  if (done_ < total_ && std::chrono::duration<double>(now - last_print_).count() >= interval_s_) {
    last_print_ = now;
    print(false);
  }
}

void Progress::finish() { print(true); }

void Progress::print(bool final) {
  if (out_ == nullptr) return;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0 ? done_ / elapsed : 0;
  const double pct = total_ > 0 ? 100.0 * done_ / total_ : 100.0;
  std::string tail = final ? "elapsed " + format_duration(elapsed)
                           : "ETA " + format_duration(rate > 0 ? (total_ - done_) / rate : -1);
  std::fprintf(out_, "%s%s: %lld/%lld (%.0f%%), %.2f/s, %s, failures %lld%s", tty_ ? "\r" : "",
               label_.c_str(), done_, total_, pct, rate, tail.c_str(), failures_,
               tty_ && !final ? "   " : "\n");
  std::fflush(out_);
}

}  // namespace hapstate
