// The one frame every stage runs in (import, grid, expand, refine, index, certify and compact):
// its run recorded in the catalogue (table stage_run: what it consumed, how it ended, so a
// re-run can skip and a user can audit), the runs a crash left "running" closed, the stop
// request (Ctrl-C, SIGTERM) polled, the time taken, and one report type, StageReport, which each
// stage's report extends with its counts. The directory's lock is taken by whoever opens the
// catalogue for writing (StageContext, or the import and compact stages themselves).
#pragma once

#include "catalogue/catalogue.h"
#include "statedir/scene_identity.h"
#include "statedir/state_dir.h"

#include <chrono>
#include <exception>
#include <optional>
#include <string>
#include <vector>

namespace hapstate {

// What every stage reports; a stage's own report derives from it and adds its counts.
struct StageReport {
  // kOk: done; kPartial: stopped (a signal or a limit) with work left, run again to go on;
  // kUnchanged: nothing to do (the one way a stage says so).
  StageOutcome outcome = StageOutcome::kOk;
  bool stopped_by_signal = false;     // kPartial because of Ctrl-C / SIGTERM
  int interrupted_runs = 0;           // earlier runs a crash left "running", now marked failed
  double wall_s = 0;                  // the stage's wall time, set at its end
  std::string message;                // one line for the user (also stored with the run)
  std::vector<std::string> warnings;  // things the user should know (mesh repairs and the like)

  bool unchanged() const { return outcome == StageOutcome::kUnchanged; }
};

// Now, as stored in stage_run (ms since the Unix epoch, UTC).
TimeMs now_ms();

// One run of `stage` with its inputs and parameters. The life of a run, always the same:
//   StageRunFrame frame(catalogue, "grid", inputs, parameters);
//   if (<the last run had these inputs>) return frame.unchanged(report, "...");
//   frame.run(report, [&] { ... work, polling frame.stop(report) ... });   (or start()/end())
// A stage whose work is one transaction may instead call end() inside that transaction without
// start(): the run is then recorded with its work or not at all (import: a directory whose import
// run is missing was never imported).
class StageRunFrame {
 public:
  // `started`: when the stage began (its report's wall_s counts from there).
  StageRunFrame(Catalogue& catalogue, std::string stage, NamedHashes inputs, std::string parameters,
                std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now());

  // Whether the last successful run recorded the same hash as this one for every name in
  // `names` (false without a last run).
  bool same_as_last(const std::vector<std::string>& names) const;

  // Nothing to do: records the run as ended now with outcome kUnchanged and `message`, in one
  // transaction with closing the runs of this stage a crash left "running" (a run killed after
  // it had done all its work leaves nothing to do, and its row must not stay "running"); sets
  // the report's outcome, message and time. Returns `report`.
  template <typename Report>
  Report unchanged(Report report, const std::string& message) {
    record_unchanged(report, message);
    return report;
  }

  // Starts recording: the run inserted as running, in one transaction with closing the runs of
  // this stage a crash left "running" (marked failed "interrupted: ..."; the caller holds the
  // directory's lock, so they are not running); counts those in report.interrupted_runs.
  void start(StageReport& report);

  // Records the end: the report's outcome and message, ended now; sets report.wall_s. Updates
  // the row start() inserted, or (not started) inserts the ended run, closing interrupted ones.
  // Once per run (std::logic_error otherwise).
  void end(StageReport& report);

  // start(), body(), end(); if body (or the end's record) throws, the run is recorded as failed
  // with the exception's message (best effort: a catalogue that cannot be written is not hidden
  // behind a second error) and the exception goes on.
  template <typename Body>
  void run(StageReport& report, Body&& body) {
    start(report);
    try {
      body();
      end(report);
    } catch (const std::exception& e) {
      fail(e.what());
      throw;
    }
  }

  // Whether a stop was requested (Ctrl-C, SIGTERM: util/stop_request.h); if so the report
  // becomes kPartial, stopped by a signal. Long stages poll it between units of work.
  static bool stop(StageReport& report);

 private:
  void record_unchanged(StageReport& report, const std::string& message);
  void fail(const std::string& message) noexcept;
  int close_interrupted_runs();

  Catalogue& catalogue_;
  StageRun run_;
  std::optional<StageRun> last_;  // the newest successful run of this stage before this one
  StageRunId id_;                 // invalid until start()
  bool ended_ = false;            // end() was called
  std::chrono::steady_clock::time_point started_;
};

}  // namespace hapstate
