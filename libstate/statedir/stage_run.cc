#include "statedir/stage_run.h"

#include "catalogue/transaction.h"
#include "util/stop_request.h"

#include <algorithm>
#include <stdexcept>

namespace hapstate {

TimeMs now_ms() { return std::chrono::time_point_cast<std::chrono::milliseconds>(Clock::now()); }

StageRunFrame::StageRunFrame(Catalogue& catalogue, std::string stage, NamedHashes inputs,
                             std::string parameters, std::chrono::steady_clock::time_point started)
    : catalogue_(catalogue), started_(started) {
  std::sort(inputs.begin(), inputs.end());
  run_.stage = std::move(stage);
  run_.inputs = std::move(inputs);
  run_.parameters = std::move(parameters);
  run_.started = now_ms();
  run_.outcome = StageOutcome::kRunning;
  last_ = catalogue_.last_successful_stage_run(run_.stage);
}

bool StageRunFrame::same_as_last(const std::vector<std::string>& names) const {
  if (!last_) return false;
  return std::all_of(names.begin(), names.end(), [&](const std::string& name) {
    return run_input(*last_, name) == run_input(run_, name);
  });
}

int StageRunFrame::close_interrupted_runs() {
  int closed = 0;
  for (const StageRun& old : catalogue_.read_stage_runs(run_.stage)) {
    if (old.outcome != StageOutcome::kRunning || old.id == id_) continue;
    catalogue_.update_stage_run_end(old.id, StageOutcome::kFailed, now_ms(),
                                    "interrupted: the process ended before finishing (killed?); "
                                    "resumed by a later run");
    ++closed;
  }
  return closed;
}

void StageRunFrame::record_unchanged(StageReport& report, const std::string& message) {
  report.outcome = StageOutcome::kUnchanged;
  report.message = message;
  end(report);
}

void StageRunFrame::start(StageReport& report) {
  Transaction tx(catalogue_);
  report.interrupted_runs += close_interrupted_runs();
  id_ = catalogue_.insert_stage_run(run_);
  tx.commit();
}

void StageRunFrame::end(StageReport& report) {
  if (ended_) throw std::logic_error("StageRunFrame::end: the run " + run_.stage + " ended twice");
  ended_ = true;
  report.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  if (id_.valid()) {
    catalogue_.update_stage_run_end(id_, report.outcome, now_ms(), report.message);
    return;
  }
  // Not started: the ended run, in the caller's transaction if one is open, else in its own.
  std::optional<Transaction> tx;
  if (!catalogue_.in_transaction()) tx.emplace(catalogue_);
  report.interrupted_runs += close_interrupted_runs();
  StageRun run = run_;
  run.outcome = report.outcome;
  run.ended = now_ms();
  run.message = report.message;
  catalogue_.insert_stage_run(run);
  if (tx) tx->commit();
}

void StageRunFrame::fail(const std::string& message) noexcept {
  try {
    // Not started: the ended row (import, grid) is rolled back with the stage's transaction.
    if (id_.valid()) catalogue_.update_stage_run_end(id_, StageOutcome::kFailed, now_ms(), message);
  } catch (...) {
  }
}

bool StageRunFrame::stop(StageReport& report) {
  if (!stop_requested()) return false;
  report.stopped_by_signal = true;
  report.outcome = StageOutcome::kPartial;
  return true;
}

}  // namespace hapstate
