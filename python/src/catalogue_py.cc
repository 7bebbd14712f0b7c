// Catalogue: a state directory's catalogue (catalogue.sqlite) and blobs, read-only, for Python.
// Tables come back as dicts of NumPy arrays, one entry per column (force and stiffness
// columns gathered into (n, 3) and (n, 3, 3)); nothing in the state directory is written.
#include "bindings.h"

#include "blobs/blob_store.h"
#include "catalogue/catalogue.h"
#include "maintenance/inspect.h"
#include "maintenance/state_paths.h"
#include "scene/scene.h"
#include "statedir/stored_problem.h"
#include "statedir/stored_scene.h"
#include "util/error.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <limits>
#include <string>
#include <variant>
#include <vector>

namespace py = pybind11;

namespace hapstate::python {
namespace {

// Column `c` of every row as integers (NULL -> `null`).
py::array_t<std::int64_t> int_column(const QueryResult& r, std::size_t c, std::int64_t null = -1) {
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(r.rows.size()));
  std::int64_t* p = out.mutable_data();
  for (const auto& row : r.rows) {
    const QueryValue& v = row[c];
    if (const auto* i = std::get_if<std::int64_t>(&v))
      *p++ = *i;
    else if (const auto* d = std::get_if<double>(&v))
      *p++ = static_cast<std::int64_t>(*d);
    else
      *p++ = null;
  }
  return out;
}

double real_of(const QueryValue& v) {
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  return std::numeric_limits<double>::quiet_NaN();
}

// Columns c0 .. c0 + width - 1 as an (n, shape...) float64 array (NULL -> NaN).
py::array_t<double> real_columns(const QueryResult& r, std::size_t c0, std::size_t width,
                                 std::vector<py::ssize_t> shape) {
  shape.insert(shape.begin(), static_cast<py::ssize_t>(r.rows.size()));
  py::array_t<double> out(shape);
  double* p = out.mutable_data();
  for (const auto& row : r.rows)
    for (std::size_t k = 0; k < width; ++k) *p++ = real_of(row[c0 + k]);
  return out;
}

py::list text_column(const QueryResult& r, std::size_t c) {
  py::list out;
  for (const auto& row : r.rows) {
    const auto* s = std::get_if<std::string>(&row[c]);
    out.append(s ? *s : std::string());
  }
  return out;
}

// Any read-only statement's result: column name -> NumPy array (numbers; None for NULL makes
// an object array) or list (text, bytes).
py::dict generic(const QueryResult& r) {
  py::dict out;
  py::module_ np = py::module_::import("numpy");
  for (std::size_t c = 0; c < r.columns.size(); ++c) {
    py::list values;
    bool text = false;
    for (const auto& row : r.rows) {
      std::visit(
          [&](const auto& x) {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, std::monostate>) {
              values.append(py::none());
            } else if constexpr (std::is_same_v<T, std::vector<std::byte>>) {
              values.append(py::bytes(reinterpret_cast<const char*>(x.data()), x.size()));
              text = true;
            } else {
              values.append(x);
              text = text || std::is_same_v<T, std::string>;
            }
          },
          row[c]);
    }
    out[py::str(r.columns[c])] = text ? py::object(values) : np.attr("asarray")(values);
  }
  return out;
}

class PyCatalogue {
 public:
  explicit PyCatalogue(const std::filesystem::path& root)
      : dir_(locate_state(root)), catalogue_(dir_.catalogue(), OpenMode::kReadOnly) {}

  py::dict configurations() {
    const QueryResult r = catalogue_.query_read_only(
        "SELECT c.id, c.checkpoint, p.i, p.j, p.k, c.level, c.wave, c.expandable, c.status, "
        "c.blob_segment, c.blob_name, p.x, p.y, p.z, c.force_x, c.force_y, c.force_z, "
        "c.k_xx, c.k_xy, c.k_xz, c.k_yx, c.k_yy, c.k_yz, c.k_zx, c.k_zy, c.k_zz "
        "FROM configuration c JOIN checkpoint p ON p.id = c.checkpoint ORDER BY c.id");
    py::dict d;
    const char* ints[] = {"id",    "checkpoint", "i",          "j",      "k",
                          "level", "wave",       "expandable", "status", "blob_segment"};
    for (std::size_t c = 0; c < std::size(ints); ++c) d[ints[c]] = int_column(r, c);
    d["expandable"] = d["expandable"].attr("astype")("bool");
    d["blob_name"] = text_column(r, 10);
    d["position"] = real_columns(r, 11, 3, {3});
    d["force"] = real_columns(r, 14, 3, {3});
    d["stiffness"] = real_columns(r, 17, 9, {3, 3});
    return d;
  }

  py::dict transitions() {
    const QueryResult r = catalogue_.query_read_only(
        "SELECT source, direction, outcome, target, substeps, newton_iterations, factorisations, "
        "midpoint_blob_segment, final_residual, wall_ms, failure_reason, midpoint_blob_name, "
        "midpoint_fx, midpoint_fy, midpoint_fz, midpoint_k0, midpoint_k1, midpoint_k2, "
        "midpoint_k3, midpoint_k4, midpoint_k5, midpoint_k6, midpoint_k7, midpoint_k8 "
        "FROM transition ORDER BY source, direction");
    py::dict d;
    const char* ints[] = {
        "source",   "direction",         "outcome",        "target",
        "substeps", "newton_iterations", "factorisations", "midpoint_blob_segment"};
    for (std::size_t c = 0; c < std::size(ints); ++c) d[ints[c]] = int_column(r, c);
    d["final_residual"] = real_columns(r, 8, 1, {}).attr("reshape")(-1);
    d["wall_ms"] = real_columns(r, 9, 1, {}).attr("reshape")(-1);
    d["failure_reason"] = text_column(r, 10);
    d["midpoint_blob_name"] = text_column(r, 11);
    d["midpoint_force"] = real_columns(r, 12, 3, {3});
    d["midpoint_stiffness"] = real_columns(r, 15, 9, {3, 3});
    return d;
  }

  py::dict checkpoints() {
    const QueryResult r = catalogue_.query_read_only(
        "SELECT id, i, j, k, classification, x, y, z FROM checkpoint ORDER BY id");
    py::dict d;
    const char* ints[] = {"id", "i", "j", "k", "classification"};
    for (std::size_t c = 0; c < std::size(ints); ++c) d[ints[c]] = int_column(r, c);
    d["position"] = real_columns(r, 5, 3, {3});
    return d;
  }

  py::dict query(const std::string& sql) { return generic(catalogue_.query_read_only(sql)); }

  py::object summary() {
    const InspectOutput o = inspect_summary(dir_);
    return py::module_::import("json").attr("loads")(o.json);
  }

  // The vectors of configuration `id` by dataset name ("u" as (n, 3); "du_dp" as (3, n, 3):
  // du_dp[a] the slopes along probe axis a; others flat). A configuration without stored
  // vectors (a zero configuration) gives its u: the loaded rest state, or zeros.
  py::dict vectors(std::int64_t id) {
    const ConfigId config{id};
    if (!catalogue_.exists_configuration(config))
      throw InputError(dir_.catalogue().string() + ": no configuration with id " +
                       std::to_string(id));
    const Configuration c = catalogue_.read_configuration(config);
    py::dict d;
    if (!c.blob) {
      const auto scene = catalogue_.read_scene();
      const auto nodes = scene ? scene->mesh_nodes : 0;
      std::vector<double> u;
      if (scene) {
        const Scene parsed = parse_stored_scene(*scene, dir_, /*require_probe=*/false);
        u = stored_rest_displacements(dir_, parsed.mesh.unit);
      }
      u.resize(3 * static_cast<std::size_t>(nodes), 0.0);
      d[BlobRef::leaf(BlobVector::kU)] = shaped(u, {static_cast<py::ssize_t>(nodes), 3});
      return d;
    }
    const BlobStore& blobs = this->blobs();
    const std::string prefix = c.blob->name + "/";
    for (const std::string& full : blobs.list_vectors(c.blob->segment)) {
      if (full.rfind(prefix, 0) != 0) continue;
      const std::string name = full.substr(prefix.size());
      const std::vector<double> v = blobs.read(c.blob->segment, full);
      const auto n = static_cast<py::ssize_t>(v.size());
      if (name == BlobRef::leaf(BlobVector::kU) && n % 3 == 0)
        d[py::str(name)] = shaped(v, {n / 3, 3});
      else if (name == BlobRef::leaf(BlobVector::kDuDp) && n % 9 == 0)
        d[py::str(name)] = shaped(v, {3, n / 9, 3});
      else
        d[py::str(name)] = shaped(v, {n});
    }
    return d;
  }

  const std::filesystem::path& root() const { return dir_.root; }

 private:
  static py::array_t<double> shaped(const std::vector<double>& v,
                                    const std::vector<py::ssize_t>& shape) {
    py::array_t<double> out(shape);
    std::copy(v.begin(), v.end(), out.mutable_data());
    return out;
  }
  const BlobStore& blobs() {
    if (!blobs_) blobs_ = std::make_unique<BlobStore>(dir_.blobs());
    return *blobs_;
  }

  StateDir dir_;
  Catalogue catalogue_;
  std::unique_ptr<BlobStore> blobs_;
};

}  // namespace

void bind_catalogue(py::module_& m) {
  py::class_<PyCatalogue>(m, "Catalogue",
                          "A state directory's catalogue and configuration vectors, read-only "
                          "(opening it writes nothing and takes no stage lock; docs/storage.md "
                          "has the tables).")
      .def(py::init<const std::filesystem::path&>(), py::arg("state_dir"),
           "Opens `state_dir` (holding catalogue.sqlite). Raises InputError naming it if it is "
           "not a state directory.")
      .def("configurations", &PyCatalogue::configurations,
           "Every configuration (level of a check-point), by id: id, checkpoint, i, j, k, level, "
           "wave, expandable, status (0 open, 1 expanded, 2 merged), blob_segment (-1: none), "
           "blob_name, position (n, 3) of its check-point, force (n, 3) in N, stiffness (n, 3, 3) "
           "in N per mesh unit.")
      .def("transitions", &PyCatalogue::transitions,
           "Every decided move, by source and direction (0..25, docs/state-space.md): outcome "
           "(0 reached, 1 outside, 2 failed), target (-1: none), substeps, newton_iterations, "
           "factorisations, final_residual (N), wall_ms, failure_reason, midpoint_force (n, 3) and "
           "midpoint_stiffness (n, 3, 3) (NaN where none was recorded), midpoint_blob_segment, "
           "midpoint_blob_name.")
      .def("checkpoints", &PyCatalogue::checkpoints,
           "Every check-point: id, i, j, k, classification, position (n, 3) in mesh units.")
      .def("query", &PyCatalogue::query, py::arg("sql"),
           "One read-only SQL statement: column name -> NumPy array (text and bytes as lists). "
           "Raises InputError for anything that is not a read.")
      .def("summary", &PyCatalogue::summary,
           "The report of `hapstate-inspect summary --json`, as a dict.")
      .def("vectors", &PyCatalogue::vectors, py::arg("config_id"),
           "The stored vectors of a configuration by name: u (n, 3) displacements in mesh "
           "units, du_dp (3, n, 3) their slopes along probe x, y, z, and the others flat "
           "(docs/storage.md, 'Blob segments').")
      .def_property_readonly("root", &PyCatalogue::root)
      .def("__repr__",
           [](const PyCatalogue& c) { return "<hapstate.Catalogue '" + c.root().string() + "'>"; });
}

}  // namespace hapstate::python
