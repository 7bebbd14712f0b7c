// solve(): the precise solver (hapstate/solver.h, SceneSolver) along a probe path, for Python;
// from_both_sides(): a position reached from either side (eval/equilibria.h).
#include "bindings.h"

#include "eval/equilibria.h"
#include "hapstate/error.h"
#include "hapstate/solver.h"
#include "scene/bind.h"
#include "scene/grid_spec.h"
#include "scene/scene.h"

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

py::array_t<double> vector3(const Eigen::Vector3d& v) {
  py::array_t<double> out(3);
  std::copy_n(v.data(), 3, out.mutable_data());
  return out;
}

Eigen::Vector3d position(const std::string& what, const py::object& value) {
  const Positions a = py::cast<Positions>(value);
  if (a.size() != 3) throw InputError(what + ": expected 3 numbers");
  const Eigen::Vector3d v(a.data()[0], a.data()[1], a.data()[2]);
  if (!v.allFinite()) throw InputError(what + ": expected 3 finite numbers");
  return v;
}

py::list from_both_sides(const std::filesystem::path& scene, const py::object& point,
                         const py::object& along, int steps, double tolerance) {
  const Eigen::Vector3d p = position("point", point);
  if (!(tolerance > 0 && std::isfinite(tolerance)))
    throw InputError("tolerance: expected a number > 0 (got " + std::to_string(tolerance) + ")");
  const Scene parsed = load_scene(scene);
  std::vector<Eigen::Vector3d> approaches;
  if (along.is_none()) {
    const auto half = half_spacing_approaches(grid_spacing(parsed.grid));
    approaches.assign(half.begin(), half.end());
  } else {
    approaches.push_back(position("along", along));
  }
  const Problem problem = build_problem(parsed);
  std::vector<TwoSided> results;
  {
    py::gil_scoped_release release;
    for (const Eigen::Vector3d& d : approaches)
      results.push_back(from_both_sides(problem, p, d, steps));
  }
  py::list out;
  for (const TwoSided& r : results) {
    py::dict d;
    d["along"] = vector3(r.along);
    d["force_minus"] = vector3(r.minus.force);
    d["force_plus"] = vector3(r.plus.force);
    d["started_minus"] = r.minus.started;
    d["started_plus"] = r.plus.started;
    d["converged_minus"] = r.minus.converged;
    d["converged_plus"] = r.plus.converged;
    d["difference"] = r.difference;
    d["largest"] = r.largest;
    d["verdict"] = equilibria_name(judge(r, tolerance));
    out.append(d);
  }
  return out;
}

}  // namespace

void bind_solver(py::module_& m) {
  m.def("from_both_sides", &from_both_sides, py::arg("scene"), py::arg("point"),
        py::arg("along") = py::none(), py::arg("steps") = 10, py::arg("tolerance") = 0.01,
        "The precise force at `point` (mesh units) reached from either side, as hapstate-certify "
        "checks its worst steps: per approach the body starts at rest, the probe moves to point "
        "- along (and, on a second solver, point + along) in `steps` moves and slides to point in "
        "`steps` more. along=None: half the scene's grid spacing on x, y and z in turn. Returns a "
        "list of dicts, one per approach: along, force_minus and force_plus (N; NaN where that "
        "approach's last solve failed), started_minus/plus (every move to the start converged), "
        "converged_minus/plus (every move converged), difference (|f- - f+|, N; NaN unless both "
        "converged), largest (the larger |f| that converged, N) and verdict: 'one', 'two' (the "
        "forces differ by more than tolerance x largest and 1e-7 N), 'ends' (Newton failed on "
        "one side only) or 'undecided' (a start not reached, or neither converged). Raises "
        "InputError naming the file for a bad scene or mesh, or for a bad point or along.");
  m.def("solve", &solve, py::arg("scene"), py::arg("path"), py::arg("stiffness") = false,
        "The precise non-linear solver along `path`: the body starts at rest and the probe moves "
        "through the (n, 3) positions (mesh units) in order. Returns a dict: force (n, 3) in N, "
        "displacements (n, nodes, 3) of every mesh node in mesh units, converged (n,) bool, "
        "failure (n,) reasons ('' where converged; a failed move leaves the state where it "
        "was), iterations, residual (N), and with stiffness=True stiffness (n, 3, 3) in N per "
        "mesh unit. Raises InputError naming the file for a bad scene or mesh.");
}

}  // namespace hapstate::python
