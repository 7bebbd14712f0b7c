#include "index/refined_cells.h"

#include <array>
#include <limits>
#include <set>

namespace hapstate {
namespace {

using Base = std::array<std::int32_t, 3>;

// The constraint bits of the refined cell at `base`: its faces and edges shared with a cell of
// the grid that is not refined.
std::int32_t constraints(const Base& base, const std::set<Base>& refined, const playback::Meta& m) {
  auto unrefined = [&](Base b) {
    for (int a = 0; a < 3; ++a) {
      const std::int32_t last = m.lo[a] + (m.dims[a] > 1 ? m.dims[a] - 2 : 0);
      if (b[a] < m.lo[a] || b[a] > last) return false;  // no cell there
    }
    return refined.count(b) == 0;
  };
  std::int32_t bits = 0;
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) {
      Base n = base;
      n[a] += s ? 1 : -1;
      if (unrefined(n)) bits |= 1 << playback::refined_face_bit(a, s);
    }
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int s1 = 0; s1 < 2; ++s1)
      for (int s2 = 0; s2 < 2; ++s2) {
        Base nb = base, nc = base, nbc = base;
        nb[b] += s1 ? 1 : -1;
        nc[c] += s2 ? 1 : -1;
        nbc[b] = nb[b], nbc[c] = nc[c];
        if (unrefined(nb) || unrefined(nc) || unrefined(nbc))
          bits |= 1 << playback::refined_edge_bit(a, s1, s2);
      }
  }
  return bits;
}

}  // namespace

void add_refined_cells(const std::vector<RefinementPoint>& rows,
                       const std::map<std::int64_t, std::int32_t>& index_of,
                       playback::Content* content) {
  playback::Content& c = *content;
  if (c.midpoint_stiffness.empty()) return;
  const std::size_t n = c.config_checkpoint.size();
  // Complete cells: every point the stage stores (those with an odd quarter index).
  int expected = 0;
  for (int p = 0; p < playback::kRefinedPoints; ++p)
    expected += (p / 25) % 2 || (p / 5 % 5) % 2 || (p % 5) % 2;
  std::map<std::int32_t, std::vector<const RefinementPoint*>> cells;  // file index -> points
  for (const RefinementPoint& r : rows) {
    const auto it = index_of.find(r.cell.value());
    if (it != index_of.end()) cells[it->second].push_back(&r);
  }
  const playback::Meta& m = c.meta;
  auto base_of = [&](std::int32_t k) {
    const std::int32_t g = c.config_checkpoint[k];
    const std::int32_t yz = m.dims[1] * m.dims[2];
    return Base{m.lo[0] + g / yz, m.lo[1] + (g / m.dims[2]) % m.dims[1], m.lo[2] + g % m.dims[2]};
  };
  std::set<Base> refined;
  for (auto it = cells.begin(); it != cells.end();) {
    if (static_cast<int>(it->second.size()) != expected) {
      it = cells.erase(it);
      continue;
    }
    refined.insert(base_of(it->first));
    ++it;
  }
  if (cells.empty()) return;
  c.refined_cells.assign(2 * n, 0);
  for (std::size_t k = 0; k < n; ++k) c.refined_cells[2 * k] = -1;
  c.refined_points.assign(12 * playback::kRefinedPoints * cells.size(),
                          std::numeric_limits<double>::quiet_NaN());
  std::int32_t slot = 0;
  for (const auto& [k, points] : cells) {
    c.refined_cells[2 * k] = slot;
    c.refined_cells[2 * k + 1] = constraints(base_of(k), refined, m);
    for (const RefinementPoint* p : points) {
      if (!p->reached) continue;
      double* out =
          &c.refined_points[12 * (playback::kRefinedPoints * std::size_t(slot) + p->point)];
      std::copy(p->force.begin(), p->force.end(), out);
      std::copy(p->stiffness.begin(), p->stiffness.end(), out + 3);
    }
    ++slot;
  }
}

}  // namespace hapstate
