#include "stages/import_stage.h"

#include "catalogue/catalogue.h"
#include "catalogue/transaction.h"
#include "scene/bind.h"
#include "scene/grid_spec.h"
#include "scene/scene.h"
#include "statedir/scene_identity.h"
#include "statedir/stage_run.h"
#include "statedir/state_dir.h"
#include "statedir/stored_problem.h"
#include "statedir/stored_scene.h"
#include "statespace/expand_batch.h"
#include "util/error.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>

namespace hapstate {
namespace {

namespace fs = std::filesystem;

SceneRecord make_scene_record(const Scene& scene, const Problem& problem,
                              const ContentHash& mesh_hash) {
  SceneRecord r;
  r.text = scene.text;
  r.hash = content_hash(scene.text);
  r.mesh_file = scene.mesh.file.string();
  r.mesh_hash = mesh_hash;
  const Mesh& mesh = problem.mesh;
  r.mesh_nodes = mesh.num_nodes();
  r.mesh_elements = mesh.num_tets();
  r.mesh_surface_triangles = mesh.surface.cols();
  if (mesh.num_nodes() > 0) {
    const Eigen::Vector3d lo = mesh.nodes.rowwise().minCoeff(),
                          hi = mesh.nodes.rowwise().maxCoeff();
    for (int a = 0; a < 3; ++a) {
      r.bbox_min[a] = lo[a];
      r.bbox_max[a] = hi[a];
    }
  }
  double volume = 0;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    const Eigen::Vector3d a = mesh.nodes.col(mesh.tets(0, e));
    volume += (mesh.nodes.col(mesh.tets(1, e)) - a)
                  .cross(mesh.nodes.col(mesh.tets(2, e)) - a)
                  .dot(mesh.nodes.col(mesh.tets(3, e)) - a) /
              6.0;
  }
  r.volume = volume;
  return r;
}

std::string parameters_of(const ImportOptions& o) {
  return "scene=" + o.scene.string() + " fresh=" + (o.fresh ? "1" : "0");
}

// Imports into a directory without an imported scene (new, emptied, or left by a crash).
// The import run is recorded in one transaction with the scene: a directory without it was never
// imported.
// `rest`: the zero configurations' stiffness (rest_stiffness), computed before anything in the
// directory is touched.
void import_new(const StateDir& dir, const ImportOptions& options, const Scene& scene,
                const Problem& problem, const RestStiffness& rest, const ContentHash& mesh_hash,
                const NamedHashes& identity, ImportReport& report) {
  fs::create_directories(dir.root);
  fs::create_directories(dir.blobs());
  // A problem segment without a scene row is left by a crash: replace it.
  fs::remove_all(dir.problem());
  write_stored_problem(dir, problem, content_hash(scene.text), rest);
  Catalogue catalogue(dir.catalogue(), OpenMode::kCreate);
  Transaction tx(catalogue);
  catalogue.write_scene(make_scene_record(scene, problem, mesh_hash));
  StageRunFrame(catalogue, "import", identity, parameters_of(options)).end(report);
  tx.commit();
}

std::string format_force(double f) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g N", f);
  return buf;
}

// The parts of the scene that changed since the recorded import (`last`), all of them parts that
// may change; InputError naming the others if any changed.
std::vector<std::string> changed_parts(const ImportOptions& options, const StateDir& dir,
                                       const NamedHashes& identity, const StageRun& last) {
  std::vector<std::string> refused, changed;
  for (const auto& [name, hash] : identity) {
    if (run_input(last, name) == hash) continue;
    (is_mutable_scene_part(name) ? changed : refused).push_back(name);
  }
  if (!refused.empty()) {
    std::string what;
    for (const auto& part : refused) what += (what.empty() ? "" : "; ") + describe_scene_part(part);
    throw InputError(options.scene.string() + ": the state directory " + dir.root.string() +
                     " was built from another scene; changed: " + what +
                     ". A state directory belongs to one scene (only probe.max_force and an "
                     "enlarged grid.box may change): import into another --state directory, or "
                     "give --fresh to delete this one's configurations and start again");
  }
  return changed;
}

// The workspace may only grow: InputError if a stored workspace check-point is outside `grid`.
void require_larger_workspace(const ImportOptions& options, const StateDir& dir,
                              Catalogue& catalogue, const GridSpec& grid) {
  for (const Checkpoint& c : catalogue.read_all_checkpoints()) {
    const Eigen::Vector3d p(c.position[0], c.position[1], c.position[2]);
    if (c.classification == CheckpointClass::kWorkspace && !grid.in_workspace(p)) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "check-point (%d, %d, %d) at (%.9g, %.9g, %.9g)", c.ijk[0],
                    c.ijk[1], c.ijk[2], p.x(), p.y(), p.z());
      throw InputError(options.scene.string() + ": [grid] box: the new workspace no longer holds " +
                       buf + " of the state directory " + dir.root.string() +
                       ": the workspace may only be enlarged (give --fresh to start again)");
    }
  }
}

// What an allowed change changed, for the message ("probe.max_force 1 N -> 2 N; ...").
std::string describe_update(const std::vector<std::string>& changed, Catalogue& catalogue,
                            const StateDir& dir, const Scene& scene) {
  std::string what;
  const SceneRecord old_scene = read_stored_scene(catalogue, dir);
  for (const auto& part : changed) {
    if (part == "max_force") {
      const Scene old = parse_stored_scene(old_scene, dir);
      what += (what.empty() ? "" : "; ") + std::string("probe.max_force ") +
              format_force(old.probe.max_force) + " -> " + format_force(scene.probe.max_force);
    } else if (part == "workspace") {
      what += (what.empty() ? "" : "; ") + std::string("workspace enlarged");
    }
  }
  return what.empty() ? "scene text (nothing the state depends on)" : what;
}

}  // namespace

void ImportOptions::check() const {
  if (scene.empty()) throw InputError("no scene file given");
  if (state.empty()) throw InputError("--state: no state directory given");
}

ImportReport run_import(const ImportOptions& options) {
  options.check();
  // 1. Validate everything before touching the state directory.
  const Scene scene = load_scene(options.scene);
  MeshReport mesh_report;
  const Problem problem = build_problem(scene, &mesh_report);
  const GridSpec grid =
      resolve_grid(scene.grid, problem.probe_rest, options.scene.string(), problem.probe_sag);
  const ContentHash mesh_hash = content_hash_file(scene.mesh.file);
  const NamedHashes identity = scene_identity(scene, problem, mesh_hash);
  const StateDir dir{options.state};

  ImportReport report;
  report.warnings = mesh_report.warnings;
  for (std::string& note : grid_short_axes(scene.grid, grid, options.scene.string()))
    report.warnings.push_back(std::move(note));
  const std::string summary = std::to_string(problem.mesh.num_nodes()) + " nodes, " +
                              std::to_string(problem.mesh.num_tets()) + " tets, " +
                              std::to_string(grid.num_checkpoints()) + " check-points" +
                              ("; " + describe_grab(scene, problem));

  if (fs::exists(dir.root) && !fs::is_directory(dir.root)) {
    throw InputError(dir.root.string() + ": exists and is not a directory");
  }
  const bool has_catalogue = fs::exists(dir.catalogue());
  if (has_catalogue && fs::file_size(dir.catalogue()) > 0 &&
      !is_hapstate_catalogue_file(dir.catalogue())) {
    throw InputError(dir.catalogue().string() +
                     ": not a hapstate catalogue: refusing to use or delete it (choose another "
                     "--state directory)");
  }

  fs::create_directories(dir.root);
  const StateDirLock lock(dir);

  // 2. --fresh: start over.
  if (options.fresh) {
    const bool existed = has_catalogue;
    const RestStiffness rest = rest_stiffness(problem);
    remove_state_files(dir);
    report.change = existed ? ImportChange::kRecreated : ImportChange::kCreated;
    report.message = (existed ? "deleted the old state and imported: " : "imported: ") + summary;
    import_new(dir, options, scene, problem, rest, mesh_hash, identity, report);
    return report;
  }

  // 3. No imported scene yet.
  std::optional<StageRun> last;
  if (has_catalogue) {
    Catalogue catalogue(dir.catalogue(), OpenMode::kMigrate);  // refuses future/foreign/corrupt
    if (catalogue.read_scene()) last = catalogue.last_successful_stage_run("import");
    if (catalogue.read_scene() && !last) {
      throw InputError(dir.catalogue().string() +
                       ": has a scene but no successful import run "
                       "(damaged?): use --fresh to start over");
    }
  }
  if (!last) {
    report.change = ImportChange::kCreated;
    report.message = "imported: " + summary;
    import_new(dir, options, scene, problem, rest_stiffness(problem), mesh_hash, identity, report);
    return report;
  }

  // 4. Compare with the recorded scene.
  const std::vector<std::string> changed = changed_parts(options, dir, identity, *last);
  Catalogue catalogue(dir.catalogue(), OpenMode::kMigrate);
  StageRunFrame frame(catalogue, "import", identity, parameters_of(options));
  if (changed.empty())
    return frame.unchanged(report, "unchanged: the same scene was imported before, nothing to do");
  require_larger_workspace(options, dir, catalogue, grid);
  report.change = ImportChange::kUpdated;
  report.message =
      "updated: " + describe_update(changed, catalogue, dir, scene) + " (every configuration kept)";
  Transaction tx(catalogue);
  catalogue.write_scene(make_scene_record(scene, problem, mesh_hash));
  frame.end(report);
  tx.commit();
  return report;
}

}  // namespace hapstate
