// A progress line for long work: "label: done/total (pct), rate/s, ETA, failures".
// Printed to a stream at most once per `interval_s` (and at finish()); on a terminal the line
// is rewritten in place, otherwise one line per update. Not thread-safe.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace hapstate {

class Progress {
 public:
  Progress(std::string label, long long total, std::FILE* out = stderr, double interval_s = 1.0);
  // Records that `done` items are finished (cumulative) and `failures` of them failed.
  void update(long long done, long long failures = 0);
  // Prints the final line (always) with the total elapsed time.
  void finish();

 private:
  void print(bool final);

  std::string label_;
  long long total_, done_ = 0, failures_ = 0;
  std::FILE* out_;
  double interval_s_;
  bool tty_;
  std::chrono::steady_clock::time_point start_, last_print_;
};

// "1h02m", "3m05s", "12.3s".
std::string format_duration(double seconds);

}  // namespace hapstate
