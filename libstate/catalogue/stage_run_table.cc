// Tables stage_run and stage_run_input.
#include "catalogue/catalogue_impl.hpp"
#include "util/error.h"
#include "util/version.h"

#include <algorithm>

namespace hapstate {
namespace {

constexpr const char* kInsertRun =
    "INSERT INTO stage_run (id, stage, parameters, hapstate_version, started_ms, ended_ms, "
    "outcome, message) VALUES (?, ?, ?, ?, ?, ?, ?, ?)";
constexpr const char* kInsertInput =
    "INSERT INTO stage_run_input (run, name, hash) VALUES (?, ?, ?)";
constexpr const char* kUpdateEnd =
    "UPDATE stage_run SET outcome = ?, ended_ms = ?, message = ? WHERE id = ?";
constexpr const char* kReadRun =
    "SELECT id, stage, parameters, hapstate_version, started_ms, ended_ms, outcome, message "
    "FROM stage_run WHERE id = ?";
constexpr const char* kReadRunsOfStage =
    "SELECT id, stage, parameters, hapstate_version, started_ms, ended_ms, outcome, message "
    "FROM stage_run WHERE stage = ? ORDER BY id";
constexpr const char* kLastSuccessful =
    "SELECT id FROM stage_run WHERE stage = ? AND outcome IN ('ok', 'unchanged') "
    "ORDER BY id DESC LIMIT 1";
constexpr const char* kReadInputs =
    "SELECT name, hash FROM stage_run_input WHERE run = ? ORDER BY name";

StageOutcome parse_outcome(const std::string& text, const std::string& where) {
  for (auto o : {StageOutcome::kRunning, StageOutcome::kOk, StageOutcome::kUnchanged,
                 StageOutcome::kPartial, StageOutcome::kFailed}) {
    if (text == stage_outcome_name(o)) return o;
  }
  throw InputError(where + ": unknown stage outcome '" + text + "'");
}

StageRun row_to_run(const catalogue_detail::Statement& s, const std::string& label) {
  StageRun run;
  run.id = StageRunId(s.column_int(0));
  run.stage = s.column_text(1);
  run.parameters = s.column_text(2);
  run.hapstate_version = s.column_text(3);
  run.started = TimeMs(std::chrono::milliseconds(s.column_int(4)));
  if (!s.is_null(5)) run.ended = TimeMs(std::chrono::milliseconds(s.column_int(5)));
  run.outcome =
      parse_outcome(s.column_text(6), label + ": stage_run " + std::to_string(run.id.value()));
  run.message = s.column_text(7);
  return run;
}

}  // namespace

const char* stage_outcome_name(StageOutcome outcome) {
  switch (outcome) {
    case StageOutcome::kRunning:
      return "running";
    case StageOutcome::kOk:
      return "ok";
    case StageOutcome::kUnchanged:
      return "unchanged";
    case StageOutcome::kPartial:
      return "partial";
    case StageOutcome::kFailed:
      return "failed";
  }
  return "failed";
}

StageRunId Catalogue::insert_stage_run(const StageRun& run) {
  catalogue_detail::Savepoint savepoint(*impl_->db);
  StageRunId id;
  {
    catalogue_detail::StatementUse s(impl_->statement(kInsertRun));
    if (run.id.valid()) {
      s->bind(1, run.id.value());
    } else {
      s->bind_null(1);
    }
    s->bind(2, run.stage);
    s->bind(3, run.parameters);
    s->bind(4, run.hapstate_version.empty() ? std::string_view(version_string())
                                            : std::string_view(run.hapstate_version));
    s->bind(5, static_cast<std::int64_t>(run.started.time_since_epoch().count()));
    if (run.ended) {
      s->bind(6, static_cast<std::int64_t>(run.ended->time_since_epoch().count()));
    } else {
      s->bind_null(6);
    }
    s->bind(7, std::string_view(stage_outcome_name(run.outcome)));
    s->bind(8, run.message);
    s->run();
    id = StageRunId(sqlite3_last_insert_rowid(impl_->db->get()));
  }
  for (const auto& [name, hash] : run.inputs) {
    catalogue_detail::StatementUse s(impl_->statement(kInsertInput));
    s->bind(1, id.value());
    s->bind(2, name);
    s->bind(3, hash.hex());
    s->run();
  }
  savepoint.release();
  return id;
}

void Catalogue::update_stage_run_end(StageRunId id, StageOutcome outcome, TimeMs ended,
                                     std::string_view message) {
  catalogue_detail::StatementUse s(impl_->statement(kUpdateEnd));
  s->bind(1, std::string_view(stage_outcome_name(outcome)));
  s->bind(2, static_cast<std::int64_t>(ended.time_since_epoch().count()));
  s->bind(3, message);
  s->bind(4, id.value());
  s->run();
  if (sqlite3_changes(impl_->db->get()) != 1) {
    throw InputError(impl_->label() + ": no stage_run with id " + std::to_string(id.value()));
  }
}

StageRun Catalogue::read_stage_run(StageRunId id) {
  StageRun run;
  {
    catalogue_detail::StatementUse s(impl_->statement(kReadRun));
    s->bind(1, id.value());
    if (!s->step()) {
      throw InputError(impl_->label() + ": no stage_run with id " + std::to_string(id.value()));
    }
    run = row_to_run(*s, impl_->label());
  }
  catalogue_detail::StatementUse s(impl_->statement(kReadInputs));
  s->bind(1, id.value());
  while (s->step())
    run.inputs.emplace_back(s->column_text(0), ContentHash::from_hex(s->column_text(1)));
  return run;
}

std::vector<StageRun> Catalogue::read_stage_runs(std::string_view stage) {
  std::vector<StageRunId> ids;
  {
    catalogue_detail::StatementUse s(impl_->statement(kReadRunsOfStage));
    s->bind(1, stage);
    while (s->step()) ids.push_back(StageRunId(s->column_int(0)));
  }
  std::vector<StageRun> runs;
  runs.reserve(ids.size());
  for (StageRunId id : ids) runs.push_back(read_stage_run(id));
  return runs;
}

std::optional<StageRun> Catalogue::last_successful_stage_run(std::string_view stage) {
  StageRunId id;
  {
    catalogue_detail::StatementUse s(impl_->statement(kLastSuccessful));
    s->bind(1, stage);
    if (!s->step()) return std::nullopt;
    id = StageRunId(s->column_int(0));
  }
  return read_stage_run(id);
}

}  // namespace hapstate
