// Fallback volume meshing for closed surfaces that Gmsh cannot fill (self-intersecting ones):
// carve a regular tet grid (TetGrid, box_mesh.h) with the surface's generalized winding number.
// The boundary is stair-stepped on the grid; it does not follow the input triangles.
#pragma once

#include "mesh/box_mesh.h"
#include "mesh/raw_mesh.h"
#include "mesh/surface.h"

#include <Eigen/Core>

#include <vector>

namespace hapstate {

// Cell-size rule (docs/mesh-formats.md): the cell size h is chosen so that the carved mesh has
// about kCarveTargetTets tets, V / (h^3 / 6) = kCarveTargetTets for the enclosed volume V, but no
// fewer than kCarveMinCellsAcross cells across the bounding box's smallest extent; if that grid
// would exceed kCarveMaxCells cells (very thin shapes), h grows until it fits (reported).
inline constexpr double kCarveTargetTets = 12000;
inline constexpr double kCarveMinCellsAcross = 8;
inline constexpr double kCarveMaxCells = 2e6;

// Snapping (snap_boundary_nodes): a boundary node moves to the closest point of the surface
// within kCarveSnapReach cells, on a triangle facing within 60 degrees of the node's outward
// normal (cos > kCarveSnapFacing), if every tet around it keeps det >= kCarveSnapMinVolume * h^3
// (a grid tet has det = h^3); else halfway there under the same test; else it stays.
inline constexpr double kCarveSnapReach = 1.0;
inline constexpr double kCarveSnapFacing = 0.5;
inline constexpr double kCarveSnapMinVolume = 0.2;

// Cell size for a surface with bounding-box `extent` enclosing volume `volume` (> 0). Sets
// *capped when kCarveMaxCells forced a coarser grid than the rule asks for.
double carve_cell_size(const Eigen::Vector3d& extent, double volume, bool* capped);

struct CarveResult {
  RawMesh mesh;          // kept nodes renumbered in grid order, tets positively oriented
  double cell_size = 0;  // h
  int tets = 0;
  double carved_volume = 0;   // tets * h^3 / 6
  double surface_volume = 0;  // |volume enclosed by the input surface|
  int added_tets = 0;         // grid tets added to make the boundary a 2-manifold
  int removed_tets = 0;       // grid tets removed for the same reason
  int dropped_pieces = 0;     // face-connected pieces other than the largest (removed)
  int dropped_tets = 0;       // tets in those pieces
  bool capped = false;        // see carve_cell_size
  int boundary_nodes = 0;     // nodes on the carved boundary
  int snapped_nodes = 0;      // of those, moved onto (or towards) the surface
};

// Carves `s` (closed; may self-intersect): grid over its bounding box plus one cell of margin,
// keeps the grid tets whose centroid has winding number > 0.5 (sign taken from the enclosed
// volume, so inward-oriented surfaces work too), adds or removes grid tets where the kept set's
// boundary would be non-manifold at an edge or node, keeps the largest face-connected piece and
// drops unused nodes, then snaps boundary nodes onto the surface (snap_boundary_nodes; `snap` false
// leaves the stair steps). mesh.warnings notes dropped pieces and a capped grid. Throws InputError
// if the surface encloses no volume or no tet is inside.
CarveResult carve_surface(const TriangleSurface& s, bool snap = true);

// Steps of carve_surface (carve_repair.cc), on `kept` (one flag per grid tet):
// Where the boundary of the kept set is not a 2-manifold -- around a node whose kept tets, or
// whose other tets, are not face-connected, or around an edge whose kept tets form more than one
// fan -- the smaller side switches (kept tets there are removed, or the missing ones added; a
// tet is never switched back unless both options would undo an earlier switch, then the fan or
// star is filled). Repeats until none is left: the boundary is then a closed 2-manifold.
// *added / *removed get the numbers of tets switched each way.
void make_carved_boundary_manifold(const TetGrid& grid, std::vector<char>* kept, int* added,
                                   int* removed);
// Keeps the largest face-connected piece of the kept tets (first in grid order on ties).
// Returns the number of pieces dropped; *dropped_tets gets their tet count.
int keep_largest_piece(const TetGrid& grid, std::vector<char>* kept, int* dropped_tets);
// Moves the boundary nodes of a carved `mesh` (cell size h) onto the surface `s` as described at
// kCarveSnapReach (carve_snap.cc); `orientation` is +1 for an outward surface, -1 for an inward
// one. Tets stay positive. Returns the number of nodes moved; *boundary gets the boundary nodes.
int snap_boundary_nodes(const TriangleSurface& s, double orientation, double h, RawMesh* mesh,
                        int* boundary);

}  // namespace hapstate
