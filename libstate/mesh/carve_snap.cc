// Snapping the stair-stepped boundary of a carved mesh onto the input surface (see carve.h).
#include "mesh/carve.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>

namespace hapstate {
namespace {

Eigen::Vector3d corner(const TriangleSurface& s, int v) {
  return {s.xyz[3 * static_cast<std::size_t>(v)], s.xyz[3 * static_cast<std::size_t>(v) + 1],
          s.xyz[3 * static_cast<std::size_t>(v) + 2]};
}

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Triangles bucketed by a uniform grid of cell size h (each in every cell its box touches).
class TriangleBuckets {
 public:
  TriangleBuckets(const TriangleSurface& s, double h) : h_(h) {
    for (const auto& f : s.faces) {
      Eigen::Vector3d lo = corner(s, f[0]).cwiseMin(corner(s, f[1])).cwiseMin(corner(s, f[2]));
      Eigen::Vector3d hi = corner(s, f[0]).cwiseMax(corner(s, f[1])).cwiseMax(corner(s, f[2]));
      const int id = static_cast<int>(&f - s.faces.data());
      visit(
          lo, hi, [&](std::vector<int>& cell) { cell.push_back(id); }, true);
    }
  }
  // Calls f(face) for the triangles bucketed in the cells the box [lo, hi] touches (repeats).
  template <class F>
  void for_each(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, F&& f) {
    visit(
        lo, hi,
        [&](std::vector<int>& cell) {
          for (int t : cell) f(t);
        },
        false);
  }

 private:
  template <class F>
  void visit(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, F&& f, bool create) {
    std::array<long long, 3> a{};
    std::array<long long, 3> b{};
    for (int k = 0; k < 3; ++k) {
      a[static_cast<std::size_t>(k)] = static_cast<long long>(std::floor(lo[k] / h_));
      b[static_cast<std::size_t>(k)] = static_cast<long long>(std::floor(hi[k] / h_));
    }
    for (long long i = a[0]; i <= b[0]; ++i)
      for (long long j = a[1]; j <= b[1]; ++j)
        for (long long k = a[2]; k <= b[2]; ++k) {
          if (create) {
            f(cells_[{i, j, k}]);
          } else {
            const auto it = cells_.find({i, j, k});
            if (it != cells_.end()) f(it->second);
          }
        }
  }
  double h_;
  std::map<std::array<long long, 3>, std::vector<int>> cells_;
};

double det(const RawMesh& m, const std::array<int, 4>& t) {
  const auto p = [&](int k) {
    const auto v = static_cast<std::size_t>(t[static_cast<std::size_t>(k)]);
    return Eigen::Vector3d(m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2]);
  };
  Eigen::Matrix3d e;
  e << p(1) - p(0), p(2) - p(0), p(3) - p(0);
  return e.determinant();
}

// Outward faces of a positive tet (a,b,c,d), face i opposite node i.
constexpr int kFaceNodes[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

}  // namespace

int snap_boundary_nodes(const TriangleSurface& s, double orientation, double h, RawMesh* mesh,
                        int* boundary) {
  // Boundary faces (used by one tet) and each boundary node's outward normal.
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 3>>>
      faces;  // sorted key -> (count, face)
  for (const auto& t : mesh->tets) {
    for (const auto& fn : kFaceNodes) {
      const std::array<int, 3> f{t[static_cast<std::size_t>(fn[0])],
                                 t[static_cast<std::size_t>(fn[1])],
                                 t[static_cast<std::size_t>(fn[2])]};
      std::array<int, 3> key = f;
      std::sort(key.begin(), key.end());
      auto& e = faces[key];
      e.first += 1;
      e.second = f;
    }
  }
  const int n = mesh->num_nodes();
  std::vector<Eigen::Vector3d> normal(static_cast<std::size_t>(n), Eigen::Vector3d::Zero());
  const auto node = [&](int v) {
    return Eigen::Vector3d(mesh->xyz[3 * static_cast<std::size_t>(v)],
                           mesh->xyz[3 * static_cast<std::size_t>(v) + 1],
                           mesh->xyz[3 * static_cast<std::size_t>(v) + 2]);
  };
  for (const auto& [key, e] : faces) {
    if (e.first != 1) continue;
    const auto& f = e.second;
    const Eigen::Vector3d nf = (node(f[1]) - node(f[0])).cross(node(f[2]) - node(f[0]));
    for (int v : f) normal[static_cast<std::size_t>(v)] += nf;
  }
  std::vector<std::vector<int>> tets_of(static_cast<std::size_t>(n));
  for (std::size_t t = 0; t < mesh->tets.size(); ++t) {
    for (int v : mesh->tets[t]) tets_of[static_cast<std::size_t>(v)].push_back(static_cast<int>(t));
  }

  *boundary = static_cast<int>(std::count_if(
      normal.begin(), normal.end(), [](const Eigen::Vector3d& x) { return x.squaredNorm() > 0; }));
  TriangleBuckets buckets(s, h);
  const double reach = kCarveSnapReach * h;
  const double min_det = kCarveSnapMinVolume * h * h * h;
  int moved = 0;
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector3d nv = normal[static_cast<std::size_t>(v)];
    if (nv.squaredNorm() == 0) continue;  // interior node
    const Eigen::Vector3d p = node(v);
    const Eigen::Vector3d dir = nv.normalized();
    Eigen::Vector3d best = p;
    double best_d2 = reach * reach;
    buckets.for_each(
        p - Eigen::Vector3d::Constant(reach), p + Eigen::Vector3d::Constant(reach), [&](int t) {
          const auto& f = s.faces[static_cast<std::size_t>(t)];
          const Eigen::Vector3d a = corner(s, f[0]), b = corner(s, f[1]), c = corner(s, f[2]);
          // Only triangles facing the way this part of the boundary faces (not folds inside).
          if ((b - a).cross(c - a).normalized().dot(dir) * orientation < kCarveSnapFacing) return;
          const Eigen::Vector3d q = closest_on_triangle(p, a, b, c);
          const double d2 = (q - p).squaredNorm();
          if (d2 < best_d2) {
            best_d2 = d2;
            best = q;
          }
        });
    if (best == p) continue;
    for (const double step : {1.0, 0.5}) {
      const Eigen::Vector3d target = p + step * (best - p);
      for (int k = 0; k < 3; ++k)
        mesh->xyz[3 * static_cast<std::size_t>(v) + static_cast<std::size_t>(k)] = target[k];
      bool ok = true;
      for (int t : tets_of[static_cast<std::size_t>(v)])
        ok = ok && det(*mesh, mesh->tets[static_cast<std::size_t>(t)]) >= min_det;
      if (ok) {
        ++moved;
        break;
      }
      for (int k = 0; k < 3; ++k)
        mesh->xyz[3 * static_cast<std::size_t>(v) + static_cast<std::size_t>(k)] = p[k];
    }
  }
  return moved;
}

}  // namespace hapstate
