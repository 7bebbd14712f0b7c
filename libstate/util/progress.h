// A progress line for long work: "label: done/total (pct), rate/s, ETA, failures".
// Printed to a stream at most once per `interval_s` (and at finish()); on a terminal the line
// is rewritten in place, otherwise one line per update and at most one per 10 s (a log). Not
// thread-safe.
// The rate and the ETA are those of the recent work (the last quarter of the elapsed time, at
// least 5 s), not of the whole run: work whose items get slower (the later waves of a contact
// expansion) is not promised at its early speed. The percentage never goes down: when a new
// estimate of the total grows, it holds until the work catches up (issue 42).
#pragma once

#include <chrono>
#include <cstdio>
#include <deque>
#include <string>
#include <utility>

namespace hapstate {

class Progress {
 public:
  Progress(std::string label, long long total, std::FILE* out = stderr, double interval_s = 1.0);
  // Work finished before this process started (a resumed run): counted in done/total, not in
  // the rate.
  void set_resumed(long long done_before);
  // A new estimate of the whole job; `estimate` prints it as "~total" and the ETA as "ETA ~".
  void set_total(long long total, bool estimate);
  // The seconds left as a model of the work estimates them (the expansion's per-wave costs):
  // replaces the rate's ETA until the next call; it counts down with the clock in between. A
  // negative value returns to the rate's ETA.
  void set_eta(double seconds);
  // Text printed after the numbers (for example the current wave).
  void set_note(std::string note) { note_ = std::move(note); }
  // Records that `done` items are finished (cumulative, resumed ones included) and `failures`
  // of them failed.
  void update(long long done, long long failures = 0);
  // Prints the final line (always) with the total elapsed time.
  void finish();
  // The line as it would be printed now (what print writes; it counts as shown for the
  // never-backwards percentage).
  std::string line(bool final = false);

 private:
  void print(bool final);
  // Items per second over the recent window (the whole run until it is long enough).
  double recent_rate(std::chrono::steady_clock::time_point now);

  std::string label_, note_;
  long long total_, done_ = 0, done_before_ = 0, failures_ = 0;
  bool estimate_ = false;
  std::FILE* out_;
  bool tty_;
  double interval_s_;
  std::chrono::steady_clock::time_point start_, last_print_;
  double shown_pct_ = 0;  // the largest percentage printed so far
  double eta_ = -1;       // set_eta's seconds (negative: none), at eta_set_
  std::chrono::steady_clock::time_point eta_set_;
  // (seconds since start, done) at each update, oldest first; older than the window dropped.
  std::deque<std::pair<double, long long>> samples_;
};

// "1h02m", "3m05s", "12.3s"; ">1000h" from 1000 hours on; "?" for a negative or non-finite time.
std::string format_duration(double seconds);

}  // namespace hapstate
