// Playback and Cursor: the memory-mapped playback file and the haptic cursor (hapstate/playback.h)
// for Python. A path of probe positions is walked in C++ with the GIL released, as a device loop
// would call force() once per tick.
#include "bindings.h"

#include "hapstate/error.h"
#include "hapstate/playback.h"
#include "playback/scheme_name.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace py = pybind11;

namespace hapstate::python {
namespace {

using Positions = py::array_t<double, py::array::c_style | py::array::forcecast>;

Scheme scheme_from(const std::string& name) {
  if (const auto s = parse_scheme(name)) return *s;
  throw InputError("scheme '" + name + "': expected \"hermite\" or \"trilinear\"");
}

// The rows of an (n, 3) array, or of one (3,) position; non-finite values refused.
struct PathView {
  const double* data = nullptr;
  py::ssize_t rows = 0;
  bool single = false;  // given as one (3,) position
};

PathView path_view(const Positions& path) {
  PathView v;
  if (path.ndim() == 1 && path.shape(0) == 3) {
    v.rows = 1;
    v.single = true;
  } else if (path.ndim() == 2 && path.shape(1) == 3) {
    v.rows = path.shape(0);
  } else {
    std::string shape;
    for (py::ssize_t a = 0; a < path.ndim(); ++a) {
      if (a > 0) shape += ", ";
      shape += std::to_string(path.shape(a));
    }
    throw InputError(
        "path: expected an (n, 3) array of probe positions (or one (3,) position), "
        "got shape (" +
        shape + ")");
  }
  v.data = path.data();
  for (py::ssize_t i = 0; i < 3 * v.rows; ++i)
    if (!std::isfinite(v.data[i]))
      throw InputError("path: row " + std::to_string(i / 3) + " is not finite");
  return v;
}

template <typename T>
py::array_t<T> rows_of(const T* data, py::ssize_t rows, py::ssize_t cols) {
  py::array_t<T> out({rows, cols});
  std::copy_n(data, rows * cols, out.mutable_data());
  return out;
}

py::array_t<double> vec3(const std::array<double, 3>& v) {
  py::array_t<double> out(3);
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

py::array_t<std::int32_t> ivec3(const std::array<std::int32_t, 3>& v) {
  py::array_t<std::int32_t> out(3);
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

// A haptic cursor and the file it reads (kept alive by the cursor). The lock serialises Python
// threads sharing one cursor; the C++ loop inside a call is the device loop's.
class PyCursor {
 public:
  PyCursor(std::shared_ptr<const PlaybackFile> file, Scheme scheme)
      : file_(std::move(file)), cursor_(*file_, scheme) {}

  // Walks `path`; calls fill(row, force) per position. A new or reset() cursor is first
  // placed at the path's first position with the body at rest, as hapstate-play and
  // hapstate-eval place theirs (the grab probe walks there from rest).
  template <typename Fill>
  void walk(const PathView& v, Fill fill) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (v.rows > 0 && !placed_) {
      cursor_.reset({v.data[0], v.data[1], v.data[2]});
      placed_ = true;
    }
    for (py::ssize_t r = 0; r < v.rows; ++r) {
      const Force f = cursor_.force({v.data[3 * r], v.data[3 * r + 1], v.data[3 * r + 2]});
      fill(r, f);
    }
  }

  py::array_t<double> force(const Positions& path) {
    const PathView v = path_view(path);
    std::vector<double> out(3 * v.rows);
    {
      py::gil_scoped_release release;
      walk(v, [&](py::ssize_t r, const Force& f) { std::copy_n(f.value.data(), 3, &out[3 * r]); });
    }
    if (v.single) return vec3({out[0], out[1], out[2]});
    return rows_of(out.data(), v.rows, 3);
  }

  py::array_t<double> stiffness(const Positions& path) {
    const PathView v = path_view(path);
    std::vector<double> out(9 * v.rows);
    {
      py::gil_scoped_release release;
      walk(v,
           [&](py::ssize_t r, const Force& f) { std::copy_n(f.stiffness.data(), 9, &out[9 * r]); });
    }
    py::array_t<double> a(v.single ? std::vector<py::ssize_t>{3, 3}
                                   : std::vector<py::ssize_t>{v.rows, 3, 3});
    std::copy(out.begin(), out.end(), a.mutable_data());
    return a;
  }

  py::array_t<double> deform() {
    const auto n = static_cast<py::ssize_t>(file_->num_view_nodes());
    std::vector<float> u(3 * static_cast<std::size_t>(n));
    {
      py::gil_scoped_release release;  // another thread may hold the cursor for a long walk
      std::lock_guard<std::mutex> lock(mutex_);
      Snapshot s;
      cursor_.snapshot(&s);
      if (s.sequence > 0) displacements(*file_, s, u);  // before any query: the body at rest
    }
    py::array_t<double> out({n, py::ssize_t{3}});
    std::copy(u.begin(), u.end(), out.mutable_data());
    return out;
  }

  py::object probe() {
    Snapshot s;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      cursor_.snapshot(&s);
    }
    if (s.sequence == 0) return py::none();
    return vec3(s.probe);
  }

  void reset(const std::optional<std::array<double, 3>>& at) {
    if (at)
      for (double x : *at)
        if (!std::isfinite(x)) throw InputError("reset: the position is not finite");
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    if (at) {
      cursor_.reset(*at);
    } else {
      cursor_.reset();
    }
    placed_ = at.has_value();
  }

  // The getters below wait for a walk another thread may be in (the GIL released meanwhile).
  template <typename Get>
  auto locked(Get get) const {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    return get();
  }
  std::string scheme() const {
    return scheme_name(locked([&] { return cursor_.scheme(); }));
  }
  void set_scheme(const std::string& name) {
    const Scheme s = scheme_from(name);
    locked([&] {
      cursor_.set_scheme(s);
      return 0;
    });
  }
  std::int32_t anchor_configuration() const {
    return locked([&] { return cursor_.anchor_configuration(); });
  }
  py::array_t<std::int32_t> anchor_checkpoint() const {
    return ivec3(locked([&] { return cursor_.anchor_checkpoint(); }));
  }
  std::uint64_t cells_walked() const {
    return locked([&] { return cursor_.cells_walked(); });
  }

 private:
  std::shared_ptr<const PlaybackFile> file_;
  HapticCursor cursor_;
  bool placed_ = false;
  mutable std::mutex mutex_;
};

// What hapstate-certify measured on the file, as Playback.certificate returns it.
py::object certificate_dict(const PlaybackFile& f) {
  const auto c = f.certificate();
  if (!c) return py::none();
  py::dict d;
  d["paths"] = c->paths;
  d["steps_per_path"] = c->steps_per_path;
  d["steps"] = c->steps;
  d["failed_steps"] = c->failed_steps;
  for (int s = 0; s < kNumSchemes; ++s) {
    py::dict e;
    e["force_error_worst"] = c->force_error_worst[s];
    e["force_error_p99"] = c->force_error_p99[s];
    e["force_error_worst_newtons"] = c->force_error_worst_n[s];
    e["deformation_error_worst"] = c->deformation_error_worst[s];
    d[scheme_name(s)] = e;
  }
  d["stiffness_n_per_mm"] = c->stiffness_n_per_mm;
  d["query_median_ns"] = c->query_median_ns;
  d["query_p999_ns"] = c->query_p999_ns;
  return d;
}

// The check-points' positions, (I, J, K, 3).
py::array_t<double> grid_points(const PlaybackFile& f) {
  const auto o = f.grid_origin(), h = f.grid_spacing();
  const auto lo = f.grid_lo(), n = f.grid_dims();
  py::array_t<double> out(
      {py::ssize_t{n[0]}, py::ssize_t{n[1]}, py::ssize_t{n[2]}, py::ssize_t{3}});
  double* p = out.mutable_data();
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int k = 0; k < n[2]; ++k) {
        const int idx[3] = {lo[0] + i, lo[1] + j, lo[2] + k};
        for (int a = 0; a < 3; ++a) *p++ = o[a] + idx[a] * h[a];
      }
  return out;
}

using PyPlayback = py::class_<PlaybackFile, std::shared_ptr<PlaybackFile>>;

// Playback's grid: the probe's rest point, the check-points' origin, spacing, extent, positions.
void bind_grid(PyPlayback& playback) {
  playback
      .def_property_readonly(
          "probe_rest", [](const PlaybackFile& f) { return vec3(f.rest_position()); },
          "(3,) the probe's position at rest, mesh units.")
      .def_property_readonly(
          "grid_origin", [](const PlaybackFile& f) { return vec3(f.grid_origin()); },
          "(3,) position of grid index (0, 0, 0), mesh units.")
      .def_property_readonly(
          "grid_spacing", [](const PlaybackFile& f) { return vec3(f.grid_spacing()); },
          "(3,) check-point spacing per axis, mesh units.")
      .def_property_readonly(
          "grid_lo", [](const PlaybackFile& f) { return ivec3(f.grid_lo()); },
          "(3,) grid index of the first check-point per axis.")
      .def_property_readonly(
          "grid_dims", [](const PlaybackFile& f) { return ivec3(f.grid_dims()); },
          "(3,) number of check-points per axis.")
      .def("grid_points", &grid_points, "(I, J, K, 3) positions of the check-points, mesh units.");
}

// Playback's stored data per configuration, its certificate and its cursors.
void bind_data(PyPlayback& playback) {
  playback
      .def(
          "force",
          [](const PlaybackFile& f, std::int32_t c) {
            if (c < 0 || c >= f.num_configurations())
              throw InputError("configuration " + std::to_string(c) + ": out of range");
            return vec3(f.force(c));
          },
          py::arg("configuration"), "(3,) the stored force of a configuration (file index), N.")
      .def(
          "displacements",
          [](const PlaybackFile& f, std::int32_t c) {
            if (c < 0 || c >= f.num_configurations())
              throw InputError("configuration " + std::to_string(c) + ": out of range");
            const auto u = f.displacements(c);
            py::array_t<double> out({static_cast<py::ssize_t>(u.size() / 3), py::ssize_t{3}});
            std::copy(u.begin(), u.end(), out.mutable_data());
            return out;
          },
          py::arg("configuration"),
          "(m, 3) the stored displacements of a configuration's view nodes, mesh units.")
      .def_property_readonly(
          "certificate", &certificate_dict,
          "What hapstate-certify measured on this file (docs/certificate.md) as a dict, or None "
          "before it has run (or when another version of the playback code measured it): "
          "paths, steps, per scheme ('hermite', 'trilinear') the worst and "
          "99th-percentile force error (relative to the path's largest force), the worst in N "
          "and the worst deformation error, the largest stored stiffness (N/mm) and the haptic "
          "query's median and 99.9th percentile (ns).")
      .def(
          "cursor",
          [](std::shared_ptr<PlaybackFile> f, const std::string& scheme) {
            return std::make_unique<PyCursor>(std::move(f), scheme_from(scheme));
          },
          py::arg("scheme") = "hermite",
          "A haptic cursor on this file: scheme \"hermite\" (default) or \"trilinear\".")
      .def("__repr__", [](const PlaybackFile& f) {
        return "<hapstate.Playback '" + f.path().string() +
               "': " + std::to_string(f.num_configurations()) + " configurations, " +
               (f.is_contact() ? "contact" : "grab") + ">";
      });
}

void bind_cursor(py::module_& m) {
  py::class_<PyCursor>(m, "Cursor",
                       "The haptic cursor of one device (HapticCursor): it follows the probe cell "
                       "by cell through the stored transitions, so the order of positions matters "
                       "(the history of a device loop). Made by Playback.cursor().")
      .def("force", &PyCursor::force, py::arg("path"),
           "Forces (n, 3) in N along `path`, an (n, 3) array of probe positions (mesh units) "
           "visited in order, continuing from the cursor's last position; a (3,) position gives "
           "a (3,) force. A new (or reset()) cursor starts at the path's first position with the "
           "body at rest, as hapstate-eval and hapstate-play do.")
      .def("stiffness", &PyCursor::stiffness, py::arg("path"),
           "Stiffness d force / d probe, (n, 3, 3) in N per mesh unit, along `path` (visited in "
           "order as by force()).")
      .def("deform", &PyCursor::deform,
           "(m, 3) displacements of the view nodes at the cursor's current position (mesh units, "
           "from the mesh as drawn); zeros before the first query.")
      .def("reset", &PyCursor::reset, py::arg("at") = py::none(),
           "Back to rest; with `at`, placed there with the body at rest (a contact probe clear of "
           "the body).")
      .def_property("scheme", &PyCursor::scheme, &PyCursor::set_scheme,
                    "\"hermite\" or \"trilinear\".")
      .def_property_readonly("probe", &PyCursor::probe,
                             "(3,) the last position queried, or None before the first.")
      .def_property_readonly("anchor_configuration", &PyCursor::anchor_configuration,
                             "The configuration at the check-point nearest to the last position "
                             "(-1 if that corner is extended).")
      .def_property_readonly("anchor_checkpoint", &PyCursor::anchor_checkpoint,
                             "(3,) grid index of the check-point nearest to the last position.")
      .def_property_readonly("cells_walked", &PyCursor::cells_walked,
                             "Cells entered since the cursor was made.");
}

}  // namespace

void bind_playback(py::module_& m) {
  PyPlayback playback(
      m, "Playback",
      "A playback file written by hapstate-index (state/playback.bin), memory-mapped read-only. "
      "Positions are in mesh units (the scene's), forces in N, stiffness in N per mesh unit.");
  playback
      .def(py::init([](const std::filesystem::path& p) {
             return std::make_shared<PlaybackFile>(
                 std::filesystem::is_directory(p) ? p / "playback.bin" : p);
           }),
           py::arg("path"),
           "Maps `path` (a playback file, or a state directory holding playback.bin). Raises "
           "InputError naming the file when it is missing or not a playback file.")
      .def("verify", &PlaybackFile::verify,
           "Checks every section's checksum and cross-references; raises InputError on the first "
           "problem.")
      .def_property_readonly("path", &PlaybackFile::path)
      .def_property_readonly("num_configurations", &PlaybackFile::num_configurations)
      .def_property_readonly("num_view_nodes", &PlaybackFile::num_view_nodes)
      .def_property_readonly("num_mesh_nodes", &PlaybackFile::num_mesh_nodes)
      .def_property_readonly("is_contact", &PlaybackFile::is_contact,
                             "True for a contact (sphere) probe, False for a grabbed node.")
      .def_property_readonly("max_force", &PlaybackFile::max_force, "The device limit F_max, N.")
      .def_property_readonly("scene_hash", &PlaybackFile::scene_hash)
      .def_property_readonly(
          "view_nodes",
          [](const PlaybackFile& f) {
            const auto v = f.view_nodes();
            py::array_t<std::int32_t> out(static_cast<py::ssize_t>(v.size()));
            std::copy(v.begin(), v.end(), out.mutable_data());
            return out;
          },
          "Mesh node index of each view node (the nodes whose displacements are stored), int32.")
      .def_property_readonly(
          "rest_positions",
          [](const PlaybackFile& f) {
            const auto v = f.reference_positions();
            py::array_t<double> out({static_cast<py::ssize_t>(v.size() / 3), py::ssize_t{3}});
            std::copy(v.begin(), v.end(), out.mutable_data());
            return out;
          },
          "(m, 3) positions of the view nodes in the mesh as drawn, mesh units.")
      .def_property_readonly(
          "triangles",
          [](const PlaybackFile& f) {
            const auto t = f.triangles();
            return rows_of(t.data(), static_cast<py::ssize_t>(t.size() / 3), 3);
          },
          "(t, 3) surface triangles as view-node indices, int32.");
  bind_grid(playback);
  bind_data(playback);
  bind_cursor(m);
}

}  // namespace hapstate::python
