#include "maintenance/inspect_common.hpp"

#include <cstdio>
#include <variant>

namespace hapstate::inspect_detail {

const char* checkpoint_class_name(CheckpointClass c) {
  switch (c) {
    case CheckpointClass::kUnclassified:
      return "unclassified";
    case CheckpointClass::kWorkspace:
      return "workspace";
    case CheckpointClass::kOutsideWorkspace:
      return "outside_workspace";
    case CheckpointClass::kFree:
      return "free";
    case CheckpointClass::kInsideBody:
      return "inside_body";
  }
  return "unknown";
}

const char* config_status_name(ConfigStatus s) {
  switch (s) {
    case ConfigStatus::kOpen:
      return "open";
    case ConfigStatus::kExpanded:
      return "expanded";
    case ConfigStatus::kMerged:
      return "merged";
  }
  return "unknown";
}

const char* transition_outcome_name(TransitionOutcome o) {
  switch (o) {
    case TransitionOutcome::kReached:
      return "reached";
    case TransitionOutcome::kOutsideGrid:
      return "outside_grid";
    case TransitionOutcome::kFailed:
      return "failed";
  }
  return "unknown";
}

Catalogue open_read_only(const StateDir& dir) {
  return Catalogue(dir.catalogue(), OpenMode::kReadOnly);
}

std::int64_t query_int(Catalogue& catalogue, const std::string& sql) {
  const QueryResult r = catalogue.query_read_only(sql);
  if (r.rows.empty() || r.rows.front().empty()) return 0;
  const QueryValue& v = r.rows.front().front();
  if (const auto* i = std::get_if<std::int64_t>(&v)) return *i;
  if (const auto* d = std::get_if<double>(&v)) return static_cast<std::int64_t>(*d);
  return 0;
}

Json stage_run_json(const StageRun& run) {
  Json j;
  j["id"] = run.id.value();
  j["stage"] = run.stage;
  j["outcome"] = stage_outcome_name(run.outcome);
  j["started_ms"] = run.started.time_since_epoch().count();
  j["ended_ms"] = run.ended ? Json(run.ended->time_since_epoch().count()) : Json(nullptr);
  j["message"] = run.message;
  return j;
}

std::string dump(const Json& json) { return json.dump(2) + "\n"; }

std::string num(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

}  // namespace hapstate::inspect_detail
