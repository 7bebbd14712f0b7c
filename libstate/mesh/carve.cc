// carve_surface: grid choice, inside/outside classification by winding number, extraction.
#include "mesh/carve.h"

#include "mesh/winding_number.h"
#include "util/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hapstate {
namespace {

// Grid cells touched by a triangle's bounding box (slightly enlarged); the winding number is
// constant on each connected region of the other cells.
std::vector<char> near_surface_cells(const TriangleSurface& s, const TetGrid& grid, double h) {
  std::vector<char> near(static_cast<std::size_t>(grid.num_cells()), 0);
  const int n[3] = {grid.nx, grid.ny, grid.nz};
  const double eps = 1e-3 * h;
  for (const auto& f : s.faces) {
    int lo[3];
    int hi[3];
    for (int k = 0; k < 3; ++k) {
      double a = 1e300;
      double b = -1e300;
      for (int v : f) {
        a = std::min(a, s.xyz[3 * static_cast<std::size_t>(v) + static_cast<std::size_t>(k)]);
        b = std::max(b, s.xyz[3 * static_cast<std::size_t>(v) + static_cast<std::size_t>(k)]);
      }
      lo[k] = std::clamp(static_cast<int>(std::floor((a - eps - grid.origin[k]) / h)), 0, n[k] - 1);
      hi[k] = std::clamp(static_cast<int>(std::floor((b + eps - grid.origin[k]) / h)), 0, n[k] - 1);
    }
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i)
          near[static_cast<std::size_t>(grid.cell_id(i, j, k))] = 1;
  }
  return near;
}

// One flag per grid tet: centroid winding number (times `sign`) > 0.5. Near-surface cells are
// evaluated tet by tet; every other region of face-adjacent cells once, at one cell centre.
std::vector<char> classify(const TriangleSurface& s, const TetGrid& grid, double h, double sign) {
  const WindingNumber winding(s);
  const std::vector<char> near = near_surface_cells(s, grid, h);
  std::vector<char> kept(static_cast<std::size_t>(grid.num_tets()), 0);
  std::vector<char> done(near);
  std::vector<int> stack;
  for (int c = 0; c < grid.num_cells(); ++c) {
    if (done[static_cast<std::size_t>(c)] != 0) continue;
    const auto [i, j, k] = grid.cell_index(c);
    const bool inside =
        sign * winding((grid.node(i, j, k) + grid.node(i + 1, j + 1, k + 1)) / 2) > 0.5;
    stack.assign(1, c);
    done[static_cast<std::size_t>(c)] = 1;
    while (!stack.empty()) {
      const int d = stack.back();
      stack.pop_back();
      if (inside) std::fill_n(kept.begin() + 6 * static_cast<std::ptrdiff_t>(d), 6, 1);
      const auto [a, b, e] = grid.cell_index(d);
      const int next[6][3] = {{a - 1, b, e}, {a + 1, b, e}, {a, b - 1, e},
                              {a, b + 1, e}, {a, b, e - 1}, {a, b, e + 1}};
      for (const auto& q : next) {
        if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= grid.nx || q[1] >= grid.ny ||
            q[2] >= grid.nz)
          continue;
        const int m = grid.cell_id(q[0], q[1], q[2]);
        if (done[static_cast<std::size_t>(m)] == 0) {
          done[static_cast<std::size_t>(m)] = 1;
          stack.push_back(m);
        }
      }
    }
  }
  for (int c = 0; c < grid.num_cells(); ++c) {
    if (near[static_cast<std::size_t>(c)] == 0) continue;
    for (int local = 0; local < 6; ++local) {
      const int t = 6 * c + local;
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (int v : grid.tet(t)) centroid += grid.node(v);
      kept[static_cast<std::size_t>(t)] = sign * winding(centroid / 4) > 0.5 ? 1 : 0;
    }
  }
  return kept;
}

}  // namespace

double carve_cell_size(const Eigen::Vector3d& extent, double volume, bool* capped) {
  double h = std::min(std::cbrt(6.0 * volume / kCarveTargetTets),
                      extent.minCoeff() / kCarveMinCellsAcross);
  *capped = false;
  for (int round = 0; round < 100; ++round) {
    double cells = 1;
    for (int k = 0; k < 3; ++k) cells *= std::ceil(extent[k] / h) + 2;
    if (cells <= kCarveMaxCells) break;
    *capped = true;
    h *= std::max(1.01, std::cbrt(cells / kCarveMaxCells));
  }
  return h;
}

CarveResult carve_surface(const TriangleSurface& s, bool snap) {
  CarveResult r;
  r.mesh.source = s.source;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-1e300);
  for (std::size_t v = 0; 3 * v < s.xyz.size(); ++v) {
    const Eigen::Vector3d p(s.xyz[3 * v], s.xyz[3 * v + 1], s.xyz[3 * v + 2]);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d extent = hi - lo;
  const double signed_volume = WindingNumber(s).enclosed_volume();
  r.surface_volume = std::abs(signed_volume);
  if (!(extent.minCoeff() > 0) || !(r.surface_volume > 1e-9 * extent.prod())) {
    throw InputError(s.source + ": the surface encloses no volume (enclosed volume " +
                     std::to_string(signed_volume) + "); cannot carve a volume mesh from it");
  }
  const double h = carve_cell_size(extent, r.surface_volume, &r.capped);
  TetGrid grid;
  grid.nx = static_cast<int>(std::ceil(extent.x() / h)) + 2;
  grid.ny = static_cast<int>(std::ceil(extent.y() / h)) + 2;
  grid.nz = static_cast<int>(std::ceil(extent.z() / h)) + 2;
  grid.size = h * Eigen::Vector3d(grid.nx, grid.ny, grid.nz);
  grid.origin = (lo + hi) / 2 - grid.size / 2;
  r.cell_size = h;

  std::vector<char> kept = classify(s, grid, h, signed_volume > 0 ? 1.0 : -1.0);
  if (std::find(kept.begin(), kept.end(), 1) == kept.end()) {
    throw InputError(s.source + ": no grid tet of cell size " + std::to_string(h) +
                     " lies inside the surface; cannot carve it");
  }
  make_carved_boundary_manifold(grid, &kept, &r.added_tets, &r.removed_tets);
  r.dropped_pieces = keep_largest_piece(grid, &kept, &r.dropped_tets);

  std::vector<int> id(static_cast<std::size_t>(grid.num_nodes()), -1);
  for (int t = 0; t < grid.num_tets(); ++t) {
    if (kept[static_cast<std::size_t>(t)] == 0) continue;
    for (int v : grid.tet(t)) id[static_cast<std::size_t>(v)] = 0;
  }
  int nodes = 0;
  for (int v = 0; v < grid.num_nodes(); ++v) {
    if (id[static_cast<std::size_t>(v)] < 0) continue;
    id[static_cast<std::size_t>(v)] = nodes++;
    const Eigen::Vector3d p = grid.node(v);
    r.mesh.xyz.insert(r.mesh.xyz.end(), {p.x(), p.y(), p.z()});
  }
  for (int t = 0; t < grid.num_tets(); ++t) {
    if (kept[static_cast<std::size_t>(t)] == 0) continue;
    std::array<int, 4> tet = grid.tet(t);
    for (int& v : tet) v = id[static_cast<std::size_t>(v)];
    r.mesh.tets.push_back(tet);
  }
  r.tets = static_cast<int>(r.mesh.tets.size());
  if (snap)
    r.snapped_nodes =
        snap_boundary_nodes(s, signed_volume > 0 ? 1.0 : -1.0, h, &r.mesh, &r.boundary_nodes);
  for (const auto& t : r.mesh.tets) {
    const auto p = [&](int k) {
      const auto v = static_cast<std::size_t>(t[static_cast<std::size_t>(k)]);
      return Eigen::Vector3d(r.mesh.xyz[3 * v], r.mesh.xyz[3 * v + 1], r.mesh.xyz[3 * v + 2]);
    };
    r.carved_volume += (p(1) - p(0)).dot((p(2) - p(0)).cross(p(3) - p(0))) / 6.0;
  }

  if (r.dropped_pieces > 0) {
    std::ostringstream w;
    w << s.source << ": carving left " << r.dropped_pieces + 1
      << " disconnected pieces; kept the largest (" << r.tets << " tets), dropped "
      << r.dropped_pieces << " smaller piece" << (r.dropped_pieces > 1 ? "s" : "") << " ("
      << r.dropped_tets << " tets)";
    r.mesh.warnings.push_back(w.str());
  }
  if (r.capped) {
    std::ostringstream w;
    w << s.source << ": the shape is too thin for " << kCarveMinCellsAcross
      << " grid cells across its smallest extent within " << kCarveMaxCells
      << " cells; carved with cell size " << h;
    r.mesh.warnings.push_back(w.str());
  }
  return r;
}

}  // namespace hapstate
