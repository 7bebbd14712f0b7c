// Table scene: one row, id = 1.
#include "catalogue/catalogue_impl.hpp"

namespace hapstate {
namespace {

constexpr const char* kWriteScene =
    "INSERT OR REPLACE INTO scene (id, text, hash, mesh_file, mesh_hash, mesh_nodes, "
    "mesh_elements, mesh_surface_triangles, bbox_min_x, bbox_min_y, bbox_min_z, bbox_max_x, "
    "bbox_max_y, bbox_max_z, volume) VALUES (1, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)";
constexpr const char* kReadScene =
    "SELECT text, hash, mesh_file, mesh_hash, mesh_nodes, mesh_elements, "
    "mesh_surface_triangles, bbox_min_x, bbox_min_y, bbox_min_z, bbox_max_x, bbox_max_y, "
    "bbox_max_z, volume FROM scene WHERE id = 1";

}  // namespace

void Catalogue::write_scene(const SceneRecord& scene) {
  catalogue_detail::StatementUse s(impl_->statement(kWriteScene));
  s->bind(1, scene.text);
  s->bind(2, scene.hash.hex());
  s->bind(3, scene.mesh_file);
  s->bind(4, scene.mesh_hash.hex());
  s->bind(5, scene.mesh_nodes);
  s->bind(6, scene.mesh_elements);
  s->bind(7, scene.mesh_surface_triangles);
  for (int a = 0; a < 3; ++a) {
    s->bind(8 + a, scene.bbox_min[a]);
    s->bind(11 + a, scene.bbox_max[a]);
  }
  s->bind(14, scene.volume);
  s->run();
}

std::optional<SceneRecord> Catalogue::read_scene() {
  catalogue_detail::StatementUse s(impl_->statement(kReadScene));
  if (!s->step()) return std::nullopt;
  SceneRecord scene;
  scene.text = s->column_text(0);
  scene.hash = ContentHash::from_hex(s->column_text(1));
  scene.mesh_file = s->column_text(2);
  scene.mesh_hash = ContentHash::from_hex(s->column_text(3));
  scene.mesh_nodes = s->column_int(4);
  scene.mesh_elements = s->column_int(5);
  scene.mesh_surface_triangles = s->column_int(6);
  for (int a = 0; a < 3; ++a) {
    scene.bbox_min[a] = s->column_double(7 + a);
    scene.bbox_max[a] = s->column_double(10 + a);
  }
  scene.volume = s->column_double(13);
  return scene;
}

}  // namespace hapstate
