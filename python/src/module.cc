// hapstate._core: the C++ half of the Python package `hapstate` (python/hapstate/__init__.py
// re-exports it). Errors are the tools' messages: hapstate::InputError becomes
// hapstate.InputError (a ValueError), hapstate::EnvironmentError hapstate.EnvironmentError (an
// OSError).
#include "bindings.h"

#include "hapstate/error.h"

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
  m.doc() =
      "hapstate's C++ runtime and state directory from Python: the memory-mapped playback file "
      "and its haptic cursor, the read-only catalogue, and the precise solver (docs/python.md).";
  py::register_exception<hapstate::InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<hapstate::EnvironmentError>(m, "EnvironmentError", PyExc_OSError);
  hapstate::python::bind_playback(m);
  hapstate::python::bind_catalogue(m);
  hapstate::python::bind_solver(m);
}
