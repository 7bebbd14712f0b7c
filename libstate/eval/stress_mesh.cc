#include "eval/stress_mesh.h"

#include "scene/select.h"

#include <Eigen/Dense>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hapstate {

double tet_quality(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   const Eigen::Vector3d& d) {
  const Eigen::Vector3d u = b - a, v = c - a, w = d - a;
  const double six_volume = u.dot(v.cross(w));
  // Inradius: 3V / (sum of face areas).
  const double area = 0.5 * (v.cross(w).norm() + u.cross(v).norm() + u.cross(w).norm() +
                             (c - b).cross(d - b).norm());
  if (area == 0) return 0;
  const double r_in = 0.5 * six_volume / area;  // 3 V / A with V = six_volume / 6
  // Circumradius: |u|^2 (v x w) + |v|^2 (w x u) + |w|^2 (u x v), over 2 * 6V.
  if (six_volume == 0) return 0;
  const Eigen::Vector3d num =
      u.squaredNorm() * v.cross(w) + v.squaredNorm() * w.cross(u) + w.squaredNorm() * u.cross(v);
  const double r_circ = num.norm() / (2.0 * std::abs(six_volume));
  return 3.0 * r_in / r_circ;
}

double min_tet_quality(const Mesh& mesh) {
  double q = std::numeric_limits<double>::infinity();
  for (int e = 0; e < mesh.num_tets(); ++e)
    q = std::min(q, tet_quality(mesh.nodes.col(mesh.tets(0, e)), mesh.nodes.col(mesh.tets(1, e)),
                                mesh.nodes.col(mesh.tets(2, e)), mesh.nodes.col(mesh.tets(3, e))));
  return q;
}

namespace {

// splitmix64: a tiny generator whose output is the same everywhere.
struct SplitMix {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double symmetric() {
    return 2.0 * static_cast<double>(next() >> 11) * 0x1.0p-53 - 1.0;
  }  // [-1, 1)
};

}  // namespace

Mesh perturb_interior(const Mesh& mesh, double amplitude, double floor, std::uint64_t seed) {
  Mesh out = mesh;
  std::vector<bool> on_surface(mesh.num_nodes(), false);
  for (int n : surface_nodes(mesh)) on_surface[n] = true;
  std::vector<std::vector<int>> around(mesh.num_nodes());
  for (int e = 0; e < mesh.num_tets(); ++e)
    for (int a = 0; a < 4; ++a) around[mesh.tets(a, e)].push_back(e);
  // The smallest edge length: offsets are relative to it.
  double edge = std::numeric_limits<double>::infinity();
  for (int e = 0; e < mesh.num_tets(); ++e)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        edge = std::min(edge,
                        (mesh.nodes.col(mesh.tets(a, e)) - mesh.nodes.col(mesh.tets(b, e))).norm());
  SplitMix rng{seed};
  auto quality_ok = [&](int n) {
    for (int e : around[n]) {
      const double q = tet_quality(out.nodes.col(out.tets(0, e)), out.nodes.col(out.tets(1, e)),
                                   out.nodes.col(out.tets(2, e)), out.nodes.col(out.tets(3, e)));
      if (!(q >= floor)) return false;
    }
    return true;
  };
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (on_surface[n] || around[n].empty()) continue;
    const Eigen::Vector3d offset(rng.symmetric(), rng.symmetric(), rng.symmetric());
    const Eigen::Vector3d keep = out.nodes.col(n);
    // Try the full offset, then shorter ones, until every tet around the node stays valid.
    for (double scale = 1.0; scale > 0.1; scale *= 0.7) {
      out.nodes.col(n) = keep + scale * amplitude * edge * offset;
      if (quality_ok(n)) break;
      out.nodes.col(n) = keep;
    }
  }
  return out;
}

StretchRange stretch_range(const Mesh& mesh, const Eigen::Matrix3Xd& u) {
  StretchRange r;
  r.max_stretch = 0;
  r.min_stretch = r.min_jacobian = std::numeric_limits<double>::infinity();
  for (int e = 0; e < mesh.num_tets(); ++e) {
    Eigen::Matrix3d dm, ds;
    const int n0 = mesh.tets(0, e);
    for (int a = 1; a < 4; ++a) {
      const int n = mesh.tets(a, e);
      dm.col(a - 1) = mesh.nodes.col(n) - mesh.nodes.col(n0);
      ds.col(a - 1) = dm.col(a - 1) + u.col(n) - u.col(n0);
    }
    const Eigen::Matrix3d f = ds * dm.inverse();
    const Eigen::Vector3d s = Eigen::JacobiSVD<Eigen::Matrix3d>(f).singularValues();
    r.max_stretch = std::max(r.max_stretch, s.maxCoeff());
    r.min_stretch = std::min(r.min_stretch, s.minCoeff());
    r.min_jacobian = std::min(r.min_jacobian, f.determinant());
  }
  if (mesh.num_tets() == 0) r = StretchRange{};
  return r;
}

}  // namespace hapstate
