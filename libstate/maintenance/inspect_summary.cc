// hapstate-inspect summary.
#include "hapstate/playback.h"
#include "maintenance/certificate_report.h"
#include "maintenance/inspect_common.hpp"
#include "util/text.h"

#include <cstdio>
#include <sstream>
#include <variant>

namespace hapstate {

using namespace inspect_detail;

namespace {

constexpr int kLastRuns = 10;

std::int64_t int_at(const std::vector<QueryValue>& row, std::size_t c) {
  const auto* v = std::get_if<std::int64_t>(&row.at(c));
  return v != nullptr ? *v : 0;
}

std::string text_at(const std::vector<QueryValue>& row, std::size_t c) {
  const auto* v = std::get_if<std::string>(&row.at(c));
  return v != nullptr ? *v : "";
}

// A run recorded as running while no process holds the directory's lock was killed. (The lock
// is probed after the rows were read, so a stage starting in between is not called killed.)
void mark_interrupted(Json* run, bool busy) {
  if ((*run)["outcome"] != "running" || busy) return;
  (*run)["outcome"] = "interrupted";
  (*run)["message"] =
      "the process ended before finishing (Ctrl-C, kill, crash); run it again to "
      "resume";
}

// The "stages" and "last_runs" keys: each stage's runs and last run, the last runs overall.
void add_stage_runs(const StateDir& dir, Catalogue& cat, Json* out) {
  Json& j = *out;
  Json stages = Json::array();
  for (const auto& row : cat.query_read_only("SELECT stage, count(*), max(id) FROM stage_run "
                                             "GROUP BY stage ORDER BY min(id)")
                             .rows) {
    stages.push_back({{"stage", text_at(row, 0)},
                      {"runs", int_at(row, 1)},
                      {"last", stage_run_json(cat.read_stage_run(StageRunId(int_at(row, 2))))}});
  }
  Json last = Json::array();
  for (const auto& row : cat.query_read_only("SELECT id FROM stage_run ORDER BY id DESC LIMIT " +
                                             std::to_string(kLastRuns))
                             .rows) {
    last.push_back(stage_run_json(cat.read_stage_run(StageRunId(int_at(row, 0)))));
  }
  const bool busy = state_dir_busy(dir);
  for (Json& stage : stages) mark_interrupted(&stage["last"], busy);
  for (Json& run : last) mark_interrupted(&run, busy);
  j["stages"] = stages;
  j["last_runs"] = last;
}

// The "checkpoints", "configurations" and "levels_per_checkpoint" keys.
void add_configurations(Catalogue& cat, Json* out) {
  Json& j = *out;
  Json by_class = Json::object();
  for (int c = 0; c <= 4; ++c) by_class[checkpoint_class_name(static_cast<CheckpointClass>(c))] = 0;
  for (const auto& row :
       cat.query_read_only("SELECT classification, count(*) FROM checkpoint GROUP BY 1").rows) {
    by_class[checkpoint_class_name(static_cast<CheckpointClass>(int_at(row, 0)))] = int_at(row, 1);
  }
  const std::int64_t checkpoints = cat.num_checkpoints();
  j["checkpoints"] = {{"total", checkpoints}, {"by_class", by_class}};

  Json configs = {{"total", cat.num_configurations()}, {"open", 0}, {"expanded", 0}, {"merged", 0}};
  for (const auto& row :
       cat.query_read_only("SELECT status, count(*) FROM configuration GROUP BY 1").rows) {
    configs[config_status_name(static_cast<ConfigStatus>(int_at(row, 0)))] = int_at(row, 1);
  }
  configs["expandable"] = query_int(cat, "SELECT count(*) FROM configuration WHERE expandable = 1");
  // Open but never to be expanded: the felt force is above probe.max_force (or the check-point
  // is outside the workspace).
  configs["open_not_expandable"] =
      query_int(cat, "SELECT count(*) FROM configuration WHERE status = 0 AND expandable = 0");
  // The two reasons apart: the check-point outside the workspace, or the force too strong.
  configs["open_outside_workspace"] = query_int(
      cat,
      "SELECT count(*) FROM configuration c JOIN checkpoint p ON p.id = c.checkpoint WHERE "
      "c.status = 0 AND c.expandable = 0 AND p.classification = 2");
  const auto max_wave = cat.max_wave();
  configs["max_wave"] = max_wave ? Json(*max_wave) : Json(nullptr);
  j["configurations"] = configs;

  // Live levels (not merged) per check-point; check-points without any count as 0.
  Json histogram = Json::array();
  std::int64_t with_levels = 0;
  const auto rows = cat.query_read_only(
                           "SELECT n, count(*) FROM (SELECT count(*) AS n FROM configuration "
                           "WHERE status != 2 GROUP BY checkpoint) GROUP BY n ORDER BY n")
                        .rows;
  for (const auto& row : rows) with_levels += int_at(row, 1);
  if (checkpoints > with_levels)
    histogram.push_back({{"levels", 0}, {"checkpoints", checkpoints - with_levels}});
  for (const auto& row : rows)
    histogram.push_back({{"levels", int_at(row, 0)}, {"checkpoints", int_at(row, 1)}});
  j["levels_per_checkpoint"] = histogram;
}

// The "transitions", "failures_by_reason" and "refinement" keys.
void add_transitions(Catalogue& cat, Json* out) {
  Json& j = *out;
  Json transitions = {
      {"total", cat.num_transitions()}, {"reached", 0}, {"outside_grid", 0}, {"failed", 0}};
  for (const auto& row :
       cat.query_read_only("SELECT outcome, count(*) FROM transition GROUP BY 1").rows) {
    transitions[transition_outcome_name(static_cast<TransitionOutcome>(int_at(row, 0)))] =
        int_at(row, 1);
  }
  // The cost of the solved ones (reached or failed; 0 in rows older than schema 2).
  const QueryResult cost = cat.query_read_only(
      "SELECT avg(newton_iterations), avg(factorisations) FROM transition WHERE outcome != 1");
  const auto average = [&](std::size_t c) -> Json {
    if (cost.rows.empty()) return nullptr;
    const auto* v = std::get_if<double>(&cost.rows.front().at(c));
    return v != nullptr ? Json(*v) : Json(nullptr);
  };
  transitions["mean_newton_iterations"] = average(0);
  transitions["mean_factorisations"] = average(1);
  j["transitions"] = transitions;
  Json failures = Json::array();
  for (const auto& row : cat.query_read_only("SELECT failure_reason, count(*) FROM transition "
                                             "WHERE outcome = 2 GROUP BY 1 ORDER BY 2 DESC, 1")
                             .rows) {
    failures.push_back({{"reason", text_at(row, 0)}, {"count", int_at(row, 1)}});
  }
  j["failures_by_reason"] = failures;
  const QueryResult refined = cat.query_read_only(
      "SELECT count(DISTINCT cell), count(*), count(*) FILTER (WHERE outcome = 2), "
      "count(DISTINCT cell) FILTER (WHERE point >= 125 AND point < 854), "
      "count(DISTINCT cell) FILTER (WHERE point >= 854), "
      "count(*) FILTER (WHERE point >= 854) FROM refinement");
  j["refinement"] = {{"cells", int_at(refined.rows.front(), 0)},
                     {"points", int_at(refined.rows.front(), 1)},
                     {"failed", int_at(refined.rows.front(), 2)},
                     {"depth2_cells", int_at(refined.rows.front(), 3)},
                     {"depth3_cells", int_at(refined.rows.front(), 4)},
                     {"depth3_points", int_at(refined.rows.front(), 5)}};
}

Json summary_json(const StateDir& dir, Catalogue& cat) {
  Json j;
  j["state"] = dir.root.string();
  j["schema_version"] = cat.schema_version();
  if (const auto scene = cat.read_scene()) {
    j["scene"] = {{"hash", scene->hash.hex()},
                  {"mesh_file", scene->mesh_file},
                  {"mesh_nodes", scene->mesh_nodes},
                  {"mesh_elements", scene->mesh_elements},
                  {"mesh_surface_triangles", scene->mesh_surface_triangles}};
  } else {
    j["scene"] = nullptr;
  }

  add_stage_runs(dir, cat, &j);
  add_configurations(cat, &j);
  add_transitions(cat, &j);

  const DiskUse disk = measure_disk_use(dir);
  j["disk"] = {{"catalogue_bytes", disk.catalogue_bytes},
               {"blob_bytes", disk.blob_bytes},
               {"segments", disk.segments},
               {"problem_bytes", disk.problem_bytes},
               {"total_bytes", disk.total()}};
  return j;
}

std::string summary_text(const Json& j) {
  std::ostringstream s;
  s << "state " << j["state"].get<std::string>() << " (schema " << j["schema_version"] << ")\n";
  if (j["scene"].is_null()) {
    s << "scene: none (not imported)\n";
  } else {
    s << "scene " << j["scene"]["hash"].get<std::string>() << ": mesh "
      << j["scene"]["mesh_file"].get<std::string>() << ", " << j["scene"]["mesh_nodes"]
      << " nodes, " << j["scene"]["mesh_elements"] << " tets\n";
  }
  s << "stages:\n";
  if (j["stages"].empty()) s << "  (no run yet)\n";
  for (const auto& st : j["stages"]) {
    s << "  " << st["stage"].get<std::string>() << ": " << st["runs"] << " runs, last #"
      << st["last"]["id"] << " " << st["last"]["outcome"].get<std::string>();
    const std::string outcome = st["last"]["outcome"].get<std::string>();
    std::string message = st["last"]["message"].get<std::string>();
    // "unchanged: unchanged: the grid is up to date" would say it twice.
    if (message.rfind(outcome + ": ", 0) == 0) message.erase(0, outcome.size() + 2);
    if (!message.empty() && message != outcome) s << ": " << message;
    s << "\n";
  }
  s << "check-points: " << j["checkpoints"]["total"] << " (grid points where states are stored";
  const char* by = ": ";
  for (const auto& [name, n] : j["checkpoints"]["by_class"].items()) {
    if (n.get<std::int64_t>() == 0) continue;
    s << by << n << " " << name;
    by = ", ";
  }
  s << ")";
  const Json& c = j["configurations"];
  const std::int64_t not_expandable = c["open_not_expandable"].get<std::int64_t>();
  const std::int64_t outside = c["open_outside_workspace"].get<std::int64_t>();
  s << "\nconfigurations (stored equilibrium states): " << c["total"] << " (" << c["expanded"]
    << " expanded, " << c["open"].get<std::int64_t>() - not_expandable << " still to expand, "
    << not_expandable - outside << " not expanded: force above probe.max_force, " << outside
    << " not expanded: outside the workspace; " << c["merged"] << " merged as duplicates)";
  if (!c["max_wave"].is_null())
    s << "; the farthest is " << c["max_wave"]
      << " waves (moves) from a zero configuration (the rest state, or a free check-point)";
  s << "\nlevels per check-point (a level: the same probe position reached by another history):";
  const char* sep = " ";
  for (const auto& h : j["levels_per_checkpoint"]) {
    s << sep << plural(h["checkpoints"].get<std::int64_t>(), "check-point", "check-points")
      << " with " << plural(h["levels"].get<std::int64_t>(), "level", "levels");
    sep = ", ";
  }
  const Json& t = j["transitions"];
  s << "\ntransitions (moves to a neighbouring check-point): " << t["total"] << " (" << t["reached"]
    << " solved, " << t["outside_grid"] << " outside the grid, " << t["failed"] << " failed)";
  if (!t["mean_factorisations"].is_null()) {
    char cost[200];
    std::snprintf(cost, sizeof cost,
                  "; per move solved or tried, on average %.3g Newton iterations and %.3g "
                  "factorisations of the stiffness matrix of its own (otherwise it reuses its "
                  "start state's)",
                  t["mean_newton_iterations"].get<double>(),
                  t["mean_factorisations"].get<double>());
    s << cost;
  }
  s << "\n";
  for (const auto& f : j["failures_by_reason"]) {
    s << "  failed " << f["count"] << "x: " << f["reason"].get<std::string>() << "\n";
  }
  const Json& r = j["refinement"];
  s << "refined cells: " << r["cells"] << ", " << r["depth2_cells"]
    << " of them to eighth spacings";
  if (r["depth3_cells"].get<std::int64_t>() > 0)
    s << ", " << r["depth3_cells"] << " with sixteenth-spacing points (" << r["depth3_points"]
      << ")";
  s << " (" << r["points"] << " points, " << r["failed"] << " failed)\n";
  const Json& d = j["disk"];
  s << "disk: " << size_text(d["total_bytes"].get<std::int64_t>()) << " (catalogue "
    << size_text(d["catalogue_bytes"].get<std::int64_t>()) << ", vectors "
    << size_text(d["blob_bytes"].get<std::int64_t>()) << " in "
    << plural(d["segments"].get<std::int64_t>(), "segment file", "segment files") << ", problem "
    << size_text(d["problem_bytes"].get<std::int64_t>()) << ")\n";
  return s.str();
}

}  // namespace

InspectOutput inspect_summary(const StateDir& dir) {
  Catalogue cat = open_read_only(dir);
  Json j = summary_json(dir, cat);
  // The certificate, stale unless measured on the playback file the directory holds now, by
  // this build's playback code.
  std::optional<ContentHash> current;
  bool contact = false;
  try {
    if (std::filesystem::exists(dir.root / "playback.bin")) {
      const PlaybackFile file(dir.root / "playback.bin");
      current = certified_hash(file.source_hash());
      contact = file.is_contact();
    }
  } catch (const std::exception&) {  // unreadable or older: no current file to match
  }
  const CertificateText certificate = certificate_text(
      summarise_certificate(cat.read_all_certificate_paths(), cat.read_all_certificate_equilibria(),
                            cat.read_certificate(), current, contact));
  j["certificate"] = Json::parse(certificate.json);
  return {dump(j), summary_text(j) + certificate.text};
}

}  // namespace hapstate
