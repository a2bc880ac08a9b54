// The parts of the extension module stvd._core, each registered by its own
// translation unit.
#pragma once

#include <pybind11/pybind11.h>

namespace stvd::python {

/// TensorField and VolumePropagation: tensor volumes, paths, connectivity.
void bindVolumes(pybind11::module_& m);
/// tet_mesh_propagate and surface_propagate.
void bindMeshes(pybind11::module_& m);
/// RunFiles and OutputTransaction: what a call writes, checked and atomic.
void bindFiles(pybind11::module_& m);

}  // namespace stvd::python
