// Fills a closed triangle surface with tets through Gmsh, falling back to carving a tet grid
// (carve.h) for self-intersecting surfaces. libgmsh pulls in about ninety shared libraries
// (OpenCASCADE, FLTK, X11, OpenGL); linked into every tool it cost 0.1 s of dynamic loading at
// each start (hapstate-solve on the bundled liver: 0.11 s of its 0.16 s). It is therefore
// loaded with dlopen when a surface is to be filled, and called through its C API (gmshc.h,
// whose declarations type-check the function pointers). Gmsh keeps global state, so every use
// is serialised by one mutex and wrapped in initialize/finalize. (libgmsh 4.8 installs no
// signal handlers; terminal output is switched off.)
#include "mesh/surface.h"

#include "mesh/carve.h"
#include "util/error.h"

#include <dlfcn.h>
#include <gmshc.h>

#include <mutex>
#include <sstream>
#include <stdexcept>

namespace hapstate {
namespace {

// One function a line (clang-format would indent the X-macro list unevenly).
// clang-format off
#define HAPSTATE_GMSH_FUNCTIONS(X) \
  X(gmshInitialize) \
  X(gmshFinalize) \
  X(gmshOptionSetNumber) \
  X(gmshModelAdd) \
  X(gmshModelAddDiscreteEntity) \
  X(gmshModelMeshAddNodes) \
  X(gmshModelMeshAddElementsByType) \
  X(gmshModelGeoAddSurfaceLoop) \
  X(gmshModelGeoAddVolume) \
  X(gmshModelGeoSynchronize) \
  X(gmshModelMeshGenerate) \
  X(gmshModelMeshGetNodes) \
  X(gmshModelMeshGetElementsByType) \
  X(gmshLoggerGetLastError) \
  X(gmshFree)
// clang-format on

// The Gmsh C API, loaded once (HAPSTATE_GMSH_LIBRARY: the library the build found).
struct GmshApi {
// NOLINTNEXTLINE(bugprone-macro-parentheses): f names a member; it cannot be parenthesised.
#define HAPSTATE_GMSH_POINTER(f) decltype(&::f) f = nullptr;
  HAPSTATE_GMSH_FUNCTIONS(HAPSTATE_GMSH_POINTER)
#undef HAPSTATE_GMSH_POINTER
  std::string error;  // why it could not be loaded (empty if loaded)
};

const GmshApi& gmsh_api() {
  static const GmshApi api = [] {
    GmshApi g;
    void* library = dlopen(HAPSTATE_GMSH_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    if (library == nullptr) {
      const char* why = dlerror();
      g.error = std::string("cannot load the Gmsh library: ") + (why ? why : HAPSTATE_GMSH_LIBRARY);
      return g;
    }
#define HAPSTATE_GMSH_LOAD(f)                                 \
  g.f = reinterpret_cast<decltype(&::f)>(dlsym(library, #f)); \
  if (g.f == nullptr && g.error.empty())                      \
    g.error = std::string("the Gmsh library " HAPSTATE_GMSH_LIBRARY " has no ") + #f;
    HAPSTATE_GMSH_FUNCTIONS(HAPSTATE_GMSH_LOAD)
#undef HAPSTATE_GMSH_LOAD
    return g;
  }();
  return api;
}

std::mutex& gmsh_mutex() {
  static std::mutex m;
  return m;
}

// Throws with Gmsh's last error when a call reported one (ierr != 0).
void check(const GmshApi& g, int ierr, const char* what) {
  if (ierr == 0) return;
  std::string message = what;
  char* last = nullptr;
  int ignored = 0;
  g.gmshLoggerGetLastError(&last, &ignored);
  if (last != nullptr) {
    if (*last != '\0') message += std::string(": ") + last;
    g.gmshFree(last);
  }
  throw std::runtime_error(message);
}

// An array Gmsh allocated, released with gmshFree on every path.
template <typename T>
struct GmshArray {
  GmshArray(const GmshApi& g, T* p) : g_(g), p_(p) {}
  ~GmshArray() {
    if (p_ != nullptr) g_.gmshFree(p_);
  }
  GmshArray(const GmshArray&) = delete;
  GmshArray& operator=(const GmshArray&) = delete;
  const GmshApi& g_;
  T* p_;
};

// gmshInitialize / gmshFinalize as a scope guard.
struct GmshSession {
  explicit GmshSession(const GmshApi& g) : g_(g) {
    int ierr = 0;
    g_.gmshInitialize(0, nullptr, /*readConfigFiles=*/0, &ierr);
    check(g_, ierr, "initialize");
    g_.gmshOptionSetNumber("General.Terminal", 0, &ierr);
    g_.gmshOptionSetNumber("General.Verbosity", 1, &ierr);
  }
  ~GmshSession() {
    int ierr = 0;
    g_.gmshFinalize(&ierr);
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
  const GmshApi& g_;
};

}  // namespace

RawMesh tetrahedralize_surface(const TriangleSurface& s) {
  std::lock_guard<std::mutex> lock(gmsh_mutex());
  RawMesh mesh;
  mesh.source = s.source;
  const std::string failure = s.source + ": Gmsh could not fill the surface with tetrahedra: ";
  const GmshApi& g = gmsh_api();
  // Not bad input, and not a reason to carve instead (a different mesh): the installation lacks
  // the library it was built with.
  if (!g.error.empty()) throw std::runtime_error(s.source + ": " + g.error);
  try {
    GmshSession session(g);
    int ierr = 0;
    g.gmshModelAdd("surface", &ierr);
    check(g, ierr, "model");
    g.gmshModelAddDiscreteEntity(2, 1, nullptr, 0, &ierr);
    check(g, ierr, "discrete surface");
    std::vector<std::size_t> node_tags(s.xyz.size() / 3);
    for (std::size_t i = 0; i < node_tags.size(); ++i) node_tags[i] = i + 1;
    std::vector<double> xyz = s.xyz;
    g.gmshModelMeshAddNodes(2, 1, node_tags.data(), node_tags.size(), xyz.data(), xyz.size(),
                            nullptr, 0, &ierr);
    check(g, ierr, "surface nodes");
    std::vector<std::size_t> tri_nodes;
    tri_nodes.reserve(3 * s.faces.size());
    for (const auto& f : s.faces) {
      for (int v : f) tri_nodes.push_back(static_cast<std::size_t>(v) + 1);
    }
    g.gmshModelMeshAddElementsByType(1, 2, nullptr, 0, tri_nodes.data(), tri_nodes.size(), &ierr);
    check(g, ierr, "surface triangles");
    int surface = 1;
    int loop = g.gmshModelGeoAddSurfaceLoop(&surface, 1, -1, &ierr);
    check(g, ierr, "surface loop");
    g.gmshModelGeoAddVolume(&loop, 1, -1, &ierr);
    check(g, ierr, "volume");
    g.gmshModelGeoSynchronize(&ierr);
    check(g, ierr, "synchronize");
    g.gmshModelMeshGenerate(3, &ierr);
    check(g, ierr, "mesh generation");

    std::size_t* tags = nullptr;
    double* coords = nullptr;
    double* params = nullptr;
    std::size_t num_tags = 0, num_coords = 0, num_params = 0;
    g.gmshModelMeshGetNodes(&tags, &num_tags, &coords, &num_coords, &params, &num_params, -1, -1,
                            /*includeBoundary=*/0, /*returnParametricCoord=*/0, &ierr);
    const GmshArray<std::size_t> own_tags(g, tags);
    const GmshArray<double> own_coords(g, coords), own_params(g, params);
    check(g, ierr, "nodes");
    NodeTags index;
    mesh.xyz.assign(coords, coords + num_coords);
    for (std::size_t i = 0; i < num_tags; ++i)
      index.add(static_cast<long long>(tags[i]), static_cast<int>(i));
    std::size_t* tet_tags = nullptr;
    std::size_t* tet_nodes = nullptr;
    std::size_t num_tets = 0, num_tet_nodes = 0;
    g.gmshModelMeshGetElementsByType(4, &tet_tags, &num_tets, &tet_nodes, &num_tet_nodes, -1, 0, 1,
                                     &ierr);
    const GmshArray<std::size_t> own_tet_tags(g, tet_tags), own_tet_nodes(g, tet_nodes);
    check(g, ierr, "tetrahedra");
    for (std::size_t t = 0; t < num_tets && 4 * t + 3 < num_tet_nodes; ++t) {
      std::array<int, 4> tet{};
      for (int k = 0; k < 4; ++k) {
        tet[k] = index.find(static_cast<long long>(tet_nodes[4 * t + k]));
        if (tet[k] < 0) throw InputError(failure + "Gmsh returned a tet with an unknown node");
      }
      mesh.tets.push_back(tet);
    }
    if (mesh.tets.empty()) throw InputError(failure + "no tetrahedra generated");
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(failure + e.what());
  } catch (...) {
    throw InputError(failure + "unknown Gmsh error");
  }
  return mesh;
}

RawMesh fill_closed_surface(const TriangleSurface& s) {
  check_surface_topology(
      s);  // holes and non-manifold edges stay errors: carving needs a closed surface
  std::string why;
  if (const auto hit = find_self_intersection(s)) {
    why = "the surface self-intersects near " + hit->near() + " (" + hit->face +
          " is crossed by the edge (" + std::to_string(hit->edge[0] + 1) + ", " +
          std::to_string(hit->edge[1] + 1) + "))";
  } else {
    try {
      return tetrahedralize_surface(s);
    } catch (const InputError& e) {
      why = std::string("Gmsh could not fill the surface (") + e.what() + ")";
    }
  }
  CarveResult carved = carve_surface(s);
  std::ostringstream w;
  w.precision(4);
  w << s.source << ": " << why
    << "; the volume was carved on a grid of cell size h = " << carved.cell_size << " ("
    << carved.tets << " tets, enclosed-volume ratio carved/surface = "
    << carved.carved_volume / carved.surface_volume << "); " << carved.snapped_nodes << " of its "
    << carved.boundary_nodes
    << " boundary nodes were moved onto the surface, the rest keep the grid's stair steps";
  carved.mesh.warnings.insert(carved.mesh.warnings.begin(), w.str());
  return std::move(carved.mesh);
}

}  // namespace hapstate
