#include "stages/index_stage.h"

#include "blobs/blob_store.h"
#include "hapstate/playback.h"
#include "index/refined_cells.h"
#include "playback/onset_model.h"
#include "playback/writer.h"
#include "statedir/stage_context.h"
#include "statedir/stage_run.h"
#include "statespace/expand_batch.h"
#include "statespace/probe_model.h"
#include "util/error.h"
#include "util/grid_direction.h"
#include "util/progress.h"
#include "util/text.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <optional>

namespace hapstate {
namespace {

struct Gathered {
  playback::Content content;
  std::vector<Configuration> configs;  // in file order
  // Per configuration and midpoint direction (kMidpointDirections each): where the
  // displacements half-way are stored, if they are.
  std::vector<std::optional<BlobRef>> midpoint_blobs;
  ContentHash fingerprint;  // of everything the file is built from
};

ContentHash fingerprint_of(const std::vector<Configuration>& configs,
                           const std::vector<Transition>& transitions,
                           const std::vector<RefinementPoint>& refinement,
                           const NamedHashes& inputs, ViewNodes view) {
  ContentHasher h;
  for (const auto& [name, hash] : inputs)
    h.update(name).update(static_cast<std::int64_t>(hash.value));
  h.update(static_cast<std::int64_t>(view == ViewNodes::kAll));
  for (const Configuration& c : configs) {
    h.update(c.id.value()).update(c.checkpoint.value()).update(std::int64_t{c.level.value()});
    h.update(std::span<const double>(c.force)).update(std::span<const double>(c.stiffness));
    h.update(std::int64_t{static_cast<int>(c.status)});
    h.update(c.blob ? c.blob->name : std::string("-"));
    h.update(c.blob ? static_cast<std::int64_t>(c.blob->segment.value) : std::int64_t{-1});
  }
  for (const Transition& t : transitions) {
    h.update(t.source.value()).update(std::int64_t{t.direction.index()});
    h.update(std::int64_t{static_cast<int>(t.outcome)})
        .update(t.target.valid() ? t.target.value() : -1);
  }
  for (const RefinementPoint& r : refinement) {
    h.update(r.cell.value()).update(std::int64_t{r.point}).update(std::int64_t{r.reached});
    h.update(std::span<const double>(r.force)).update(std::span<const double>(r.stiffness));
  }
  return h.value();
}

// The contact probe's clearance from the rest body at every grid point, 4 per point (gap,
// gradient; x-major), for the cursor's contact-onset cells (docs/playback.md). Exact within
// two cell diagonals of the surface, which covers every corner of a cell the sphere enters
// the body in (the clearance changes by at most a cell diagonal across a cell).
std::vector<double> clearance_table(const ProbeModel& probe, const playback::Meta& m) {
  double diagonal = 0;
  for (int a = 0; a < 3; ++a) diagonal += m.spacing[a] * m.spacing[a];
  const double range = 2.0 * std::sqrt(diagonal);
  std::vector<double> out;
  for (int i = 0; i < m.dims[0]; ++i)
    for (int j = 0; j < m.dims[1]; ++j)
      for (int k = 0; k < m.dims[2]; ++k) {
        const int ijk[3] = {m.lo[0] + i, m.lo[1] + j, m.lo[2] + k};
        Eigen::Vector3d p;
        for (int a = 0; a < 3; ++a) p[a] = m.origin[a] + ijk[a] * m.spacing[a];
        const ProbeModel::Clearance c = probe.clearance(p, range).value();  // a contact probe
        out.push_back(c.gap);
        for (int a = 0; a < 3; ++a) out.push_back(c.gradient[a]);
      }
  return out;
}

Gathered gather(StageContext& ctx, ViewNodes view, const NamedHashes& inputs) {
  Catalogue& cat = ctx.catalogue;
  const GridSpec& grid = ctx.grid;
  const std::string where = ctx.dir.root.string();
  Gathered g;
  playback::Meta& m = g.content.meta;
  for (int a = 0; a < 3; ++a) {
    m.origin[a] = grid.origin[a];
    m.spacing[a] = grid.spacing[a];
    m.rest_position[a] = ctx.problem.probe_rest[a];
    m.lo[a] = grid.lo[a];
    m.dims[a] = grid.hi[a] - grid.lo[a] + 1;
  }
  m.max_force = ctx.scene.probe.max_force;
  m.unit = ctx.problem.unit;
  m.probe_mode = static_cast<std::int32_t>(ctx.scene.probe.mode == ProbeMode::kContact
                                               ? playback::ProbeModeCode::kContact
                                               : playback::ProbeModeCode::kGrab);
  m.num_mesh_nodes = ctx.problem.mesh.num_nodes();
  m.view_all_nodes = view == ViewNodes::kAll;
  m.scene_hash = ctx.scene_record.hash.value;

  // Grid points and the configurations at them, in (point, level) order.
  const std::int64_t points = std::int64_t(m.dims[0]) * m.dims[1] * m.dims[2];
  std::map<std::int64_t, std::int32_t> point_of_checkpoint;  // checkpoint id -> grid point
  for (const Checkpoint& c : cat.read_all_checkpoints()) {
    const std::int32_t p = playback::grid_point_index(m, {c.ijk[0], c.ijk[1], c.ijk[2]});
    if (p >= 0) point_of_checkpoint.emplace(c.id.value(), p);
  }
  std::vector<std::pair<std::int32_t, Configuration>> ordered;
  for (Configuration& c : cat.read_all_configurations()) {
    if (c.status == ConfigStatus::kMerged) continue;
    const auto p = point_of_checkpoint.find(c.checkpoint.value());
    if (p == point_of_checkpoint.end()) continue;
    ordered.emplace_back(p->second, std::move(c));
  }
  std::sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second.level.value() < b.second.level.value();
  });
  if (ordered.empty())
    throw InputError(where + ": no configurations: run hapstate-grid and hapstate-expand first");
  playback::Content& c = g.content;
  c.checkpoints.assign(2 * points, 0);
  for (std::int64_t p = 0; p < points; ++p) c.checkpoints[2 * p] = -1;
  std::map<std::int64_t, std::int32_t> index_of;  // configuration id -> file index
  // grid point of check-point (0, 0, 0), -1 if outside the grid
  const std::int32_t rest_point = playback::grid_point_index(m, {0, 0, 0});
  m.rest_configuration = -1;
  for (std::size_t k = 0; k < ordered.size(); ++k) {
    const auto& [p, conf] = ordered[k];
    if (c.checkpoints[2 * p] < 0) c.checkpoints[2 * p] = static_cast<std::int32_t>(k);
    ++c.checkpoints[2 * p + 1];
    index_of.emplace(conf.id.value(), static_cast<std::int32_t>(k));
    c.config_checkpoint.push_back(p);
    c.config_level.push_back(conf.level.value());
    c.config_zero.push_back(conf.blob ? 0 : 1);  // no blob: the body at rest
    c.force.insert(c.force.end(), conf.force.begin(), conf.force.end());
    c.stiffness.insert(c.stiffness.end(), conf.stiffness.begin(), conf.stiffness.end());
    if (!conf.blob && p == rest_point && conf.level.value() == 0)
      m.rest_configuration = static_cast<std::int32_t>(k);
    g.configs.push_back(conf);
  }
  if (m.rest_configuration < 0)
    throw InputError(
        where + ": no zero configuration at the rest check-point (0, 0, 0): run hapstate-grid");

  const std::vector<Transition> transitions = cat.read_all_transitions();
  c.transitions.assign(grid::kDirections * ordered.size(), playback::kUndecided);
  for (const Transition& t : transitions) {
    const auto s = index_of.find(t.source.value());
    if (s == index_of.end()) continue;
    std::int32_t code = playback::kFailed;
    if (t.outcome == TransitionOutcome::kOutsideGrid) code = playback::kOutsideGrid;
    if (t.outcome == TransitionOutcome::kReached) {
      const auto target = index_of.find(t.target.value());
      code = target == index_of.end() ? playback::kUndecided : target->second;
    }
    c.transitions[grid::kDirections * s->second + t.direction.index()] = code;
    if (t.midpoint_force && code >= 0) {
      const auto o = t.direction.offset();
      const int d = playback::midpoint_direction(o[0], o[1], o[2]);
      if (c.midpoint_force.empty())
        c.midpoint_force.assign(3 * playback::kMidpointDirections * ordered.size(),
                                std::numeric_limits<double>::quiet_NaN());
      if (d >= 0)
        std::copy_n(t.midpoint_force->begin(), 3,
                    c.midpoint_force.begin() + 3 * (playback::kMidpointDirections * s->second + d));
      if (d >= 0 && t.midpoint_blob) {
        if (g.midpoint_blobs.empty()) {
          g.midpoint_blobs.resize(playback::kMidpointDirections * ordered.size());
          c.midpoint_displacement_mask.assign(ordered.size(), 0);
        }
        g.midpoint_blobs[playback::kMidpointDirections * s->second + d] = t.midpoint_blob;
        c.midpoint_displacement_mask[s->second] |= 1 << d;
      }
      if (d >= 0 && t.midpoint_stiffness) {
        if (c.midpoint_stiffness.empty())
          c.midpoint_stiffness.assign(9 * playback::kMidpointDirections * ordered.size(),
                                      std::numeric_limits<double>::quiet_NaN());
        std::copy_n(
            t.midpoint_stiffness->begin(), 9,
            c.midpoint_stiffness.begin() + 9 * (playback::kMidpointDirections * s->second + d));
      }
    }
  }

  // View nodes, their reference positions and the surface triangles.
  const Mesh& mesh = ctx.problem.mesh;
  std::vector<std::int32_t> view_of(mesh.num_nodes(), -1);
  if (view == ViewNodes::kAll) {
    for (int n = 0; n < mesh.num_nodes(); ++n) view_of[n] = n;
  } else {
    for (Eigen::Index t = 0; t < mesh.surface.cols(); ++t)
      for (int r = 0; r < 3; ++r) view_of[mesh.surface(r, t)] = 0;
    std::int32_t next = 0;
    for (int n = 0; n < mesh.num_nodes(); ++n)
      if (view_of[n] == 0) view_of[n] = next++;
  }
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (view_of[n] < 0) continue;
    c.view_nodes.push_back(n);
    for (int r = 0; r < 3; ++r) c.reference.push_back(static_cast<float>(mesh.nodes(r, n)));
  }
  for (Eigen::Index t = 0; t < mesh.surface.cols(); ++t)
    for (int r = 0; r < 3; ++r) c.triangles.push_back(view_of[mesh.surface(r, t)]);
  if (ctx.scene.probe.mode == ProbeMode::kContact) {
    const auto probe = make_probe_model(ctx.problem);
    c.clearance = clearance_table(*probe, m);
    c.onset = playback::onset_corners(c);
    if (const auto surface = probe->rest_surface())
      playback::add_onset_triangles(&c, surface->triangles, surface->radius);
  }
  const std::vector<RefinementPoint> refinement = cat.read_all_refinement_points();
  add_refined_cells(refinement, index_of, &c);
  g.fingerprint = fingerprint_of(g.configs, transitions, refinement, inputs, view);
  m.source_hash = g.fingerprint.value;
  return g;
}

// Whether `file` opens as a playback file built from `fingerprint`.
bool up_to_date(const std::filesystem::path& file, const ContentHash& fingerprint) {
  if (!std::filesystem::exists(file)) return false;
  try {
    PlaybackFile f(file);
    return f.source_hash() == fingerprint.value;
  } catch (const std::exception&) {
    return false;
  }
}

// What an existing playback file holds, for the message when it is replaced ("" if none).
std::string describe_existing(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) return "";
  try {
    PlaybackFile f(file);
    return std::to_string(f.num_configurations()) + " configurations, " +
           (f.view_is_all_nodes() ? "all nodes" : "surface nodes");
  } catch (const std::exception&) {
    return "an unreadable or older file";
  }
}

// The index needs an expansion, complete or partial (stopped by --max-*): the transitions a
// partial one left undecided are stored as kUndecided and the cursor extends past them.
void require_expansion(StageContext& ctx) {
  for (const StageRun& run : ctx.catalogue.read_stage_runs("expand"))
    if (run.outcome == StageOutcome::kOk || run.outcome == StageOutcome::kUnchanged ||
        run.outcome == StageOutcome::kPartial)
      return;
  throw InputError(ctx.dir.root.string() +
                   ": hapstate-expand has not run in this state directory yet: run it first");
}

// Where the file's per-configuration sections come from: each configuration's blob (the zero
// configurations' from the loaded rest state), read while the file is written.
class BlobSections {
 public:
  BlobSections(const StageContext& ctx, const Gathered& g, Progress& progress)
      : ctx_(ctx),
        g_(g),
        blobs_(ctx.dir.blobs()),
        num_nodes_(ctx.problem.mesh.num_nodes()),
        view_nodes_(g.content.view_nodes),
        // The zero configurations' u: the loaded rest state (empty without a body force: zeros).
        rest_u_(ctx.problem.loads.has_force() ? rest_displacements(ctx.problem)
                                              : std::vector<double>{}),
        progress_(progress) {}

  // The view nodes' displacements of configuration k.
  void displacements(std::int32_t k, std::span<float> out) {
    const Configuration& conf = g_.configs[k];
    if (conf.blob) {
      const std::vector<float> u =
          blobs_.read_float32(conf.blob->segment, conf.blob->dataset(BlobVector::kU));
      check_size(u.size(), 3, "displacement values", conf);
      for (std::size_t v = 0; v < view_nodes_.size(); ++v)
        for (int r = 0; r < 3; ++r) out[3 * v + r] = u[3 * std::size_t(view_nodes_[v]) + r];
    } else if (!rest_u_.empty()) {  // a zero configuration: the loaded rest state
      for (std::size_t v = 0; v < view_nodes_.size(); ++v)
        for (int r = 0; r < 3; ++r)
          out[3 * v + r] = static_cast<float>(rest_u_[3 * std::size_t(view_nodes_[v]) + r]);
    }
    progress_.update(k + 1);
  }

  // Whether every configuration has its slopes d u / d p (a state expanded before they were
  // stored has none: the file then has none and Hermite deformation is trilinear).
  bool all_have_slopes() const {
    return std::all_of(g_.configs.begin(), g_.configs.end(), [&](const Configuration& conf) {
      return !conf.blob ||
             blobs_.contains(conf.blob->segment, conf.blob->dataset(BlobVector::kDuDp));
    });
  }

  // The view nodes' slopes of configuration k (none for a zero configuration not touched).
  void slopes(std::int32_t k, std::span<float> out) {
    const Configuration& conf = g_.configs[k];
    std::vector<float> du_dp;
    if (conf.blob) {
      du_dp = blobs_.read_float32(conf.blob->segment, conf.blob->dataset(BlobVector::kDuDp));
    } else if (std::any_of(conf.stiffness.begin(), conf.stiffness.end(),
                           [](double v) { return v != 0.0; })) {
      if (!rest_) rest_ = zero_stiffness(ctx_.dir, ctx_.problem);
      du_dp = rest_->du_dp;
    } else {
      return;  // a zero configuration the probe does not touch: no slopes
    }
    check_size(du_dp.size(), 9, "displacement slope values", conf);
    const std::size_t v = view_nodes_.size();
    for (int a = 0; a < 3; ++a)
      for (std::size_t n = 0; n < v; ++n)
        for (int r = 0; r < 3; ++r)
          out[3 * (a * v + n) + r] =
              du_dp[std::size_t(a) * 3 * num_nodes_ + 3 * std::size_t(view_nodes_[n]) + r];
  }

  // The view nodes' displacements and slopes half-way along configuration k's midpoint
  // directions, where stored.
  void midpoints(std::int32_t k, std::span<float> out) {
    const std::size_t v = view_nodes_.size();
    for (int d = 0; d < playback::kMidpointDirections; ++d) {
      const std::optional<BlobRef>& ref =
          g_.midpoint_blobs[playback::kMidpointDirections * std::size_t(k) + d];
      if (!ref) continue;
      const std::vector<float> u = blobs_.read_float32(ref->segment, ref->dataset(BlobVector::kU));
      const std::vector<float> du_dp =
          blobs_.read_float32(ref->segment, ref->dataset(BlobVector::kDuDp));
      if (static_cast<int>(u.size()) != 3 * num_nodes_ ||
          static_cast<int>(du_dp.size()) != 9 * num_nodes_)
        throw InputError(ctx_.dir.blobs().string() + ": midpoint vectors " + ref->name + " have " +
                         std::to_string(u.size()) + " and " + std::to_string(du_dp.size()) +
                         " values, the mesh needs " + std::to_string(3 * num_nodes_) + " and " +
                         std::to_string(9 * num_nodes_));
      float* row = out.data() + 12 * v * d;
      for (std::size_t n = 0; n < v; ++n)
        for (int r = 0; r < 3; ++r) {
          const std::size_t node = 3 * std::size_t(view_nodes_[n]) + r;
          row[3 * n + r] = u[node];
          for (int a = 0; a < 3; ++a)
            row[3 * ((1 + a) * v + n) + r] = du_dp[std::size_t(a) * 3 * num_nodes_ + node];
        }
    }
  }

 private:
  void check_size(std::size_t have, int per_node, const char* what,
                  const Configuration& conf) const {
    if (static_cast<int>(have) != per_node * num_nodes_)
      throw InputError(ctx_.dir.blobs().string() + ": configuration " +
                       std::to_string(conf.id.value()) + " has " + std::to_string(have) + " " +
                       what + ", the mesh needs " + std::to_string(per_node * num_nodes_));
  }

  const StageContext& ctx_;
  const Gathered& g_;
  BlobStore blobs_;
  int num_nodes_;
  std::vector<std::int32_t> view_nodes_;
  std::vector<double> rest_u_;
  std::optional<RestStiffness> rest_;  // of the zero configurations, read once
  Progress& progress_;
};

// Writes the playback file of `g` to report.output; returns the report's message.
std::string write_playback(const IndexOptions& options, const StageContext& ctx, Gathered& g,
                           IndexReport& report) {
  const std::string replaced = describe_existing(report.output);
  Progress progress("hapstate-index: displacements", static_cast<long long>(g.configs.size()),
                    options.progress);
  BlobSections sections(ctx, g, progress);
  g.content.displacements = [&](std::int32_t k, std::span<float> out) {
    sections.displacements(k, out);
  };
  report.slopes = sections.all_have_slopes();
  if (report.slopes)
    g.content.displacement_slopes = [&](std::int32_t k, std::span<float> out) {
      sections.slopes(k, out);
    };
  if (!report.slopes) g.content.midpoint_displacement_mask.clear();  // deform() needs both
  if (!g.content.midpoint_displacement_mask.empty())
    g.content.midpoint_displacements = [&](std::int32_t k, std::span<float> out) {
      sections.midpoints(k, out);
    };
  playback::write_file(std::move(g.content), report.output);
  progress.finish();
  report.bytes = static_cast<std::int64_t>(std::filesystem::file_size(report.output));
  char text[512];
  std::snprintf(text, sizeof text, "%lld configurations, %lld view nodes, %s%s",
                static_cast<long long>(report.configurations),
                static_cast<long long>(report.view_nodes), size_text(report.bytes).c_str(),
                report.slopes ? ""
                              : "; no displacement slopes (a state expanded before they "
                                "were stored): Hermite deformation falls back to trilinear");
  std::string message = "wrote " + report.output.string() + ": " + text;
  if (!replaced.empty()) message += " (replaced the previous file: " + replaced + ")";
  return message;
}

}  // namespace

void IndexOptions::check() const {
  if (state.empty()) throw InputError("--state: no state directory given");
  if (!output.empty() && output.filename().empty())
    throw InputError("--output " + output.string() + ": names a directory, not a file");
}

IndexReport run_index(const IndexOptions& options) {
  options.check();
  const auto start = std::chrono::steady_clock::now();
  StageContext ctx = open_stage_context(options.state);
  require_expansion(ctx);
  IndexReport report;
  report.output = options.output.empty() ? ctx.dir.root / "playback.bin" : options.output;
  const NamedHashes inputs = {{"problem", ctx.problem_hash}, {"scene", ctx.scene_record.hash}};
  Gathered g = gather(ctx, options.view, inputs);
  report.configurations = static_cast<std::int64_t>(g.configs.size());
  report.view_nodes = static_cast<std::int64_t>(g.content.view_nodes.size());
  const std::string params = "output=" + report.output.string() +
                             " nodes=" + (options.view == ViewNodes::kAll ? "all" : "surface");
  StageRunFrame frame(ctx.catalogue, "index",
                      {{"configurations", g.fingerprint},
                       {"problem", ctx.problem_hash},
                       {"scene", ctx.scene_record.hash}},
                      params, start);
  if (up_to_date(report.output, g.fingerprint)) {
    report.bytes = static_cast<std::int64_t>(std::filesystem::file_size(report.output));
    return frame.unchanged(report, "unchanged: " + report.output.string() + " is up to date (" +
                                       std::to_string(report.configurations) + " configurations)");
  }
  frame.run(report, [&] { report.message = write_playback(options, ctx, g, report); });
  return report;
}

}  // namespace hapstate
