#include "eval/evaluation.h"

#include "eval/region_path.h"
#include "solver/path_solver.h"
#include "statedir/stage_context.h"
#include "statespace/probe_model.h"
#include "util/error.h"
#include "util/progress.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace hapstate {
namespace {

// ||u - u*||^2 and ||u*||^2 over the listed view nodes.
struct SquaredNorms {
  double diff = 0, exact = 0;
};

SquaredNorms squared_norms(const std::vector<float>& u, const Eigen::Matrix3Xd& exact,
                           std::span<const std::int32_t> view_nodes, const std::vector<char>& use) {
  SquaredNorms s;
  for (std::size_t v = 0; v < view_nodes.size(); ++v) {
    if (!use[v]) continue;
    for (int r = 0; r < 3; ++r) {
      const double e = exact(r, view_nodes[v]);
      s.diff += (u[3 * v + r] - e) * (u[3 * v + r] - e);
      s.exact += e * e;
    }
  }
  return s;
}

// ||u - u*|| / ||u*|| per step; a step where the body is (nearly) at rest, ||u*|| below
// kNearRest of the path's largest ||u*|| (a contact probe off the body or just touching it), is
// divided by the path's largest ||u*|| instead, like the force error.
constexpr double kNearRest = 0.01;

std::vector<double> relative_errors(const std::vector<SquaredNorms>& steps) {
  double largest = 0;
  for (const SquaredNorms& s : steps) largest = std::max(largest, s.exact);
  std::vector<double> out;
  for (const SquaredNorms& s : steps) {
    const double den = s.exact > kNearRest * kNearRest * largest ? s.exact : largest;
    out.push_back(den > 0 ? std::sqrt(s.diff / den) : 0.0);
  }
  return out;
}

}  // namespace

EvalResult run_eval(const EvalOptions& options) {
  const StageContext ctx = open_stage_context(options.state, StateAccess::kRead);
  const std::filesystem::path playback =
      options.playback.empty() ? ctx.dir.root / "playback.bin" : options.playback;
  if (!std::filesystem::exists(playback))
    throw InputError(playback.string() + ": no playback file: run hapstate-index --state " +
                     ctx.dir.root.string() + " first (or give --playback)");
  const PlaybackFile file(playback);
  if (file.scene_hash() != ctx.scene_record.hash.value)
    throw InputError(playback.string() + ": built from another scene than the state directory " +
                     ctx.dir.root.string() + ": run hapstate-index --state " +
                     ctx.dir.root.string());
  const auto h = file.grid_spacing();
  const double step_length =
      options.step_length > 0 ? options.step_length : 0.5 * std::min({h[0], h[1], h[2]});
  const ProbePath path =
      options.path_file.empty()
          ? precomputed_random_path(file, options.steps, step_length, options.seed)
          : read_probe_path(options.path_file);
  char description[256];
  if (options.path_file.empty()) {
    std::snprintf(description, sizeof description,
                  "random path from rest inside the grid: %d steps of at most %.4g mesh units, "
                  "seed %llu",
                  options.steps, step_length, static_cast<unsigned long long>(options.seed));
  } else {
    std::snprintf(description, sizeof description, "path %s", options.path_file.c_str());
  }
  EvalResult result = evaluate_path(ctx.problem, file, path, options.progress);
  result.playback = playback;
  result.path_description = description;
  return result;
}

EvalResult evaluate_path(const Problem& problem, const PlaybackFile& file, const ProbePath& path,
                         std::FILE* progress_out) {
  EvalResult result;
  result.has_all_nodes = file.view_is_all_nodes();
  const auto h = file.grid_spacing();
  result.spacing = Eigen::Vector3d(h[0], h[1], h[2]);
  // Grid index 0 at the origin, lo .. lo + dims - 1 along each axis.
  const auto origin = file.grid_origin(), spacing = file.grid_spacing();
  const auto lo = file.grid_lo(), dims = file.grid_dims();
  for (const Eigen::Vector3d& p : path) {
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      const double i = (p[a] - origin[a]) / spacing[a];
      inside = inside && i >= lo[a] - 1e-9 && i <= lo[a] + dims[a] - 1 + 1e-9;
    }
    result.outside_grid += inside ? 0 : 1;
  }

  // Which view nodes count as surface nodes: those of a surface triangle.
  const auto view_nodes = file.view_nodes();
  std::vector<char> all(view_nodes.size(), 1), surface(view_nodes.size(), 0);
  for (std::int32_t v : file.triangles()) surface[v] = 1;
  if (!result.has_all_nodes) std::fill(surface.begin(), surface.end(), 1);

  const std::unique_ptr<ProbeModel> probe = make_probe_model(problem);
  PathSolver solver(problem);
  std::vector<std::unique_ptr<HapticCursor>> cursors;
  for (Scheme s : result.schemes) cursors.push_back(std::make_unique<HapticCursor>(file, s));
  // A contact path may start anywhere the sphere is clear of the body: the body at rest, the
  // probe there (the precise solver and the cursors alike). Otherwise both start at rest.
  Eigen::Vector3d start = probe->rest_position();
  if (!path.empty() && probe->start_path_at(solver, path.front())) {
    start = path.front();
    for (auto& cursor : cursors)
      cursor->reset({path.front().x(), path.front().y(), path.front().z()});
  }
  std::vector<float> u(3 * view_nodes.size());
  // With gravity both displacements include the sag; the errors are measured on what the probe
  // adds to it (u - u_rest), not flattered by the sag in the denominator.
  const bool sagged = problem.loads.has_force();
  const std::vector<double> rest_u = rest_displacements(problem);
  // Per scheme, per step.
  std::vector<std::vector<SquaredNorms>> norms_all(cursors.size()), norms_surface(cursors.size());

  Progress progress("hapstate-eval: precise solves", static_cast<long long>(path.size()),
                    progress_out);
  long long failures = 0;
  // Path length since the last position with the probe clear of the body (none yet: infinite).
  // A contact path starts clear of the body (at rest, or where it starts): its first step onto
  // the body is an onset too.
  double travel_in_contact =
      probe->clear_of_body(start) ? 0.0 : std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < path.size(); ++k) {
    const Eigen::Vector3d& p = path[k];
    EvalStep step;
    step.probe = p;
    const MoveResult move = probe->move_to(solver, p);
    step.solved = move.ok;
    step.failure = move.reason;
    step.solve_ms = move.wall_ms;
    failures += move.ok ? 0 : 1;
    step.exact_force = solver.force_felt();
    // The first cell after the probe comes onto the body (contact): left out of the
    // deformation errors, whose reference u* is there a small indentation.
    const bool free = probe->clear_of_body(p);
    travel_in_contact = free ? 0 : travel_in_contact + (p - (k > 0 ? path[k - 1] : start)).norm();
    step.contact_onset = !free && travel_in_contact < result.spacing.minCoeff();
    Eigen::Matrix3Xd exact_u = solver.displacements();
    if (sagged) exact_u -= Eigen::Map<const Eigen::Matrix3Xd>(rest_u.data(), 3, exact_u.cols());
    for (std::size_t s = 0; s < cursors.size(); ++s) {
      SchemeResult r;
      const Force f = cursors[s]->force({p.x(), p.y(), p.z()});
      r.force = Eigen::Vector3d(f.value[0], f.value[1], f.value[2]);
      Snapshot snap;
      cursors[s]->snapshot(&snap);
      displacements(file, snap, u);
      if (sagged)
        for (std::size_t v = 0; v < view_nodes.size(); ++v)
          for (int c = 0; c < 3; ++c)
            u[3 * v + c] -= static_cast<float>(rest_u[3 * std::size_t(view_nodes[v]) + c]);
      norms_all[s].push_back(squared_norms(u, exact_u, view_nodes, all));
      norms_surface[s].push_back(squared_norms(u, exact_u, view_nodes, surface));
      step.schemes.push_back(r);
    }
    if (step.solved)
      result.max_exact_force = std::max(result.max_exact_force, step.exact_force.norm());
    result.steps.push_back(std::move(step));
    progress.update(static_cast<long long>(result.steps.size()), failures);
  }
  progress.finish();
  for (std::size_t s = 0; s < cursors.size(); ++s) {
    const std::vector<double> all_error = relative_errors(norms_all[s]);
    const std::vector<double> surface_error = relative_errors(norms_surface[s]);
    for (std::size_t k = 0; k < result.steps.size(); ++k) {
      SchemeResult& r = result.steps[k].schemes[s];
      r.force_error = result.max_exact_force > 0
                          ? (r.force - result.steps[k].exact_force).norm() / result.max_exact_force
                          : 0.0;
      if (result.has_all_nodes) r.deformation_error_all = all_error[k];
      r.deformation_error_surface = surface_error[k];
    }
  }
  return result;
}

}  // namespace hapstate
