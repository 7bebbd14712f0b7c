// Fills a closed triangle surface with tets through the Gmsh C++ API, falling back to carving a
// tet grid (carve.h) for self-intersecting surfaces. Gmsh keeps global state, so every use is
// serialised by one mutex and wrapped in initialize/finalize. (libgmsh 4.8 installs no signal
// handlers; terminal output is switched off.)
#include "mesh/surface.h"

#include "mesh/carve.h"
#include "util/error.h"

#include <gmsh.h>

#include <mutex>
#include <sstream>

namespace hapstate {
namespace {

std::mutex& gmsh_mutex() {
  static std::mutex m;
  return m;
}

// gmsh::initialize / finalize as a scope guard.
struct GmshSession {
  GmshSession() {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 1);
  }
  ~GmshSession() {
    try {
      gmsh::finalize();
    } catch (...) {
    }
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

}  // namespace

RawMesh tetrahedralize_surface(const TriangleSurface& s) {
  std::lock_guard<std::mutex> lock(gmsh_mutex());
  RawMesh mesh;
  mesh.source = s.source;
  const std::string failure = s.source + ": Gmsh could not fill the surface with tetrahedra: ";
  try {
    GmshSession session;
    gmsh::model::add("surface");
    gmsh::model::addDiscreteEntity(2, 1);
    std::vector<std::size_t> node_tags(s.xyz.size() / 3);
    for (std::size_t i = 0; i < node_tags.size(); ++i) node_tags[i] = i + 1;
    gmsh::model::mesh::addNodes(2, 1, node_tags, s.xyz);
    std::vector<std::size_t> tri_nodes;
    tri_nodes.reserve(3 * s.faces.size());
    for (const auto& f : s.faces) {
      for (int v : f) tri_nodes.push_back(static_cast<std::size_t>(v) + 1);
    }
    gmsh::model::mesh::addElementsByType(1, 2, {}, tri_nodes);
    const int loop = gmsh::model::geo::addSurfaceLoop({1});
    gmsh::model::geo::addVolume({loop});
    gmsh::model::geo::synchronize();
    gmsh::model::mesh::generate(3);

    std::vector<std::size_t> tags;
    std::vector<double> coords;
    std::vector<double> params;
    gmsh::model::mesh::getNodes(tags, coords, params, -1, -1, /*includeBoundary=*/false, /*returnParametric=*/false);
    NodeTags index;
    mesh.xyz = coords;
    for (std::size_t i = 0; i < tags.size(); ++i) index.add(static_cast<long long>(tags[i]), static_cast<int>(i));
    std::vector<std::size_t> tet_tags;
    std::vector<std::size_t> tet_nodes;
    gmsh::model::mesh::getElementsByType(4, tet_tags, tet_nodes);
    for (std::size_t t = 0; t < tet_tags.size(); ++t) {
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
  } catch (const std::string& e) {
    throw InputError(failure + e);
  } catch (const std::exception& e) {
    throw InputError(failure + e.what());
  } catch (...) {
    throw InputError(failure + "unknown Gmsh error");
  }
  return mesh;
}

RawMesh fill_closed_surface(const TriangleSurface& s) {
  check_surface_topology(s);  // holes and non-manifold edges stay errors: carving needs a closed surface
  std::string why;
  if (const auto hit = find_self_intersection(s)) {
    why = "the surface self-intersects near " + hit->near() + " (" + hit->face + " is crossed by the edge (" +
          std::to_string(hit->edge[0] + 1) + ", " + std::to_string(hit->edge[1] + 1) + "))";
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
  w << s.source << ": " << why << "; the volume was carved on a grid of cell size h = " << carved.cell_size << " ("
    << carved.tets << " tets, enclosed-volume ratio carved/surface = " << carved.carved_volume / carved.surface_volume
    << "); " << carved.snapped_nodes << " of its " << carved.boundary_nodes
    << " boundary nodes were moved onto the surface, the rest keep the grid's stair steps";
  carved.mesh.warnings.insert(carved.mesh.warnings.begin(), w.str());
  return std::move(carved.mesh);
}

}  // namespace hapstate
