// solve(): the precise solver (hapstate/solver.h, SceneSolver) along a probe path, for Python.
#include "bindings.h"

#include "hapstate/error.h"
#include "hapstate/solver.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <string>
#include <vector>

namespace py = pybind11;

namespace hapstate::python {
namespace {

using Positions = py::array_t<double, py::array::c_style | py::array::forcecast>;

py::dict solve(const std::filesystem::path& scene, const Positions& path, bool stiffness) {
  if (path.ndim() != 2 || path.shape(1) != 3)
    throw InputError("path: expected an (n, 3) array of probe positions");
  const py::ssize_t n = path.shape(0);
  const double* p = path.data();
  for (py::ssize_t i = 0; i < 3 * n; ++i)
    if (!std::isfinite(p[i]))
      throw InputError("path: row " + std::to_string(i / 3) + " is not finite");

  SceneSolver solver(scene.string());
  const py::ssize_t nodes = solver.num_nodes();
  std::vector<double> force(3 * n), k(stiffness ? 9 * n : 0), u(3 * n * nodes), residual(n);
  std::vector<int> iterations(n);
  std::vector<char> converged(n);
  std::vector<std::string> failure(n);
  {
    py::gil_scoped_release release;
    for (py::ssize_t s = 0; s < n; ++s) {
      const MoveOutcome m = solver.move_to({p[3 * s], p[3 * s + 1], p[3 * s + 2]});
      converged[s] = m.ok;
      failure[s] = m.ok ? "" : m.failure + ": " + m.reason;
      iterations[s] = m.iterations;
      residual[s] = m.residual;
      const Eigen::Vector3d f = solver.force_felt();
      std::copy_n(f.data(), 3, &force[3 * s]);
      if (stiffness) {
        const Eigen::Matrix3d K = solver.haptic_stiffness();
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) k[9 * s + 3 * r + c] = K(r, c);
      }
      const Eigen::Matrix3Xd d = solver.displacements();
      std::copy_n(d.data(), 3 * nodes, &u[3 * s * nodes]);
    }
  }
  auto array = [](const auto& v, std::vector<py::ssize_t> shape) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    py::array_t<T> out(shape);
    std::copy(v.begin(), v.end(), out.mutable_data());
    return out;
  };
  py::dict out;
  out["force"] = array(force, {n, 3});
  if (stiffness) out["stiffness"] = array(k, {n, 3, 3});
  out["displacements"] = array(u, {n, nodes, 3});
  out["converged"] = array(converged, {n}).attr("astype")("bool");
  out["iterations"] = array(iterations, {n});
  out["residual"] = array(residual, {n});
  out["failure"] = failure;
  return out;
}

}  // namespace

void bind_solver(py::module_& m) {
  m.def("solve", &solve, py::arg("scene"), py::arg("path"), py::arg("stiffness") = false,
        "The precise non-linear solver along `path`: the body starts at rest and the probe moves "
        "through the (n, 3) positions (mesh units) in order. Returns a dict: force (n, 3) in N, "
        "displacements (n, nodes, 3) of every mesh node in mesh units, converged (n,) bool, "
        "failure (n,) reasons ('' where converged; a failed move leaves the state where it "
        "was), iterations, residual (N), and with stiffness=True stiffness (n, 3, 3) in N per "
        "mesh unit. Raises InputError naming the file for a bad scene or mesh.");
}

}  // namespace hapstate::python
