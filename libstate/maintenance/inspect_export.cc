// hapstate-inspect export: a configuration's mesh (as drawn) and displacement as VTU.
#include "blobs/blob_store.h"
#include "io/vtu_writer.h"
#include "maintenance/inspect_common.hpp"
#include "mesh/load.h"
#include "scene/scene.h"
#include "statedir/stored_problem.h"
#include "statedir/stored_scene.h"
#include "util/error.h"
#include "util/hash.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hapstate {

using namespace inspect_detail;

namespace {

// The mesh stored by hapstate-import (problem/seg-000001.h5: mesh/nodes, mesh/tets), if any.
std::optional<Mesh> stored_mesh(const StateDir& dir) {
  constexpr SegmentId kProblemSegment{1};
  std::error_code ec;
  if (!std::filesystem::exists(dir.problem() / segment_file_name(kProblemSegment), ec))
    return std::nullopt;
  BlobStore problem(dir.problem());
  const std::vector<double> nodes = problem.read(kProblemSegment, "mesh/nodes");
  const std::vector<double> tets = problem.read(kProblemSegment, "mesh/tets");
  const std::string where = (dir.problem() / segment_file_name(kProblemSegment)).string();
  if (nodes.size() % 3 != 0 || tets.size() % 4 != 0) {
    throw InputError(where + ": mesh/nodes or mesh/tets has a length not a multiple of 3 / 4");
  }
  Mesh mesh;
  mesh.source = where;
  mesh.nodes = Eigen::Map<const Eigen::Matrix3Xd>(nodes.data(), 3,
                                                  static_cast<Eigen::Index>(nodes.size() / 3));
  mesh.tets.resize(4, static_cast<Eigen::Index>(tets.size() / 4));
  for (std::size_t i = 0; i < tets.size(); ++i) {
    const double id = tets[i];
    if (!(id >= 0 && id < static_cast<double>(mesh.num_nodes()))) {
      throw InputError(where + ": mesh/tets[" + std::to_string(i) + "] is not a node id");
    }
    mesh.tets(static_cast<Eigen::Index>(i % 4), static_cast<Eigen::Index>(i / 4)) =
        static_cast<int>(id);
  }
  return mesh;
}

// The mesh file the configuration's displacements refer to: `given`, or the scene's mesh file
// found beside the state directory. Checked against the stored content hash.
std::filesystem::path find_mesh(const StateDir& dir, const SceneRecord& scene,
                                const std::optional<std::filesystem::path>& given) {
  std::vector<std::filesystem::path> candidates;
  if (given) {
    candidates.push_back(*given);
  } else {
    const std::filesystem::path named = scene.mesh_file.empty()
                                            ? parse_stored_scene(scene, dir).mesh.file
                                            : std::filesystem::path(scene.mesh_file);
    if (named.is_absolute()) {
      candidates.push_back(named);
    } else {
      candidates.push_back(dir.root / named);
      candidates.push_back(dir.root.parent_path() / named);
      candidates.push_back(std::filesystem::absolute(dir.root).parent_path() / named);
    }
  }
  std::string tried;
  for (const auto& file : candidates) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) {
      tried += ' ';
      tried += file.string();
      continue;
    }
    if (scene.mesh_hash.value != 0 && content_hash_file(file) != scene.mesh_hash) {
      throw InputError(file.string() + ": mesh content hash " + content_hash_file(file).hex() +
                       " differs from the one the state was built from (" + scene.mesh_hash.hex() +
                       "): wrong mesh file");
    }
    return file;
  }
  throw InputError(dir.root.string() + ": mesh '" + scene.mesh_file + "' not found (tried" + tried +
                   "); give it with --mesh FILE");
}

}  // namespace

InspectOutput export_config_vtu(const StateDir& dir, ConfigId id, const std::filesystem::path& vtu,
                                const std::optional<std::filesystem::path>& mesh_file) {
  Catalogue cat = open_read_only(dir);
  if (!cat.exists_configuration(id)) {
    throw InputError(dir.catalogue().string() + ": no configuration with id " +
                     std::to_string(id.value()));
  }
  const Configuration c = cat.read_configuration(id);
  const SceneRecord scene = read_stored_scene(cat, dir);
  std::optional<Mesh> stored = mesh_file ? std::nullopt : stored_mesh(dir);
  const std::filesystem::path mesh_path =
      stored ? std::filesystem::path(stored->source) : find_mesh(dir, scene, mesh_file);
  const Mesh mesh = stored ? std::move(*stored) : load_mesh(mesh_path);

  Eigen::Matrix3Xd u = Eigen::Matrix3Xd::Zero(3, mesh.num_nodes());
  if (c.blob) {
    BlobStore blobs(dir.blobs());
    const std::vector<double> values = blobs.read(c.blob->segment, c.blob->dataset(BlobVector::kU));
    if (values.size() != 3 * static_cast<std::size_t>(mesh.num_nodes())) {
      throw InputError((dir.blobs() / segment_file_name(c.blob->segment)).string() + ": vector '" +
                       c.blob->dataset(BlobVector::kU) + "' has " + std::to_string(values.size()) +
                       " values, the mesh " + mesh_path.string() + " has " +
                       std::to_string(mesh.num_nodes()) + " nodes (x3)");
    }
    u = Eigen::Map<const Eigen::Matrix3Xd>(values.data(), 3, mesh.num_nodes());
  } else {  // a zero configuration: the loaded rest state (none without a body force)
    const Scene parsed = parse_stored_scene(scene, dir, /*require_probe=*/false);
    const std::vector<double> rest = stored_rest_displacements(dir, parsed.mesh.unit);
    if (rest.size() == 3 * static_cast<std::size_t>(mesh.num_nodes()))
      u = Eigen::Map<const Eigen::Matrix3Xd>(rest.data(), 3, mesh.num_nodes());
  }
  write_vtu(vtu, mesh, u);
  const double max_displacement = mesh.num_nodes() > 0 ? u.colwise().norm().maxCoeff() : 0.0;
  const Json j = {{"config", id.value()},       {"file", vtu.string()},
                  {"mesh", mesh_path.string()}, {"nodes", mesh.num_nodes()},
                  {"tets", mesh.num_tets()},    {"max_displacement", max_displacement}};
  std::ostringstream s;
  s << "wrote " << vtu.string() << ": configuration " << id.value() << " on " << mesh_path.string()
    << " (" << mesh.num_nodes() << " nodes, " << mesh.num_tets() << " tets), max |u| "
    << num(max_displacement) << "\n";
  return {dump(j), s.str()};
}

}  // namespace hapstate
