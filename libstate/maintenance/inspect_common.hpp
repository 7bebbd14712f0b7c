// PRIVATE to the maintenance module: names of catalogue enums as written in reports, and
// helpers shared by the inspect_*.cc files. Exposes nlohmann::json, hence .hpp.
#pragma once

#include "catalogue/catalogue.h"
#include "maintenance/inspect.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <string_view>

namespace hapstate::inspect_detail {

using Json = nlohmann::ordered_json;

const char* checkpoint_class_name(CheckpointClass c);      // "workspace", "free", ...
const char* config_status_name(ConfigStatus s);            // "open", "expanded", "merged"
const char* transition_outcome_name(TransitionOutcome o);  // "reached", "outside_grid", "failed"

// Opens the catalogue of `dir` read-only.
Catalogue open_read_only(const StateDir& dir);

// First column of the first row of a query that returns one integer (0 if NULL / no row).
std::int64_t query_int(Catalogue& catalogue, const std::string& sql);

// Stage-run fields as JSON (times in Unix ms; ended_ms null while running).
Json stage_run_json(const StageRun& run);

// Pretty JSON with a final newline.
std::string dump(const Json& json);

// "%.6g" of a number.
std::string num(double value);

}  // namespace hapstate::inspect_detail
