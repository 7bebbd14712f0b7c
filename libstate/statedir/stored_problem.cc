#include "statedir/stored_problem.h"

#include "blobs/blob_store.h"
#include "blobs/segment_writer.h"
#include "scene/bind.h"
#include "util/error.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <vector>

namespace hapstate {
namespace {

template <class Matrix>
std::vector<double> flatten(const Matrix& m) {
  std::vector<double> out(static_cast<std::size_t>(m.size()));
  for (Eigen::Index k = 0; k < m.size(); ++k) out[k] = static_cast<double>(m.data()[k]);
  return out;
}

ContentHash hash_of(const ProblemVectors& v) {
  ContentHasher h;
  // The probe's rest position; with a sag (gravity) it is the solver's answer, and the grabbed
  // nodes hashed here already decide where it was drawn.
  const std::vector<double> none;
  const std::vector<double>* rest = v.sag.empty() ? &v.rest : &none;
  for (const auto* part :
       {&v.nodes, &v.tets, &v.surface, &v.role, &v.probe_nodes, &v.probe_components, rest}) {
    h.update(static_cast<std::int64_t>(part->size()));
    h.update(std::span<const double>(*part));
  }
  // The loads' parts only where present (a problem without loads hashes as it always did), named.
  // The rest state and the sag are not hashed: they are what the solver made of these inputs
  // (the last bits may differ between machines or BLAS threads, and a re-import must not call
  // that another scene).
  for (const auto& [name, part] :
       {std::pair{"loads/force", &v.force}, {"loads/spring", &v.spring}}) {
    if (part->empty()) continue;
    h.update(std::string_view(name));
    h.update(static_cast<std::int64_t>(part->size()));
    h.update(std::span<const double>(*part));
  }
  return h.value();
}

// Integer ids as ProblemVectors holds them, float64 (int32 on disk, widened on reading): each
// must be an integer in [0, limit).
std::vector<int> to_ids(const std::vector<double>& v, double limit, const std::string& where) {
  std::vector<int> out;
  out.reserve(v.size());
  for (double x : v) {
    if (!(x >= 0 && x < limit) || std::floor(x) != x) {
      throw InputError(where + ": value " + std::to_string(x) + " is not a valid id (corrupt?)");
    }
    out.push_back(static_cast<int>(x));
  }
  return out;
}

}  // namespace

ProblemVectors problem_vectors(const Problem& p) {
  ProblemVectors v;
  v.nodes = flatten(p.mesh.nodes);
  v.tets = flatten(p.mesh.tets);
  v.surface = flatten(p.mesh.surface);
  for (DofRole r : p.constraints.role) v.role.push_back(static_cast<double>(r));
  for (int n : p.constraints.probe_nodes) v.probe_nodes.push_back(n);
  for (bool b : p.constraints.probe_components) v.probe_components.push_back(b ? 1.0 : 0.0);
  v.rest = {p.probe_rest.x(), p.probe_rest.y(), p.probe_rest.z()};
  v.force = flatten(p.loads.force);
  v.spring = flatten(p.loads.spring);
  v.rest_u = flatten(p.rest_m);
  if (!p.probe_sag.isZero(0.0)) v.sag = {p.probe_sag.x(), p.probe_sag.y(), p.probe_sag.z()};
  return v;
}

ContentHash problem_hash(const Problem& problem) { return hash_of(problem_vectors(problem)); }

void write_stored_problem(const StateDir& dir, const Problem& problem,
                          const ContentHash& scene_hash, const RestStiffness& rest) {
  std::filesystem::create_directories(dir.problem());
  const ProblemVectors v = problem_vectors(problem);
  SegmentWriter writer(dir.problem(), kProblemSegment,
                       SegmentProvenance{scene_hash.hex(), "", "import"});
  // Indices and flags as int32 datasets (read back as float64, the vectors' in-memory type).
  const auto ints = [](const std::vector<double>& values) {
    return std::vector<int>(values.begin(), values.end());
  };
  writer.write("mesh/nodes", v.nodes);
  writer.write("mesh/tets", std::span<const int>(ints(v.tets)));
  writer.write("mesh/surface", std::span<const int>(ints(v.surface)));
  writer.write("constraints/role", std::span<const int>(ints(v.role)));
  writer.write("constraints/probe_nodes", std::span<const int>(ints(v.probe_nodes)));
  writer.write("constraints/probe_components", std::span<const int>(ints(v.probe_components)));
  writer.write("probe/rest", v.rest);
  if (!v.force.empty()) writer.write("loads/force", v.force);
  if (!v.spring.empty()) writer.write("loads/spring", v.spring);
  if (!v.rest_u.empty()) writer.write("rest/u", v.rest_u);
  if (!v.sag.empty()) writer.write("probe/sag", v.sag);
  writer.write("rest/stiffness", std::span<const double>(rest.stiffness));
  if (!rest.du_dp.empty()) writer.write("rest/du_dp", std::span<const float>(rest.du_dp));
  writer.close();
}

std::optional<RestStiffness> stored_rest_stiffness(const StateDir& dir, int num_nodes) {
  const std::string where = (dir.problem() / segment_file_name(kProblemSegment)).string();
  if (!std::filesystem::exists(where)) return std::nullopt;
  BlobStore store(dir.problem(), 1);
  if (!store.contains(kProblemSegment, "rest/stiffness")) return std::nullopt;
  RestStiffness rest;
  const std::vector<double> k = store.read(kProblemSegment, "rest/stiffness");
  if (k.size() != rest.stiffness.size())
    throw InputError(where + ": rest/stiffness has " + std::to_string(k.size()) +
                     " values, not 9 (damaged?): re-import with --fresh");
  std::copy(k.begin(), k.end(), rest.stiffness.begin());
  if (store.contains(kProblemSegment, "rest/du_dp")) {
    rest.du_dp = store.read_float32(kProblemSegment, "rest/du_dp");
    if (rest.du_dp.size() != 9 * static_cast<std::size_t>(num_nodes))
      throw InputError(where + ": rest/du_dp has " + std::to_string(rest.du_dp.size()) +
                       " values, the mesh needs " + std::to_string(9 * num_nodes) +
                       " (damaged?): re-import with --fresh");
  }
  return rest;
}

Problem load_stored_problem(const StateDir& dir, const Scene& scene, const ContentHash& expected) {
  const std::string where = (dir.problem() / segment_file_name(kProblemSegment)).string();
  BlobStore store(dir.problem(), 1);
  ProblemVectors v;
  v.nodes = store.read(kProblemSegment, "mesh/nodes");
  v.tets = store.read(kProblemSegment, "mesh/tets");
  v.surface = store.read(kProblemSegment, "mesh/surface");
  v.role = store.read(kProblemSegment, "constraints/role");
  v.probe_nodes = store.read(kProblemSegment, "constraints/probe_nodes");
  v.probe_components = store.read(kProblemSegment, "constraints/probe_components");
  v.rest = store.read(kProblemSegment, "probe/rest");
  const auto optional = [&](const char* name) {
    return store.contains(kProblemSegment, name) ? store.read(kProblemSegment, name)
                                                 : std::vector<double>{};
  };
  v.force = optional("loads/force");
  v.spring = optional("loads/spring");
  v.rest_u = optional("rest/u");
  v.sag = optional("probe/sag");
  return problem_from_vectors(v, scene, expected, where);
}

std::vector<double> stored_rest_displacements(const StateDir& dir, double unit) {
  // A state without a stored problem (hand-made in tests) has no rest state either.
  if (!std::filesystem::exists(dir.problem() / segment_file_name(kProblemSegment))) return {};
  BlobStore store(dir.problem(), 1);
  if (!store.contains(kProblemSegment, "rest/u")) return {};
  std::vector<double> u = store.read(kProblemSegment, "rest/u");
  for (double& x : u) x /= unit;
  return u;
}

Problem problem_from_vectors(const ProblemVectors& v, const Scene& scene,
                             const ContentHash& expected, const std::string& where) {
  if (hash_of(v) != expected) {
    throw InputError(where +
                     ": the stored mesh and constraints do not match the catalogue's "
                     "record (hash " +
                     hash_of(v).hex() + ", expected " + expected.hex() +
                     "): the file was replaced or damaged; re-import with --fresh");
  }
  const std::size_t num_nodes = v.nodes.size() / 3;
  if (v.nodes.size() % 3 || v.tets.size() % 4 || v.surface.size() % 3 ||
      v.role.size() != v.nodes.size() || v.probe_components.size() != 3 || v.rest.size() != 3 ||
      (!v.force.empty() && v.force.size() != v.nodes.size()) ||
      (!v.spring.empty() && v.spring.size() != v.nodes.size()) ||
      (!v.rest_u.empty() && v.rest_u.size() != v.nodes.size()) ||
      (!v.sag.empty() && v.sag.size() != 3)) {
    throw InputError(where + ": inconsistent vector sizes (corrupt?)");
  }
  Problem p;
  p.mesh.source = where;
  p.mesh.nodes =
      Eigen::Map<const Eigen::Matrix3Xd>(v.nodes.data(), 3, static_cast<Eigen::Index>(num_nodes));
  const auto tets = to_ids(v.tets, static_cast<double>(num_nodes), where + ": mesh/tets");
  p.mesh.tets = Eigen::Map<const Tets>(tets.data(), 4, static_cast<Eigen::Index>(tets.size() / 4));
  const auto tris = to_ids(v.surface, static_cast<double>(num_nodes), where + ": mesh/surface");
  p.mesh.surface =
      Eigen::Map<const Triangles>(tris.data(), 3, static_cast<Eigen::Index>(tris.size() / 3));
  for (int r : to_ids(v.role, 3, where + ": constraints/role"))
    p.constraints.role.push_back(static_cast<DofRole>(r));
  p.constraints.probe_nodes =
      to_ids(v.probe_nodes, static_cast<double>(num_nodes), where + ": constraints/probe_nodes");
  for (int c = 0; c < 3; ++c) p.constraints.probe_components[c] = v.probe_components[c] != 0;
  p.probe_rest = Eigen::Vector3d(v.rest[0], v.rest[1], v.rest[2]);
  const auto vector = [](const std::vector<double>& x) {
    return Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
  };
  p.loads.force = vector(v.force);
  if (!v.force.empty() && scene.loads.gravity && scene.material.density) {
    p.loads.density = *scene.material.density;
    p.loads.gravity = *scene.loads.gravity;
  }
  p.loads.spring = vector(v.spring);
  p.rest_m = vector(v.rest_u);
  if (!v.sag.empty()) p.probe_sag = Eigen::Vector3d(v.sag[0], v.sag[1], v.sag[2]);
  p.unit = scene.mesh.unit;
  p.material = resolve_material(scene.material);
  p.solver = scene.solver;
  p.max_force = scene.probe.max_force;
  if (scene.probe.mode == ProbeMode::kContact)
    p.contact =
        make_contact_sphere(p.mesh, p.constraints.role, *scene.probe.radius, scene.probe.friction);
  return p;
}

}  // namespace hapstate
