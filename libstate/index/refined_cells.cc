#include "index/refined_cells.h"

#include "util/grid_direction.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace hapstate {
namespace {

using Offset = std::array<int, 3>;

// The cells of the file as the cursor sees them: a cell by its lowest corner's configuration,
// the other corners the targets of its moves.
class Cells {
 public:
  explicit Cells(const playback::Content& c) : c_(c) {}

  // Configuration k's move by grid offset o (k itself for o = 0), -1 if none.
  std::int32_t move(std::int32_t k, const Offset& o) const {
    if (k < 0) return -1;
    if (o[0] == 0 && o[1] == 0 && o[2] == 0) return k;
    const std::int32_t t =
        c_.transitions[grid::kDirections * std::size_t(k) + grid::direction_index(o)];
    return t >= 0 ? t : -1;
  }
  // The 8 corners of the cell whose lowest corner is k (-1 where a move is missing).
  std::array<std::int32_t, 8> corners(std::int32_t k) const {
    std::array<std::int32_t, 8> out{};
    for (int c = 0; c < 8; ++c) out[c] = move(k, {(c >> 2) & 1, (c >> 1) & 1, c & 1});
    return out;
  }
  // Whether a cell of the grid lies at offset d from the cell whose lowest corner is at `base`.
  bool cell_exists(const std::array<std::int32_t, 3>& base, const Offset& d) const {
    const playback::Meta& m = c_.meta;
    for (int a = 0; a < 3; ++a) {
      const std::int32_t last = playback::last_cell(m, a);
      if (base[a] + d[a] < m.lo[a] || base[a] + d[a] > last) return false;
    }
    return true;
  }
  std::array<std::int32_t, 3> base_of(std::int32_t k) const {
    return playback::grid_point_ijk(c_.meta, c_.config_checkpoint[k]);
  }
  // The lowest corner of the neighbour at offset d (components -1, 0, 1) of the cell with
  // corners `own`, reached from the shared corner nearest to it, or -1; the neighbour shares
  // the corners at own-cell offsets d + o' in {0, 1}^3 and must show the same configurations.
  std::int32_t neighbour(const std::array<std::int32_t, 8>& own, const Offset& d) const {
    Offset o{}, step{};
    for (int a = 0; a < 3; ++a) o[a] = d[a] > 0 ? 1 : 0, step[a] = d[a] - o[a];
    const std::int32_t n0 = move(own[(o[0] << 2) | (o[1] << 1) | o[2]], step);
    if (n0 < 0) return -1;
    const std::array<std::int32_t, 8> theirs = corners(n0);
    for (int c = 0; c < 8; ++c) {
      const Offset p{d[0] + ((c >> 2) & 1), d[1] + ((c >> 1) & 1), d[2] + (c & 1)};
      if (p[0] < 0 || p[0] > 1 || p[1] < 0 || p[1] > 1 || p[2] < 0 || p[2] > 1) continue;
      if (theirs[c] < 0 || theirs[c] != own[(p[0] << 2) | (p[1] << 1) | p[2]]) return -1;
    }
    return n0;
  }

 private:
  const playback::Content& c_;
};

}  // namespace

namespace {

// A lattice's data in the file: points per axis, a cell's slot column in section 20 and its
// points.
struct LatticeLevel {
  int n;           // points per axis (5, 9 or 17)
  int slot;        // the column of section 20 with the slot; its constraints the next one
  double* points;  // 12 x n^3 per cell
};

// Whether cell k (a file index, or -1) has the lattice of `level`.
bool has_level(const playback::Content& c, const LatticeLevel& level, std::int32_t k) {
  return k >= 0 && c.refined_cells[playback::kRefinedCellInts * k + level.slot] >= 0;
}

// Sets the constraint bits of `level` for cell k.
void constrain(const Cells& grid, playback::Content& c, const LatticeLevel& level, std::int32_t k) {
  constexpr int ints = playback::kRefinedCellInts;
  auto refined = [&](std::int32_t cell) { return has_level(c, level, cell); };
  const std::array<std::int32_t, 8> own = grid.corners(k);
  const auto base = grid.base_of(k);
  // A face or an edge is constrained where a cell of the grid beside it is not a refined cell
  // with this lattice showing the same corners (as the cursor would show it walking there).
  auto unrefined = [&](const Offset& d) {
    return grid.cell_exists(base, d) && !refined(grid.neighbour(own, d));
  };
  std::int32_t bits = 0;
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) {
      Offset d{};
      d[a] = s ? 1 : -1;
      if (unrefined(d)) bits |= 1 << playback::refined_face_bit(a, s);
    }
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, e = (a + 2) % 3;
    for (int s1 = 0; s1 < 2; ++s1)
      for (int s2 = 0; s2 < 2; ++s2) {
        Offset db{}, de{}, dbe{};
        db[b] = dbe[b] = s1 ? 1 : -1;
        de[e] = dbe[e] = s2 ? 1 : -1;
        if (unrefined(db) || unrefined(de) || unrefined(dbe))
          bits |= 1 << playback::refined_edge_bit(a, s1, s2);
      }
  }
  c.refined_cells[ints * k + level.slot + 1] = bits;
}

// One value for each point that several cells' lattices of `level` hold (`cells`, the cells that
// have it, in the order of their slots): points joined through shared faces form a group, and
// every member takes the value of the first member that has one, the cells taken by their lowest
// corner's grid position (i, then j, then k; then by file index). So the force stays continuous
// where one of two cells' solves failed, or (a sixteenth-spacing lattice) where only one of them
// flagged the eighth cell beside the face; a point on an edge or at a corner holds one value in
// all of its up to 8 cells, even where two of them solved it to values that differ within the
// solver's tolerance and the cell between them has no such lattice (an L of refined cells).
// A point is numbered as it lies in level.points: slot x n^3 + (i n + j) n + l.
void share_points(const Cells& grid, playback::Content& c, const LatticeLevel& level,
                  const std::vector<std::int32_t>& cells) {
  const int n = level.n, last = n - 1;
  const std::size_t per_cell = std::size_t(n) * n * n;
  auto slot = [&](std::int32_t k) {
    return std::size_t(c.refined_cells[playback::kRefinedCellInts * k + level.slot]);
  };
  std::vector<std::size_t> parent(per_cell * cells.size());
  for (std::size_t e = 0; e < parent.size(); ++e) parent[e] = e;
  auto root = [&](std::size_t e) {
    while (parent[e] != e) e = parent[e] = parent[parent[e]];
    return e;
  };
  auto point = [&](std::size_t cell_slot, const int(&q)[3]) {
    return per_cell * cell_slot + std::size_t(n) * (std::size_t(n) * q[0] + q[1]) + q[2];
  };
  for (const std::int32_t k : cells) {
    const std::array<std::int32_t, 8> own = grid.corners(k);
    for (int a = 0; a < 3; ++a) {
      Offset d{};
      d[a] = 1;
      const std::int32_t other = grid.neighbour(own, d);
      if (!has_level(c, level, other)) continue;
      for (int u = 0; u < n; ++u)
        for (int v = 0; v < n; ++v) {
          int mine[3], theirs[3];
          mine[a] = last, theirs[a] = 0;
          mine[(a + 1) % 3] = theirs[(a + 1) % 3] = u;
          mine[(a + 2) % 3] = theirs[(a + 2) % 3] = v;
          parent[root(point(slot(k), mine))] = root(point(slot(other), theirs));
        }
    }
  }
  // The cells in the order whose first value a group takes.
  std::vector<std::int32_t> order = cells;
  std::sort(order.begin(), order.end(), [&](std::int32_t x, std::int32_t y) {
    const auto bx = grid.base_of(x), by = grid.base_of(y);
    return bx != by ? bx < by : x < y;
  });
  double* values = level.points;  // 12 per point
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> first(parent.size(), kNone);  // a group's root -> its value's point
  for (const std::int32_t k : order)
    for (std::size_t e = per_cell * slot(k); e < per_cell * (slot(k) + 1); ++e) {
      const std::size_t r = root(e);
      if (first[r] == kNone && std::isfinite(values[12 * e])) first[r] = e;
    }
  for (std::size_t e = 0; e < parent.size(); ++e) {
    const std::size_t from = first[root(e)];
    if (from != kNone && from != e) std::copy_n(values + 12 * from, 12, values + 12 * e);
  }
}

}  // namespace

void add_refined_cells(const std::vector<RefinementPoint>& rows,
                       const std::map<std::int64_t, std::int32_t>& index_of,
                       playback::Content* content) {
  playback::Content& c = *content;
  if (c.midpoint_stiffness.empty()) return;
  constexpr int ints = playback::kRefinedCellInts;
  constexpr int kQuarterRows = 125 - 27, kEighthRows = 729 - 125;  // the points the stage stores
  const std::size_t n = c.config_checkpoint.size();
  // file index -> its rows at depth 1, 2 and 3 (sixteenth: as many as the stage flagged)
  std::map<std::int32_t, std::vector<const RefinementPoint*>> quarter, eighth, sixteenth;
  for (const RefinementPoint& r : rows) {
    const auto it = index_of.find(r.cell.value());
    if (it == index_of.end()) continue;
    const int depth = refinement_point_depth(r.point);
    (depth == 1 ? quarter : depth == 2 ? eighth : sixteenth)[it->second].push_back(&r);
  }
  // Complete cells only; an eighth-spacing lattice only where the quarter-spacing one is.
  for (auto it = quarter.begin(); it != quarter.end();)
    it = static_cast<int>(it->second.size()) == kQuarterRows ? std::next(it) : quarter.erase(it);
  for (auto it = eighth.begin(); it != eighth.end();)
    it = static_cast<int>(it->second.size()) == kEighthRows && quarter.count(it->first)
             ? std::next(it)
             : eighth.erase(it);
  for (auto it = sixteenth.begin(); it != sixteenth.end();)
    it = eighth.count(it->first) ? std::next(it) : sixteenth.erase(it);
  if (quarter.empty()) return;
  c.refined_cells.assign(ints * n, 0);
  for (std::size_t k = 0; k < n; ++k)
    c.refined_cells[ints * k] = c.refined_cells[ints * k + 2] = c.refined_cells[ints * k + 4] = -1;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  c.refined_points.assign(12 * playback::kRefinedPoints * quarter.size(), nan);
  c.eighth_points.assign(12 * playback::kEighthPoints * eighth.size(), nan);
  c.sixteenth_points.assign(12 * playback::kSixteenthPoints * sixteenth.size(), nan);
  auto fill = [&](const std::map<std::int32_t, std::vector<const RefinementPoint*>>& cells,
                  int column, int points_per_cell, int first, std::vector<double>* out) {
    std::int32_t slot = 0;
    for (const auto& [k, points] : cells) {
      c.refined_cells[ints * k + column] = slot;
      for (const RefinementPoint* p : points) {
        if (!p->reached) continue;
        double* to = &(*out)[12 * (std::size_t(points_per_cell) * slot + (p->point - first))];
        std::copy(p->force.begin(), p->force.end(), to);
        std::copy(p->stiffness.begin(), p->stiffness.end(), to + 3);
      }
      ++slot;
    }
  };
  fill(quarter, 0, playback::kRefinedPoints, 0, &c.refined_points);
  fill(eighth, 2, playback::kEighthPoints, kEighthFirstPoint, &c.eighth_points);
  fill(sixteenth, 4, playback::kSixteenthPoints, kSixteenthFirstPoint, &c.sixteenth_points);
  const Cells grid(c);
  const LatticeLevel levels[3] = {{5, 0, c.refined_points.data()},
                                  {9, 2, c.eighth_points.data()},
                                  {17, 4, c.sixteenth_points.data()}};
  const std::map<std::int32_t, std::vector<const RefinementPoint*>>* cells[3] = {&quarter, &eighth,
                                                                                 &sixteenth};
  for (int l = 0; l < 3; ++l) {
    std::vector<std::int32_t> with_level;
    for (const auto& entry : *cells[l]) {
      constrain(grid, c, levels[l], entry.first);
      with_level.push_back(entry.first);
    }
    share_points(grid, c, levels[l], with_level);
  }
}

}  // namespace hapstate
