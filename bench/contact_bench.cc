// Collision detection of the contact probe on the liver surfaces: which surface nodes lie
// inside the sphere. Deformed surface (the solver's case): the points move between queries, so
// an index pays its rebuild every time: our grid hash (solver/sphere_query.h), a nanoflann k-d
// tree (when its header is installed), against a plain scan. Rest surface (the grid stage and
// the free-move test): one build, many queries ("QueryOnly").
// Run: build/bench/contact_bench (see docs/contact.md).
#include "mesh/load.h"
#include "scene/select.h"
#include "solver/sphere_query.h"

#include <benchmark/benchmark.h>

#if __has_include(<nanoflann.hpp>)
#include <nanoflann.hpp>
#define HAPSTATE_HAVE_NANOFLANN 1
#endif

#include <map>
#include <memory>
#include <random>
#include <string>

namespace hapstate {
namespace {

const char* const kMeshes[] = {"liver.msh", "liverSemiFine.vtu", "liverFine.vtu"};

// Surface nodes of a mesh, slightly deformed, and probe centres near the surface; the sphere
// radius is one mean surface-node spacing times 2 (a few nodes touched).
struct Setup {
  Eigen::Matrix3Xd points;
  std::vector<Eigen::Vector3d> centres;
  double radius = 0;
};

Setup& setup(int index) {
  static std::map<int, std::unique_ptr<Setup>> cache;
  auto& s = cache[index];
  if (!s) {
    s = std::make_unique<Setup>();
    const Mesh mesh = load_mesh(std::string(HAPSTATE_DATA_DIR) + "/meshes/" + kMeshes[index]);
    const std::vector<int> surface = surface_nodes(mesh);
    s->points.resize(3, static_cast<Eigen::Index>(surface.size()));
    std::mt19937 rng(1);
    std::normal_distribution<double> jitter(0.0, 0.01);
    for (std::size_t k = 0; k < surface.size(); ++k)
      s->points.col(static_cast<Eigen::Index>(k)) =
          mesh.nodes.col(surface[k]) + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
    const Eigen::Vector3d extent =
        mesh.nodes.rowwise().maxCoeff() - mesh.nodes.rowwise().minCoeff();
    s->radius = 2.0 * std::cbrt(extent.prod() / static_cast<double>(mesh.num_nodes()));
    std::uniform_int_distribution<int> pick(0, static_cast<int>(surface.size()) - 1);
    for (int q = 0; q < 256; ++q) s->centres.push_back(s->points.col(pick(rng)));
  }
  return *s;
}

void report(benchmark::State& state, const Setup& s, std::size_t found) {
  state.counters["surface_nodes"] = static_cast<double>(s.points.cols());
  state.counters["touched_per_query"] =
      static_cast<double>(found) / static_cast<double>(state.iterations());
}

void BM_GridHash(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  SphereQuery index;
  std::vector<int> out;
  std::size_t q = 0, found = 0;
  for (auto _ : state) {
    index.build(s.points, s.radius);
    out.clear();
    index.inside(s.centres[q++ % s.centres.size()], s.radius, &out);
    found += out.size();
    benchmark::DoNotOptimize(out.data());
  }
  report(state, s, found);
}

void BM_Scan(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  std::vector<int> out;
  std::size_t q = 0, found = 0;
  for (auto _ : state) {
    out.clear();
    points_inside_by_scan(s.points, s.centres[q++ % s.centres.size()], s.radius, &out);
    found += out.size();
    benchmark::DoNotOptimize(out.data());
  }
  report(state, s, found);
}

#ifdef HAPSTATE_HAVE_NANOFLANN
struct Cloud {
  const Eigen::Matrix3Xd* points;
  std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(points->cols()); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const {
    return (*points)(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(i));
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using Tree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3>;

void BM_NanoflannKdTree(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  Cloud cloud{&s.points};
  std::vector<std::pair<std::uint32_t, double>> matches;
  std::size_t q = 0, found = 0;
  for (auto _ : state) {
    Tree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    tree.buildIndex();
    const Eigen::Vector3d& c = s.centres[q++ % s.centres.size()];
    matches.clear();
    found += tree.radiusSearch(c.data(), s.radius * s.radius, matches, nanoflann::SearchParams());
    benchmark::DoNotOptimize(matches.data());
  }
  report(state, s, found);
}
BENCHMARK(BM_NanoflannKdTree)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

void BM_NanoflannKdTreeQueryOnly(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  Cloud cloud{&s.points};
  Tree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  std::vector<std::pair<std::uint32_t, double>> matches;
  std::size_t q = 0, found = 0;
  for (auto _ : state) {
    const Eigen::Vector3d& c = s.centres[q++ % s.centres.size()];
    matches.clear();
    found += tree.radiusSearch(c.data(), s.radius * s.radius, matches, nanoflann::SearchParams());
    benchmark::DoNotOptimize(matches.data());
  }
  report(state, s, found);
}
BENCHMARK(BM_NanoflannKdTreeQueryOnly)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
#endif

void BM_GridHashQueryOnly(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  SphereQuery index;
  index.build(s.points, s.radius);
  std::vector<int> out;
  std::size_t q = 0, found = 0;
  for (auto _ : state) {
    out.clear();
    index.inside(s.centres[q++ % s.centres.size()], s.radius, &out);
    found += out.size();
    benchmark::DoNotOptimize(out.data());
  }
  report(state, s, found);
}
BENCHMARK(BM_GridHashQueryOnly)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

BENCHMARK(BM_GridHash)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Scan)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hapstate

BENCHMARK_MAIN();
