// Closedness, orientation and self-intersection checks for a triangle surface before it is
// handed to Gmsh (whose failures name no face) or, if it self-intersects, carved (carve.h).
#include "mesh/surface.h"

#include "util/error.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <unordered_map>

namespace hapstate {
namespace {

std::string face_where(const TriangleSurface& s, std::size_t f) {
  const int line = s.face_lines[f];
  return line > 0 ? s.source + ":" + std::to_string(line)
                  : s.source + ": triangle " + std::to_string(f);
}

Eigen::Vector3d point(const TriangleSurface& s, int v) {
  return {s.xyz[3 * static_cast<std::size_t>(v)], s.xyz[3 * static_cast<std::size_t>(v) + 1],
          s.xyz[3 * static_cast<std::size_t>(v) + 2]};
}

// Uniform grid over the bounding box holding the triangles overlapping each cell.
class FaceGrid {
 public:
  explicit FaceGrid(const TriangleSurface& s) {
    lo_ = Eigen::Vector3d::Constant(1e300);
    Eigen::Vector3d hi = Eigen::Vector3d::Constant(-1e300);
    for (std::size_t i = 0; i < s.xyz.size() / 3; ++i) {
      lo_ = lo_.cwiseMin(point(s, static_cast<int>(i)));
      hi = hi.cwiseMax(point(s, static_cast<int>(i)));
    }
    const double diag = (hi - lo_).norm();
    const double cells_per_axis = std::max(1.0, std::cbrt(static_cast<double>(s.faces.size())));
    h_ = std::max(diag / cells_per_axis, 1e-300);
    for (int k = 0; k < 3; ++k) n_[k] = std::max(1, static_cast<int>((hi[k] - lo_[k]) / h_) + 1);
    cells_.resize(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]);
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
      Eigen::Vector3d a = point(s, s.faces[f][0]);
      Eigen::Vector3d b = a;
      for (int k = 1; k < 3; ++k) {
        a = a.cwiseMin(point(s, s.faces[f][k]));
        b = b.cwiseMax(point(s, s.faces[f][k]));
      }
      visit(a, b, [&](std::vector<int>& cell) { cell.push_back(static_cast<int>(f)); });
    }
  }

  template <class F>
  void visit(const Eigen::Vector3d& a, const Eigen::Vector3d& b, F&& f) {
    int lo[3];
    int hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::clamp(static_cast<int>((a[k] - lo_[k]) / h_), 0, n_[k] - 1);
      hi[k] = std::clamp(static_cast<int>((b[k] - lo_[k]) / h_), 0, n_[k] - 1);
    }
    for (int i = lo[0]; i <= hi[0]; ++i) {
      for (int j = lo[1]; j <= hi[1]; ++j) {
        for (int k = lo[2]; k <= hi[2]; ++k)
          f(cells_[(static_cast<std::size_t>(i) * n_[1] + j) * n_[2] + k]);
      }
    }
  }

 private:
  Eigen::Vector3d lo_;
  double h_ = 1;
  int n_[3] = {1, 1, 1};
  std::vector<std::vector<int>> cells_;
};

}  // namespace

void check_surface_topology(const TriangleSurface& s) {
  // Each directed edge once, each undirected edge in exactly two faces.
  std::map<std::pair<int, int>, int> directed;  // (a,b) -> face
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const auto& t = s.faces[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      throw InputError(face_where(s, f) +
                       ": degenerate face (a vertex repeats); a clean closed surface is required");
    }
    for (int k = 0; k < 3; ++k) {
      const auto [it, inserted] =
          directed.emplace(std::make_pair(t[k], t[(k + 1) % 3]), static_cast<int>(f));
      if (!inserted) {
        throw InputError(face_where(s, f) + ": edge (" + std::to_string(t[k] + 1) + ", " +
                         std::to_string(t[(k + 1) % 3] + 1) +
                         ") is used twice in the same direction (also by the face at " +
                         face_where(s, it->second) +
                         "): inconsistent orientation or non-manifold surface");
      }
    }
  }
  for (const auto& [edge, f] : directed) {
    if (directed.count({edge.second, edge.first}) == 0) {
      throw InputError(face_where(s, static_cast<std::size_t>(f)) + ": open surface: edge (" +
                       std::to_string(edge.first + 1) + ", " + std::to_string(edge.second + 1) +
                       ") (1-based vertices) belongs to only one face; a closed surface is "
                       "required to fill it with tets");
    }
  }
}

std::optional<SelfIntersection> find_self_intersection(const TriangleSurface& s) {
  // Every undirected edge once as (a, b) with a < b, with the face using it in that direction
  // (or, on an open surface, the one using it the other way).
  std::map<std::pair<int, int>, int> edges;
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
      const auto& t = s.faces[f];
      for (int k = 0; k < 3; ++k) {
        if ((t[k] < t[(k + 1) % 3]) == (pass == 0))
          edges.emplace(std::minmax(t[k], t[(k + 1) % 3]), static_cast<int>(f));
      }
    }
  }
  // An edge crossing a face that shares none of its vertices; grid-accelerated.
  FaceGrid grid(s);
  std::vector<int> seen(s.faces.size(), -1);
  int edge_index = 0;
  std::optional<SelfIntersection> hit;
  for (const auto& entry : edges) {
    const auto& edge = entry.first;  // plain references: lambdas below capture them
    const int f = entry.second;
    ++edge_index;
    const Eigen::Vector3d p = point(s, edge.first);
    const Eigen::Vector3d q = point(s, edge.second);
    grid.visit(p.cwiseMin(q), p.cwiseMax(q), [&](std::vector<int>& cell) {
      for (int g : cell) {
        if (hit || seen[static_cast<std::size_t>(g)] == edge_index) continue;
        seen[static_cast<std::size_t>(g)] = edge_index;
        const auto& t = s.faces[static_cast<std::size_t>(g)];
        if (std::find(t.begin(), t.end(), edge.first) != t.end() ||
            std::find(t.begin(), t.end(), edge.second) != t.end())
          continue;
        const Eigen::Vector3d a = point(s, t[0]);
        const Eigen::Vector3d b = point(s, t[1]);
        const Eigen::Vector3d c = point(s, t[2]);
        const Eigen::Vector3d n = (b - a).cross(c - a);
        const double dp = n.dot(p - a);
        const double dq = n.dot(q - a);
        if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0) || (dp == 0 && dq == 0)) continue;
        const Eigen::Vector3d d = q - p;
        const double s1 = (a - p).cross(b - p).dot(d);
        const double s2 = (b - p).cross(c - p).dot(d);
        const double s3 = (c - p).cross(a - p).dot(d);
        if ((s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0)) {
          SelfIntersection x;
          x.point = p + d * (dp / (dp - dq));
          x.face = face_where(s, static_cast<std::size_t>(g));
          x.edge = {edge.first, edge.second};
          x.edge_face = face_where(s, static_cast<std::size_t>(f));
          hit = x;
        }
      }
    });
    if (hit) return hit;
  }
  return std::nullopt;
}

std::string SelfIntersection::near() const {
  std::string out =
      "(";  // appended piece by piece: GCC 12 -O3 warns (-Wrestrict) on "(" + std::string
  out += std::to_string(point.x());
  out += ", ";
  out += std::to_string(point.y());
  out += ", ";
  out += std::to_string(point.z());
  out += ")";
  return out;
}

std::string SelfIntersection::message() const {
  return face + ": self-intersecting surface: this face is crossed by the edge (" +
         std::to_string(edge[0] + 1) + ", " + std::to_string(edge[1] + 1) +
         ") (1-based vertices; face at " + edge_face + ") near " + near();
}

void check_closed_surface(const TriangleSurface& s) {
  check_surface_topology(s);
  if (const auto hit = find_self_intersection(s))
    throw InputError(hit->message() + "; repair the surface before meshing");
}

}  // namespace hapstate
