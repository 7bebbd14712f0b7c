// The reports of hapstate-inspect over a state directory (docs/inspect.md). Each command
// opens the catalogue read-only, writes nothing (export writes only its output file), and
// returns its report twice: as JSON (the documented shapes) and as text for a terminal.
#pragma once

#include "catalogue/ids.h"
#include "maintenance/state_paths.h"

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace hapstate {

struct InspectOutput {
  std::string json;  // one JSON document, pretty-printed, ending with '\n'
  std::string text;  // lines for a terminal
};

// Counts per stage and the last runs, check-points by class, configurations by status,
// levels-per-check-point histogram, transitions by outcome, failures by reason, disk use.
InspectOutput inspect_summary(const StateDir& dir);

// One check-point, by grid index or by id, with its configurations (levels) and their forces.
// Throws InputError if there is no such check-point.
InspectOutput inspect_checkpoint(const StateDir& dir, const std::array<int, 3>& ijk);
InspectOutput inspect_checkpoint(const StateDir& dir, CheckpointId id);

// One configuration in detail: check-point, level, wave, force, stiffness, expandable,
// status, blob (segment file and vectors), summary, counts of its transitions.
InspectOutput inspect_config(const StateDir& dir, ConfigId id);

// The 26 directions of a configuration: outcome (or "undecided"), target and its level,
// sub-steps, Newton iterations, final residual, wall time, failure reason.
InspectOutput inspect_transitions(const StateDir& dir, ConfigId id);

// Runs one read-only SQL statement (Catalogue::query_read_only on a read-only connection).
// Throws InputError for anything that is not a read.
InspectOutput inspect_sql(const StateDir& dir, std::string_view sql);

// Writes the mesh as drawn with configuration `id`'s point data "displacement" to `vtu`.
// The mesh: `mesh_file` if given (its content hash must match the scene record's), else the
// mesh stored by hapstate-import (problem/seg-000001.h5: mesh/nodes, mesh/tets), else the
// scene's mesh file (absolute, or relative to the state directory or its parent; hash checked).
// Throws InputError if no matching mesh is found or the sizes disagree.
InspectOutput export_config_vtu(const StateDir& dir, ConfigId id, const std::filesystem::path& vtu,
                                const std::optional<std::filesystem::path>& mesh_file);

}  // namespace hapstate
