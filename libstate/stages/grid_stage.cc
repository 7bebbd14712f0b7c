#include "stages/grid_stage.h"

#include "catalogue/transaction.h"
#include "stages/refine_stage.h"
#include "statedir/stage_context.h"
#include "statedir/stage_run.h"
#include "statespace/expand_batch.h"
#include "statespace/level_match.h"
#include "statespace/probe_model.h"
#include "util/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

namespace hapstate {
namespace {

std::string ijk_text(const GridIndex& ijk) {
  return "(" + std::to_string(ijk[0]) + ", " + std::to_string(ijk[1]) + ", " +
         std::to_string(ijk[2]) + ")";
}

bool in_workspace(CheckpointClass c) {
  return c == CheckpointClass::kWorkspace || c == CheckpointClass::kFree;
}

// The zero configuration (no blob: u = the loaded rest state, nothing touched, t = 0) of
// `checkpoint`.
Configuration zero_configuration(const StageContext& ctx, CheckpointId checkpoint) {
  Configuration c;
  c.checkpoint = checkpoint;
  c.level = Level(0);
  c.wave = 0;
  c.stiffness = zero_stiffness(ctx.dir, ctx.problem).stiffness;
  c.expandable = 0.0 <= ctx.scene.probe.max_force;
  c.status = ConfigStatus::kOpen;
  c.summary = LevelSketch(ctx.problem).summary(rest_displacements(ctx.problem));
  return c;
}

// What the loaded rest state did (the zero configuration's shape): the largest sag and where the
// grab point went, mesh units.
std::string rest_state_text(const Problem& p) {
  const std::vector<double> u = rest_displacements(p);
  double largest = 0;
  for (std::size_t n = 0; 3 * n < u.size(); ++n)
    largest = std::max(largest, std::hypot(u[3 * n], u[3 * n + 1], u[3 * n + 2]));
  char text[320];
  if (p.contact) {
    std::snprintf(text, sizeof text,
                  "the body rests under its loads (gravity, supports) with a largest "
                  "displacement of %.4g mesh units; the sphere's rest point and the workspace "
                  "stay where the scene puts them",
                  largest);
  } else {
    std::snprintf(text, sizeof text,
                  "the body rests under its loads (gravity, supports) with a largest "
                  "displacement of %.4g mesh units; the grab point sagged by (%.4g, %.4g, %.4g) to "
                  "(%.6g, %.6g, %.6g), and the grid (an explicit grid.box too) moved with it",
                  largest, p.probe_sag.x(), p.probe_sag.y(), p.probe_sag.z(), p.probe_rest.x(),
                  p.probe_rest.y(), p.probe_rest.z());
  }
  return text;
}

// The check-points already stored, by grid index, each checked to be where the scene's grid puts
// it (InputError otherwise: nothing changed).
std::map<GridIndex, Checkpoint> stored_checkpoints(StageContext& ctx) {
  std::map<GridIndex, Checkpoint> existing;
  for (const Checkpoint& c : ctx.catalogue.read_all_checkpoints()) {
    const Eigen::Vector3d want = ctx.grid.position(c.ijk);
    const Eigen::Vector3d have(c.position[0], c.position[1], c.position[2]);
    if ((want - have).cwiseAbs().maxCoeff() > 1e-9 * ctx.grid.spacing.maxCoeff()) {
      throw InputError(ctx.dir.catalogue().string() + ": check-point " + ijk_text(c.ijk) +
                       " is stored at a position the scene's grid does not give it (the grid "
                       "spacing or the probe's rest position changed): re-import with --fresh");
    }
    existing.emplace(c.ijk, c);
  }
  return existing;
}

// The grid's workspace check-points after inserting those missing (classified); contact: which
// are free (the sphere touches nothing there).
struct WorkspaceCheckpoints {
  std::map<GridIndex, CheckpointId> ids;
  std::vector<CheckpointId> free_ids;
};

WorkspaceCheckpoints insert_checkpoints(StageContext& ctx,
                                        const std::map<GridIndex, Checkpoint>& existing,
                                        GridReport& report) {
  const GridSpec& grid = ctx.grid;
  const auto probe = make_probe_model(ctx.problem);
  WorkspaceCheckpoints w;
  for (int i = grid.lo[0]; i <= grid.hi[0]; ++i)
    for (int j = grid.lo[1]; j <= grid.hi[1]; ++j)
      for (int k = grid.lo[2]; k <= grid.hi[2]; ++k) {
        const GridIndex ijk{i, j, k};
        Checkpoint c;
        if (auto it = existing.find(ijk); it != existing.end()) {
          c = it->second;
        } else {
          c.ijk = ijk;
          const Eigen::Vector3d p = grid.position(ijk);
          c.position = {p.x(), p.y(), p.z()};
          c.classification = !grid.in_workspace(p)     ? CheckpointClass::kOutsideWorkspace
                             : probe->clear_of_body(p) ? CheckpointClass::kFree
                                                       : CheckpointClass::kWorkspace;
          c.id = ctx.catalogue.insert_checkpoint(c);
          ++report.checkpoints_added;
        }
        if (in_workspace(c.classification)) w.ids.emplace(ijk, c.id);
        if (c.classification == CheckpointClass::kFree) w.free_ids.push_back(c.id);
      }
  if (!w.free_ids.empty() && w.free_ids.size() == w.ids.size()) {
    throw InputError(ctx.scene.path.string() + ": grid.box: the sphere (probe.radius " +
                     std::to_string(ctx.problem.contact->radius) +
                     ") is clear of the body at every one of the " + std::to_string(w.ids.size()) +
                     " workspace check-points, so the probe could never touch it; draw the "
                     "workspace (or move probe.point) over the body's surface");
  }
  return w;
}

// The rest check-point and every free one (contact: the sphere clear of the body) hold the zero
// configuration (no blob), inserted once.
void insert_zero_configurations(StageContext& ctx, const WorkspaceCheckpoints& w,
                                GridReport& report) {
  const auto rest = w.ids.find(GridIndex{0, 0, 0});
  if (rest == w.ids.end()) {
    throw InputError(ctx.dir.root.string() +
                     ": the rest check-point (0, 0, 0) is not in the "
                     "workspace (internal inconsistency)");
  }
  std::vector<CheckpointId> zero_ids = w.free_ids;
  if (std::find(zero_ids.begin(), zero_ids.end(), rest->second) == zero_ids.end())
    zero_ids.insert(zero_ids.begin(), rest->second);
  std::optional<Configuration> zero;
  for (CheckpointId id : zero_ids) {
    if (!ctx.catalogue.configurations_at(id).empty()) continue;
    if (!zero) zero = zero_configuration(ctx, id);
    Configuration c = *zero;
    c.checkpoint = id;
    ctx.catalogue.insert_configuration(c);
    ++report.zero_configurations;
  }
  report.zero_configuration_added = report.zero_configurations > 0;
}

// Reopens the decisions "outside the grid" whose neighbour is now a workspace check-point.
void reopen_outside_transitions(Catalogue& cat, const WorkspaceCheckpoints& w, GridReport& report) {
  std::map<CheckpointId, GridIndex> index_of;
  for (const auto& [ijk, id] : w.ids) index_of.emplace(id, ijk);
  for (const Transition& t : cat.read_all_transitions()) {
    if (t.outcome != TransitionOutcome::kOutsideGrid) continue;
    const Configuration source = cat.read_configuration(t.source);
    const auto at = index_of.find(source.checkpoint);
    if (at == index_of.end()) continue;
    const auto off = t.direction.offset();
    const GridIndex to{at->second[0] + off[0], at->second[1] + off[1], at->second[2] + off[2]};
    if (!w.ids.count(to)) continue;
    cat.delete_transition(t.source, t.direction);
    if (source.status == ConfigStatus::kExpanded)
      cat.update_configuration_status(source.id, ConfigStatus::kOpen);
    ++report.transitions_reopened;
  }
}

// The run's one line.
std::string grid_message(const GridReport& report, bool contact_free, const Problem& problem,
                         const GridSpec& grid) {
  std::string m = std::to_string(report.checkpoints_added) + " check-points added (" +
                  std::to_string(report.checkpoints_total) + " in all)";
  if (!contact_free && report.zero_configuration_added)
    m += ", the body at rest stored at the rest check-point (0, 0, 0)";
  if (contact_free && report.zero_configurations > 0)
    m += ", " + std::to_string(report.zero_configurations) +
         " free check-points (sphere clear of the body) with the zero configuration";
  if (report.transitions_reopened)
    m += ", " + std::to_string(report.transitions_reopened) +
         " transitions reopened into the enlarged workspace";
  if (problem.loads.has_force()) m += "; " + rest_state_text(problem);
  if (problem.contact) {
    const std::string note = contact_spacing_note(problem.contact->radius, grid.spacing.maxCoeff());
    if (!note.empty()) m.append("; ").append(note);
  }
  return m;
}

}  // namespace

void GridOptions::check() const {
  if (state.empty()) throw InputError("--state: no state directory given");
}

GridReport run_grid(const GridOptions& options) {
  options.check();
  StageContext ctx = open_stage_context(options.state);
  Catalogue& cat = ctx.catalogue;
  const GridSpec& grid = ctx.grid;
  const NamedHashes inputs = {
      {"grid", grid.hash()}, {"problem", ctx.problem_hash}, {"scene", ctx.scene_record.hash}};
  char params[256];
  std::snprintf(params, sizeof params,
                "spacing=(%.9g, %.9g, %.9g) workspace=[(%.9g, %.9g, %.9g), (%.9g, %.9g, %.9g)]",
                grid.spacing.x(), grid.spacing.y(), grid.spacing.z(), grid.workspace.min.x(),
                grid.workspace.min.y(), grid.workspace.min.z(), grid.workspace.max.x(),
                grid.workspace.max.y(), grid.workspace.max.z());
  StageRunFrame frame(cat, "grid", inputs, params);
  GridReport report;

  // Validate the stored check-points against the grid before changing anything.
  const std::map<GridIndex, Checkpoint> existing = stored_checkpoints(ctx);
  if (frame.same_as_last({"grid", "problem"}) && !existing.empty()) {
    report.checkpoints_total = static_cast<std::int64_t>(existing.size());
    return frame.unchanged(report, "unchanged: the grid is up to date (" +
                                       std::to_string(existing.size()) +
                                       " check-points), nothing to do");
  }

  Transaction tx(cat);
  const WorkspaceCheckpoints w = insert_checkpoints(ctx, existing, report);
  report.checkpoints_total = cat.num_checkpoints();
  insert_zero_configurations(ctx, w, report);
  if (report.checkpoints_added > 0) reopen_outside_transitions(cat, w, report);
  report.message = grid_message(report, !w.free_ids.empty(), ctx.problem, grid);
  frame.end(report);  // recorded with the grid, in its transaction
  tx.commit();
  return report;
}

}  // namespace hapstate
