#include "playback_fixtures.h"

#include "io/probe_path.h"
#include "mesh/box_mesh.h"
#include "playback/writer.h"
#include "scene/bind.h"
#include "scene/scene.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

namespace hapstate::bench {
namespace {

[[noreturn]] void fatal(const std::string& what) {
  std::fprintf(stderr, "playback_bench: %s\n", what.c_str());
  std::exit(2);
}

void run_stage(const std::string& command) {
  std::fprintf(stderr, "playback_bench: %s\n", command.c_str());
  if (std::system(command.c_str()) != 0) fatal("failed: " + command);
}

std::filesystem::path build_liver_playback() {
  const std::filesystem::path state = HAPSTATE_BUILD_DIR "/bench/liver_state";
  const std::filesystem::path file = state / "playback.bin";
  if (std::filesystem::exists(file)) return file;
  const std::string stages = HAPSTATE_STAGES_DIR;
  const std::string s = " --state '" + state.string() + "'";
  run_stage(stages + "/hapstate-import '" HAPSTATE_SOURCE_DIR "/pipelines/liver/scene.toml'" + s);
  run_stage(stages + "/hapstate-grid" + s);
  run_stage(stages + "/hapstate-expand" + s + " --max-seconds 60 --threads 2 -q");
  run_stage(stages + "/hapstate-index" + s);
  return file;
}

// Removes the synthetic file's directory at exit.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "hapstate_bench_XXXXXX").string();
    if (!mkdtemp(pattern.data())) fatal("cannot create a temporary directory");
    path = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

constexpr int kCells = 36;  // per axis: 37^3 = 50 653 nodes
constexpr double kSpacing = 0.25;
constexpr double kStiffness = 2.0;  // N per mesh unit

// With `midpoints` the grid is 2 x 2 x 2 (one cell: 7 midpoints per configuration of 50 653
// view nodes would take 2 GB on the 5 x 5 x 5 grid) and every midpoint's force, stiffness,
// displacements and slopes are stored (the same linear fields, exact there).
void write_synthetic(const std::filesystem::path& file, bool midpoints) {
  const int grid = midpoints ? 2 : 5;
  const Mesh mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(10.0), kCells,
                                  kCells, kCells);
  const int nodes = mesh.num_nodes();
  const Eigen::Vector3d rest(5.0, 5.0, 10.0);  // middle of the top face
  playback::Content c;
  playback::Meta& m = c.meta;
  for (int a = 0; a < 3; ++a) {
    m.origin[a] = rest[a];
    m.spacing[a] = kSpacing;
    m.rest_position[a] = rest[a];
    m.lo[a] = midpoints ? 0 : -(grid / 2);  // one cell: the rest point its first corner
    m.dims[a] = grid;
  }
  m.max_force = 3.0;
  m.unit = 0.01;
  m.probe_mode = static_cast<std::int32_t>(playback::ProbeModeCode::kGrab);
  m.num_mesh_nodes = nodes;
  m.view_all_nodes = 1;
  const int points = grid * grid * grid;
  auto ijk = [grid](int g) {
    return std::array<int, 3>{g / (grid * grid), (g / grid) % grid, g % grid};
  };
  m.rest_configuration = midpoints ? 0 : ((grid / 2) * grid + grid / 2) * grid + grid / 2;
  for (int g = 0; g < points; ++g) {  // configuration g at check-point g
    const auto p = ijk(g);
    c.checkpoints.insert(c.checkpoints.end(), {g, 1});
    c.config_checkpoint.push_back(g);
    c.config_level.push_back(0);
    c.config_zero.push_back(g == m.rest_configuration ? 1 : 0);
    for (int a = 0; a < 3; ++a) c.force.push_back(-kStiffness * (p[a] + m.lo[a]) * kSpacing);
    for (int r = 0; r < 9; ++r) c.stiffness.push_back(r % 4 == 0 ? -kStiffness : 0.0);
    for (int d = 0; d < 27; ++d) {
      if (d == 13) continue;  // the centre: directions are numbered 0..25 around it
      const std::array<int, 3> q{p[0] + d / 9 - 1, p[1] + (d / 3) % 3 - 1, p[2] + d % 3 - 1};
      const bool inside =
          q[0] >= 0 && q[1] >= 0 && q[2] >= 0 && q[0] < grid && q[1] < grid && q[2] < grid;
      c.transitions.push_back(inside ? (q[0] * grid + q[1]) * grid + q[2] : playback::kOutsideGrid);
    }
  }
  // Three smooth fields: a Gaussian bump around the probe along x, y and z.
  auto bump = std::make_shared<std::vector<float>>(nodes);
  for (int n = 0; n < nodes; ++n) {
    c.view_nodes.push_back(n);
    for (int a = 0; a < 3; ++a) c.reference.push_back(static_cast<float>(mesh.nodes(a, n)));
    (*bump)[n] = static_cast<float>(std::exp(-(mesh.nodes.col(n) - rest).squaredNorm() / 18.0));
  }
  c.triangles.assign(mesh.surface.data(), mesh.surface.data() + mesh.surface.size());
  c.displacements = [bump, ijk, lo = m.lo[0]](std::int32_t k, std::span<float> out) {
    const auto p = ijk(k);
    for (std::size_t n = 0; n < bump->size(); ++n)
      for (int a = 0; a < 3; ++a)
        out[3 * n + a] = static_cast<float>((p[a] + lo) * kSpacing) * (*bump)[n];
  };
  // Their slopes: d u_a / d p_b = bump if a == b (the arrays of axis b, 3 per node).
  c.displacement_slopes = [bump](std::int32_t, std::span<float> out) {
    const std::size_t v = bump->size();
    for (int b = 0; b < 3; ++b)
      for (std::size_t n = 0; n < v; ++n)
        for (int a = 0; a < 3; ++a) out[3 * (b * v + n) + a] = a == b ? (*bump)[n] : 0.0f;
  };
  if (midpoints) {
    c.midpoint_force.assign(3 * playback::kMidpointDirections * points, 0.0);
    c.midpoint_stiffness.assign(9 * playback::kMidpointDirections * points, 0.0);
    c.midpoint_displacement_mask.assign(points, 0);
    for (int g = 0; g < points; ++g)
      for (int d = 0; d < playback::kMidpointDirections; ++d) {
        const auto p = ijk(g);
        const int* o = playback::kMidpointOffsets[d];
        if (p[0] + o[0] >= grid || p[1] + o[1] >= grid || p[2] + o[2] >= grid) continue;
        c.midpoint_displacement_mask[g] |= 1 << d;
        const std::size_t at = playback::kMidpointDirections * std::size_t(g) + d;
        for (int a = 0; a < 3; ++a) {
          c.midpoint_force[3 * at + a] = -kStiffness * (p[a] + m.lo[a] + 0.5 * o[a]) * kSpacing;
          c.midpoint_stiffness[9 * at + 4 * a] = -kStiffness;
        }
      }
    c.midpoint_displacements = [bump, ijk, lo = m.lo[0], grid](std::int32_t k,
                                                               std::span<float> out) {
      const auto p = ijk(k);
      const std::size_t v = bump->size();
      for (int d = 0; d < playback::kMidpointDirections; ++d) {
        const int* o = playback::kMidpointOffsets[d];
        if (p[0] + o[0] >= grid || p[1] + o[1] >= grid || p[2] + o[2] >= grid) continue;
        float* row = out.data() + 12 * v * d;
        for (std::size_t n = 0; n < v; ++n)
          for (int a = 0; a < 3; ++a) {
            row[3 * n + a] = static_cast<float>((p[a] + lo + 0.5 * o[a]) * kSpacing) * (*bump)[n];
            for (int b = 0; b < 3; ++b) row[3 * ((1 + b) * v + n) + a] = a == b ? (*bump)[n] : 0.0f;
          }
      }
    };
  }
  playback::write_file(std::move(c), file);
}

// The playback file `make` returns the path of (made on first use), opened and verified; a
// failure ends the benchmark with its message.
template <typename Make>
std::unique_ptr<PlaybackFile> open_verified(Make&& make) {
  try {
    auto f = std::make_unique<PlaybackFile>(make());
    f->verify();
    return f;
  } catch (const std::exception& e) {
    fatal(e.what());
  }
}

}  // namespace

const PlaybackFile& liver_playback() {
  static const std::unique_ptr<PlaybackFile> file = open_verified([] {
    const char* env = std::getenv("HAPSTATE_PLAYBACK");
    return env && *env ? std::filesystem::path(env) : build_liver_playback();
  });
  return *file;
}

const PlaybackFile& synthetic_playback() {
  static TempDir dir;
  static const std::unique_ptr<PlaybackFile> file = open_verified([] {
    const std::filesystem::path path = dir.path / "synthetic.bin";
    write_synthetic(path, false);
    return path;
  });
  return *file;
}

const PlaybackFile& synthetic_midpoint_playback() {
  static TempDir dir;
  static const std::unique_ptr<PlaybackFile> file = open_verified([] {
    const std::filesystem::path path = dir.path / "synthetic_midpoints.bin";
    write_synthetic(path, true);
    return path;
  });
  return *file;
}

const Problem& liver_problem() {
  static const Problem problem =
      build_problem(load_scene(HAPSTATE_SOURCE_DIR "/pipelines/liver/scene.toml"));
  return problem;
}

std::vector<std::array<double, 3>> device_path(const PlaybackFile& file, int steps, double step,
                                               std::uint64_t seed) {
  Eigen::Vector3d lo, hi, rest;
  for (int a = 0; a < 3; ++a) {
    lo[a] = file.grid_origin()[a] + file.grid_lo()[a] * file.grid_spacing()[a];
    hi[a] = lo[a] + (file.grid_dims()[a] - 1) * file.grid_spacing()[a];
    rest[a] = file.rest_position()[a];
  }
  const ProbePath walk = random_path(rest, steps, step, lo, hi, seed);
  std::vector<std::array<double, 3>> path;
  path.reserve(2 * walk.size());
  for (const Eigen::Vector3d& p : walk) path.push_back({p.x(), p.y(), p.z()});
  for (auto it = walk.rbegin(); it != walk.rend(); ++it)
    path.push_back({it->x(), it->y(), it->z()});
  return path;
}

}  // namespace hapstate::bench
