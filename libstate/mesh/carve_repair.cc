// Manifold repair and piece selection for carved grids (see carve.h).
#include "mesh/carve.h"

#include <algorithm>
#include <numeric>

namespace hapstate {
namespace {

// Union-find over 0..n-1.
struct Pieces {
  explicit Pieces(int n) : parent(static_cast<std::size_t>(n)) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  int find(int x) {
    while (parent[static_cast<std::size_t>(x)] != x)
      x = parent[static_cast<std::size_t>(x)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    return x;
  }
  void join(int a, int b) { parent[static_cast<std::size_t>(find(a))] = find(b); }
  std::vector<int> parent;
};

int shared_nodes(const std::array<int, 4>& a, const std::array<int, 4>& b) {
  int n = 0;
  for (int x : a) n += static_cast<int>(std::count(b.begin(), b.end(), x));
  return n;
}

// Number of pieces of the tets `ids` (indices into `nodes`) connected through shared faces.
int count_pieces(const std::vector<int>& ids, const std::array<std::array<int, 4>, 24>& nodes) {
  if (ids.empty()) return 0;
  Pieces p(static_cast<int>(ids.size()));
  for (std::size_t a = 0; a < ids.size(); ++a) {
    for (std::size_t b = a + 1; b < ids.size(); ++b) {
      if (shared_nodes(nodes[static_cast<std::size_t>(ids[a])],
                       nodes[static_cast<std::size_t>(ids[b])]) == 3) {
        p.join(static_cast<int>(a), static_cast<int>(b));
      }
    }
  }
  int count = 0;
  for (std::size_t a = 0; a < ids.size(); ++a)
    count += p.find(static_cast<int>(a)) == static_cast<int>(a);
  return count;
}

// Kept flags with the repair history of each grid tet, so that no tet flips back and forth: a
// tet the repair added is never removed, and one it removed comes back only when the other
// option is blocked too. Each tet changes at most twice, so the repair terminates.
struct Carving {
  std::vector<char>* kept;
  std::vector<char> history;  // 0 untouched, 1 added, 2 removed
  int added = 0;
  int removed = 0;
};

// Makes the tets `ids` (indices into `star`) all kept (`fill`) or all removed; false (nothing
// changed) if that would undo an earlier change the other way.
bool change(Carving* c, const std::array<int, 24>& star, const std::vector<int>& ids, bool fill,
            bool force) {
  for (int t : ids) {
    if (!force &&
        c->history[static_cast<std::size_t>(star[static_cast<std::size_t>(t)])] == (fill ? 2 : 1))
      return false;
  }
  for (int t : ids) {
    const auto g = static_cast<std::size_t>(star[static_cast<std::size_t>(t)]);
    (*c->kept)[g] = fill ? 1 : 0;
    c->history[g] = fill ? 1 : 2;
    ++(fill ? c->added : c->removed);
  }
  return true;
}

// Where the kept tets `in` and the others `out` of a star or an edge fan are not a manifold,
// the smaller set switches sides (removing `in` or filling `out`), unless that would undo an
// earlier change; then the other one, and filling if both would.
void resolve(Carving* c, const std::array<int, 24>& star, const std::vector<int>& in,
             const std::vector<int>& out) {
  const bool fill_first = out.size() <= in.size();
  if (change(c, star, fill_first ? out : in, fill_first, false)) return;
  if (change(c, star, fill_first ? in : out, !fill_first, false)) return;
  change(c, star, out, true, true);
}

// Checks the kept tets around node `u` (its star, then each edge fan) and resolves the first
// non-manifold configuration found. Returns true if something changed.
bool repair_node(const TetGrid& grid, int u, Carving* c) {
  std::array<int, 24> star{};
  const int n = grid.tets_around_node(u, &star);
  if (n < 24)
    return false;  // on the grid's outer face: never reached by kept tets (one cell margin)
  std::array<std::array<int, 4>, 24> nodes{};
  std::vector<int> in;
  std::vector<int> out;
  for (int t = 0; t < n; ++t) {
    nodes[static_cast<std::size_t>(t)] = grid.tet(star[static_cast<std::size_t>(t)]);
    ((*c->kept)[static_cast<std::size_t>(star[static_cast<std::size_t>(t)])] != 0 ? in : out)
        .push_back(t);
  }
  if (in.empty() || out.empty()) return false;
  const int before = c->added + c->removed;
  if (count_pieces(in, nodes) > 1 || count_pieces(out, nodes) > 1) {
    resolve(c, star, in, out);
    return c->added + c->removed != before;
  }
  // Edges u-v: the kept tets of the fan around the edge must form one arc.
  std::vector<int> neighbours;
  for (int t = 0; t < n; ++t) {
    for (int v : nodes[static_cast<std::size_t>(t)]) {
      if (v != u) neighbours.push_back(v);
    }
  }
  std::sort(neighbours.begin(), neighbours.end());
  neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
  for (int v : neighbours) {
    std::vector<int> fan_in;
    std::vector<int> fan_out;
    for (int t = 0; t < n; ++t) {
      const auto& tn = nodes[static_cast<std::size_t>(t)];
      if (std::find(tn.begin(), tn.end(), v) == tn.end()) continue;
      ((*c->kept)[static_cast<std::size_t>(star[static_cast<std::size_t>(t)])] != 0 ? fan_in
                                                                                    : fan_out)
          .push_back(t);
    }
    if (count_pieces(fan_in, nodes) > 1) {
      resolve(c, star, fan_in, fan_out);
      return c->added + c->removed != before;
    }
  }
  return false;
}

}  // namespace

void make_carved_boundary_manifold(const TetGrid& grid, std::vector<char>* kept, int* added,
                                   int* removed) {
  Carving c{kept, std::vector<char>(kept->size(), 0)};
  // Each tet changes at most twice (see Carving), so this ends; the bound is a safety net.
  for (int pass = 0; pass < 1000; ++pass) {
    std::vector<char> touched(static_cast<std::size_t>(grid.num_nodes()), 0);
    for (int t = 0; t < grid.num_tets(); ++t) {
      if ((*kept)[static_cast<std::size_t>(t)] == 0) continue;
      for (int v : grid.tet(t)) touched[static_cast<std::size_t>(v)] = 1;
    }
    bool changed = false;
    for (int u = 0; u < grid.num_nodes(); ++u) {
      // A node may need several fixes (star, then fans): repeat until it is clean.
      while (touched[static_cast<std::size_t>(u)] != 0 && repair_node(grid, u, &c)) changed = true;
    }
    if (!changed) break;
  }
  *added = c.added;
  *removed = c.removed;
}

int keep_largest_piece(const TetGrid& grid, std::vector<char>* kept, int* dropped_tets) {
  std::vector<int> ids;
  for (int t = 0; t < grid.num_tets(); ++t) {
    if ((*kept)[static_cast<std::size_t>(t)] != 0) ids.push_back(t);
  }
  struct Face {
    std::array<int, 3> key;
    int tet;  // index into ids
  };
  std::vector<Face> faces;
  faces.reserve(4 * ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const auto t = grid.tet(ids[i]);
    for (int skip = 0; skip < 4; ++skip) {
      Face f{{}, static_cast<int>(i)};
      int m = 0;
      for (int k = 0; k < 4; ++k) {
        if (k != skip) f.key[static_cast<std::size_t>(m++)] = t[static_cast<std::size_t>(k)];
      }
      std::sort(f.key.begin(), f.key.end());
      faces.push_back(f);
    }
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.key < b.key; });
  Pieces pieces(static_cast<int>(ids.size()));
  for (std::size_t i = 1; i < faces.size(); ++i) {
    if (faces[i].key == faces[i - 1].key) pieces.join(faces[i].tet, faces[i - 1].tet);
  }
  std::vector<int> size(ids.size(), 0);
  for (std::size_t i = 0; i < ids.size(); ++i)
    ++size[static_cast<std::size_t>(pieces.find(static_cast<int>(i)))];
  int largest = -1;
  int count = 0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (size[i] == 0) continue;
    ++count;
    if (largest < 0 || size[i] > size[static_cast<std::size_t>(largest)])
      largest = static_cast<int>(i);
  }
  *dropped_tets = 0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (pieces.find(static_cast<int>(i)) != largest) {
      (*kept)[static_cast<std::size_t>(ids[i])] = 0;
      ++*dropped_tets;
    }
  }
  return count > 0 ? count - 1 : 0;
}

}  // namespace hapstate
