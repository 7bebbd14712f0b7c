#include "mesh/validate.h"

#include "util/error.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <unordered_map>

namespace hapstate {
namespace {

// Individual warnings listed per kind before summarising the rest.
constexpr int kMaxListed = 20;

struct FaceRecord {
  std::array<int, 3> key;  // sorted node ids
  int tet;
  int local;  // face opposite local node `local`
};

// Outward faces of a positively oriented tet (a,b,c,d): face i is opposite node i.
constexpr int kFaceNodes[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

}  // namespace

Mesh validate_mesh(RawMesh raw, MeshReport* report) {
  MeshReport local_report;
  MeshReport& rep = report != nullptr ? *report : local_report;
  rep.warnings.insert(rep.warnings.end(), raw.warnings.begin(), raw.warnings.end());
  const std::string& src = raw.source;
  const int n = raw.num_nodes();

  Mesh mesh;
  mesh.source = src;
  mesh.nodes.resize(3, n);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double v = raw.xyz[3 * static_cast<std::size_t>(i) + k];
      if (!std::isfinite(v)) {
        throw InputError(src + ": node " + std::to_string(i) +
                         " (0-based, file order) has a non-finite coordinate");
      }
      mesh.nodes(k, i) = v;
    }
  }
  if (raw.tets.empty())
    throw InputError(src + ": no linear tetrahedra (4-node tets) found; a volume mesh is required");

  // Orientation and degeneracy.
  std::vector<std::array<int, 4>> kept;
  std::vector<int> kept_index;  // file-order tet index of each kept tet
  kept.reserve(raw.tets.size());
  kept_index.reserve(raw.tets.size());
  int listed_degenerate = 0;
  int listed_reoriented = 0;
  for (std::size_t t = 0; t < raw.tets.size(); ++t) {
    std::array<int, 4> tet = raw.tets[t];
    for (int k = 0; k < 4; ++k) {
      if (tet[k] < 0 || tet[k] >= n) {
        throw InputError(src + ": tet " + std::to_string(t) + " references node " +
                         std::to_string(tet[k]) + ", but the file has only " + std::to_string(n) +
                         " nodes");
      }
    }
    const Eigen::Vector3d a = mesh.nodes.col(tet[0]);
    const Eigen::Matrix3d e = (Eigen::Matrix3d() << mesh.nodes.col(tet[1]) - a,
                               mesh.nodes.col(tet[2]) - a, mesh.nodes.col(tet[3]) - a)
                                  .finished();
    const double det = e.determinant();
    double longest = 0;
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        longest =
            std::max(longest, (mesh.nodes.col(tet[i]) - mesh.nodes.col(tet[j])).squaredNorm());
      }
    }
    longest = std::sqrt(longest);
    const double relative = longest > 0 ? std::abs(det) / (longest * longest * longest) : 0.0;
    if (!(relative > kDegenerateRelativeVolume)) {
      rep.degenerate_tets.push_back(static_cast<int>(t));
      std::ostringstream msg;
      msg << src << ": tet " << t
          << " (0-based, file order) is degenerate (|det|/l^3 = " << relative
          << " <= " << kDegenerateRelativeVolume << "), removed";
      if (listed_degenerate++ < kMaxListed) rep.warnings.push_back(msg.str());
      continue;
    }
    if (det < 0) {
      std::swap(tet[2], tet[3]);
      ++rep.reoriented;
      if (listed_reoriented < kMaxListed) {
        rep.warnings.push_back(src + ": tet " + std::to_string(t) +
                               " was negatively oriented, re-oriented");
        ++listed_reoriented;
      }
    }
    kept.push_back(tet);
    kept_index.push_back(static_cast<int>(t));
  }
  rep.degenerate = static_cast<int>(rep.degenerate_tets.size());

  // Duplicates: same node set as an earlier tet.
  std::vector<int> order(kept.size());
  std::vector<std::array<int, 4>> keys(kept.size());
  for (std::size_t t = 0; t < kept.size(); ++t) {
    keys[t] = kept[t];
    std::sort(keys[t].begin(), keys[t].end());
    order[t] = static_cast<int>(t);
  }
  std::sort(order.begin(), order.end(),
            [&](int x, int y) { return keys[x] != keys[y] ? keys[x] < keys[y] : x < y; });
  std::vector<char> drop(kept.size(), 0);
  int listed_duplicate = 0;
  for (std::size_t i = 1; i < order.size(); ++i) {
    if (keys[order[i]] == keys[order[i - 1]]) {
      drop[order[i]] = 1;
      const int first = kept_index[order[i - 1]];
      const int dup = kept_index[order[i]];
      rep.duplicate_tets.push_back(dup);
      if (listed_duplicate < kMaxListed) {
        rep.warnings.push_back(src + ": tet " + std::to_string(dup) + " duplicates tet " +
                               std::to_string(first) + " (same nodes), removed");
        ++listed_duplicate;
      }
      order[i] = order[i - 1];  // later copies compare against the first
    }
  }
  std::sort(rep.duplicate_tets.begin(), rep.duplicate_tets.end());
  rep.duplicate = static_cast<int>(rep.duplicate_tets.size());

  int m = 0;
  for (std::size_t t = 0; t < kept.size(); ++t) m += drop[t] == 0;
  if (m == 0)
    throw InputError(src +
                     ": no valid tetrahedra left after removing degenerate and duplicate ones");
  mesh.tets.resize(4, m);
  {
    int j = 0;
    for (std::size_t t = 0; t < kept.size(); ++t) {
      if (drop[t] != 0) continue;
      for (int k = 0; k < 4; ++k) mesh.tets(k, j) = kept[t][k];
      ++j;
    }
  }

  // Unreferenced nodes (kept).
  std::vector<char> used(static_cast<std::size_t>(n), 0);
  for (int t = 0; t < m; ++t) {
    for (int k = 0; k < 4; ++k) used[static_cast<std::size_t>(mesh.tets(k, t))] = 1;
  }
  for (int i = 0; i < n; ++i) {
    if (used[static_cast<std::size_t>(i)] == 0) rep.unreferenced_nodes.push_back(i);
  }
  rep.unreferenced = static_cast<int>(rep.unreferenced_nodes.size());
  for (int i = 0; i < std::min<int>(rep.unreferenced, kMaxListed); ++i) {
    rep.warnings.push_back(src + ": node " + std::to_string(rep.unreferenced_nodes[i]) +
                           " (0-based) is used by no tet (kept)");
  }
  const auto summarize = [&](int total, const char* what) {
    if (total > kMaxListed) {
      rep.warnings.push_back(src + ": ... " + std::to_string(total - kMaxListed) + " more " + what +
                             " not listed");
    }
  };
  summarize(rep.degenerate, "degenerate tets");
  summarize(rep.reoriented, "re-oriented tets");
  summarize(rep.duplicate, "duplicate tets");
  summarize(rep.unreferenced, "unreferenced nodes");

  // Boundary: faces used by exactly one tet, outward.
  std::vector<FaceRecord> faces;
  faces.reserve(4 * static_cast<std::size_t>(m));
  for (int t = 0; t < m; ++t) {
    for (int f = 0; f < 4; ++f) {
      FaceRecord r{{mesh.tets(kFaceNodes[f][0], t), mesh.tets(kFaceNodes[f][1], t),
                    mesh.tets(kFaceNodes[f][2], t)},
                   t,
                   f};
      std::sort(r.key.begin(), r.key.end());
      faces.push_back(r);
    }
  }
  std::sort(faces.begin(), faces.end(), [](const FaceRecord& x, const FaceRecord& y) {
    return x.key != y.key ? x.key < y.key : x.tet < y.tet;
  });
  std::vector<std::pair<int, int>> boundary;  // (tet, local face)
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1) {
      boundary.emplace_back(faces[i].tet, faces[i].local);
    } else if (j - i > 2) {
      std::string tets;
      for (std::size_t k = i; k < j; ++k)
        tets += (k > i ? ", " : "") + std::to_string(faces[k].tet);
      throw InputError(src + ": face (" + std::to_string(faces[i].key[0]) + ", " +
                       std::to_string(faces[i].key[1]) + ", " + std::to_string(faces[i].key[2]) +
                       ") is shared by " + std::to_string(j - i) + " tets (" + tets +
                       "; ids after removing bad tets); tets overlap (non-manifold mesh)");
    }
    i = j;
  }
  std::sort(boundary.begin(), boundary.end());
  mesh.surface.resize(3, static_cast<int>(boundary.size()));
  for (std::size_t i = 0; i < boundary.size(); ++i) {
    const auto [t, f] = boundary[i];
    for (int k = 0; k < 3; ++k)
      mesh.surface(k, static_cast<int>(i)) = mesh.tets(kFaceNodes[f][k], t);
  }

  for (auto& [name, ids] : raw.groups) {
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    mesh.groups.emplace(name, std::move(ids));
  }
  return mesh;
}

}  // namespace hapstate
