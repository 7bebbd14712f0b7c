// The parts of the Python module hapstate._core (docs/python.md), one file each: the playback
// runtime (Playback, Cursor), the read-only catalogue (Catalogue) and the precise solver (solve).
#pragma once

#include <pybind11/pybind11.h>

namespace hapstate::python {

void bind_playback(pybind11::module_& m);
void bind_catalogue(pybind11::module_& m);
void bind_solver(pybind11::module_& m);

}  // namespace hapstate::python
